"""Table 1 step 7 (continued): eliminate the multipliers and the dependent coordinates.

The position constraints are solved in closed form for the dependent coordinates as
functions of the independent one (positions.py), (30)-(34). Their derivative S = dq/dtheta
spans the null space of A (A S = 0 because f(q(theta)) vanishes identically), so projecting
Lagrange's equations onto S removes A^T lambda and leaves the reduced equation (36):

    e0 thetaddot + e1 thetadot^2 + e2 thetadot + G(theta) = 0,            (37)-(41)

with G = dV/dtheta - Q_theta the static generalised force: the potential's slope less the
applied forces' and torques' virtual work per unit theta. G is kept as one expression and
also as its physical contributions (one per spring, body, force and torque), whose sizes
say how small G must be to count as zero.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from ..model import Mechanism
from .dynamics import Dynamics, contributions
from .positions import PositionSolution, solve_positions
from .state import StateSymbols


@dataclass(frozen=True)
class Reduction:
    theta: sp.Symbol
    theta_d: sp.Symbol
    theta_dd: sp.Symbol
    solution: PositionSolution  # q(theta) with its square roots, their kinds
    positions: sp.Matrix   # q(theta), (30), (31), (34), roots written out
    slopes: sp.Matrix      # S(theta) = dq/dtheta
    e_in_roots: tuple[sp.Expr, ...]  # e0, e1, e2 of (36)-(39) in the root symbols
    static_terms: tuple[sp.Expr, ...]  # G's contributions in the root symbols, summing to G
    free_motion: sp.Matrix  # Lagrange's equations without the multipliers' forces (frozen)
    state: StateSymbols     # the symbols ``equation`` replaces along the motion

    @property
    def velocities(self) -> sp.Matrix:
        """S(theta) thetadot, (32), (35)."""
        return self.slopes * self.theta_d

    @cached_property
    def equation(self) -> sp.Expr:
        """The reduced equation of motion (36), as projected: S^T times Lagrange's equations
        along the motion. Derived when asked (the paper's form is checked against it): its
        second derivatives of the explicit positions are costly for a chain of dyads, whose
        expressions are in its program's symbols (see positions.write_out): not derived."""
        if self.solution.definitions:
            raise NotImplementedError("the projected equation of a chain of dyads")
        S, theta, theta_d = self.slopes, self.theta, self.theta_d
        onto_theta = {
            **dict(zip(self.state.accels, S * self.theta_dd + S.diff(theta) * theta_d**2)),
            **dict(zip(self.state.rates, S * theta_d)),
            **dict(zip(self.state.coords, self.positions)),
        }
        return (S.T * self.free_motion.subs(onto_theta, simultaneous=True))[0]

    @cached_property
    def e(self) -> tuple[sp.Expr, ...]:
        """e0, e1, e2 with the square roots written out (declared branch)."""
        return tuple(self.solution.explicit(e) for e in self.e_in_roots)

    @property
    def static_force(self) -> sp.Expr:
        """G(theta), (42), with the square roots written out (declared branch)."""
        return self.solution.explicit(sum(self.static_terms, sp.S.Zero))

    @property
    def structured_equation(self) -> sp.Expr:
        """(36) assembled from its coefficients; equal to ``equation``, better conditioned."""
        e0, e1, e2 = self.e
        return e0 * self.theta_dd + e1 * self.theta_d**2 + e2 * self.theta_d + self.static_force

    @property
    def angular_acceleration(self) -> sp.Expr:
        """thetaddot solved from (36), which is affine in it."""
        e0, e1, e2 = self.e
        return -(e1 * self.theta_d**2 + e2 * self.theta_d + self.static_force) / e0


def derive_reduction(mechanism: Mechanism, state: StateSymbols, constraints: sp.Matrix,
                     dynamics: Dynamics, freezer: dict) -> Reduction:
    index = [c.name for c in mechanism.coordinates].index(mechanism.independent)
    theta, theta_d, theta_dd = state.coords[index], state.rates[index], state.accels[index]
    solution = solve_positions(mechanism, state.coords, constraints)
    positions = solution.explicit(solution.positions)
    # (a chain's positions are in its program's symbols: S by the chain rule through them)
    S = (positions.diff(theta) if not solution.definitions else
         solution.positions.applyfunc(lambda q: solution.explicit(solution.derivative(q))))
    free_motion = dynamics.residual().subs({m: 0 for m in state.multipliers}).subs(freezer)

    def along(expr: sp.Expr) -> sp.Expr:
        """A coordinate expression as a function of theta and the roots."""
        nonlocal solution
        solution, expr = solution.with_length_roots(solution.substitute(expr.subs(freezer)))
        return expr

    def slope(expr: sp.Expr) -> sp.Expr:
        """d/dtheta along the motion (``along`` first: it may add a length root)."""
        expr = along(expr)
        return solution.slope(expr)

    def rates(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
        """First and second derivatives along the motion, the first as solution.slope gives it."""
        first = slope(expr)
        return first, solution.derivative(first)

    # The reduced equation's coefficients from the energies, term by term: each body adds
    # m |dc/dtheta|^2 + I (dangle/dtheta)^2 to e0 (a sum of squares, so no cancellation),
    # and e1 = e0'/2; each damper adds c (dl/dtheta)^2 to e2.
    e0 = e1 = e2 = sp.S.Zero
    for body in mechanism.bodies:
        for mass, coordinate in ([(body.mass, x) for x in body.centre]
                                 + [(body.inertia, body.angle)]):
            if mass != 0 and coordinate != 0:
                first, second = rates(coordinate)
                e0 += mass * first**2
                e1 += mass * first * second
    for damper in mechanism.dampers:
        e2 += damper.coefficient * rates(damper.length)[0] ** 2
    terms = tuple(slope(p) for p in contributions(mechanism))
    return Reduction(
        theta=theta, theta_d=theta_d, theta_dd=theta_dd, solution=solution,
        positions=positions, slopes=S, e_in_roots=(e0, e1, e2), static_terms=terms,
        free_motion=free_motion, state=state,
    )
