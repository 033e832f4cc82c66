"""Table 1 step 7 (continued): eliminate the multipliers and the dependent coordinates.

The position constraints are solved in closed form for the dependent coordinates as
functions of the independent one, (30)-(34). Their derivative S = dq/dtheta spans the
null space of A (A S = 0 because f(q(theta)) vanishes identically), so projecting
Lagrange's equations onto S removes A^T lambda and leaves the reduced equation (36):

    e0 thetaddot + e1 thetadot^2 + e2 thetadot + G(theta) = 0,
    G = e3 * split_elastic(theta) + e4 * split_load(theta)          (37)-(41)
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model import Mechanism
from .algebra import tidy
from .dynamics import Dynamics
from .state import StateSymbols


@dataclass(frozen=True)
class Reduction:
    theta: sp.Symbol
    theta_d: sp.Symbol
    theta_dd: sp.Symbol
    positions: sp.Matrix   # q(theta), (30), (31), (34)
    velocities: sp.Matrix  # S(theta) thetadot, (32), (35)
    equation: sp.Expr      # the reduced equation of motion, (36), as projected
    e: tuple[sp.Expr, ...]  # e0..e4, (37)-(41)
    split: tuple[sp.Expr, sp.Expr]  # the factors of e3 and e4 in G: sin, cos for Doughty

    @property
    def static_force(self) -> sp.Expr:
        """G(theta) = e3 sin + e4 cos: the reduced equation at rest, (42)."""
        return self.e[3] * self.split[0] + self.e[4] * self.split[1]

    @property
    def structured_equation(self) -> sp.Expr:
        """(36) assembled from its coefficients; equal to ``equation``, better conditioned."""
        e0, e1, e2 = self.e[:3]
        return e0 * self.theta_dd + e1 * self.theta_d**2 + e2 * self.theta_d + self.static_force

    @property
    def angular_acceleration(self) -> sp.Expr:
        """thetaddot solved from (36), which is affine in it."""
        e0, e1, e2 = self.e[:3]
        return -(e1 * self.theta_d**2 + e2 * self.theta_d + self.static_force) / e0


def solve_positions(mechanism: Mechanism, state: StateSymbols, constraints: sp.Matrix) -> sp.Matrix:
    """Solve f(q) = 0 for every coordinate in terms of the independent one.

    Each declared polar pair (length, angle) is replaced by its Cartesian components
    X = length cos(angle), Y = length sin(angle); the constraints are then linear in the
    unknowns, so linsolve gives the unique closed form, and
    length = sqrt(X^2 + Y^2), angle = atan2(Y, X).
    """
    names = [c.name for c in mechanism.coordinates]
    sym = dict(zip(names, state.coords))
    polar = {}
    eqs = list(constraints)
    for length, angle in mechanism.polar_pairs:
        X, Y = sp.Dummy(f"X_{length}", real=True), sp.Dummy(f"Y_{length}", real=True)
        rho, ang = sym[length], sym[angle]
        eqs = [e.subs({sp.cos(ang): X / rho, sp.sin(ang): Y / rho}) for e in eqs]
        polar[length], polar[angle] = (X, Y), None
    plain = [sym[n] for n in names if n != mechanism.independent and n not in polar]
    unknowns = plain + [xy for pair in polar.values() if pair for xy in pair]
    for e in eqs:
        if e.free_symbols & {sym[n] for n in polar}:
            raise ValueError("constraints are not linear in the declared polar pairs")
    (solution,) = sp.linsolve(eqs, unknowns)
    values = dict(zip(unknowns, solution))
    result = []
    for name in names:
        if name == mechanism.independent:
            result.append(sym[name])
        elif name not in polar:
            result.append(values[sym[name]])
        else:
            pair = next((l, a) for l, a in mechanism.polar_pairs if name in (l, a))
            X, Y = (values[v] for v in polar[pair[0]])
            result.append(sp.sqrt(X**2 + Y**2) if name == pair[0] else sp.atan2(Y, X))
    return sp.Matrix(result)


def derive_reduction(mechanism: Mechanism, state: StateSymbols, constraints: sp.Matrix,
                     dynamics: Dynamics, freezer: dict) -> Reduction:
    index = [c.name for c in mechanism.coordinates].index(mechanism.independent)
    theta, theta_d, theta_dd = state.coords[index], state.rates[index], state.accels[index]
    positions = solve_positions(mechanism, state, constraints)
    S = positions.diff(theta)
    onto_theta = {
        **dict(zip(state.accels, S * theta_dd + S.diff(theta) * theta_d**2)),
        **dict(zip(state.rates, S * theta_d)),
        **dict(zip(state.coords, positions)),
    }

    def reduce(expr):
        return expr.subs(freezer).subs(onto_theta, simultaneous=True)

    free_motion = dynamics.residual().subs({m: 0 for m in state.multipliers})
    equation = (S.T * reduce(free_motion))[0]
    at_rest = {theta_d: 0, theta_dd: 0}
    # The reduced equation is affine in thetaddot and quadratic in thetadot.
    e0 = tidy(equation.diff(theta_dd).subs(at_rest))
    e1 = tidy(equation.diff(theta_d, 2).subs(at_rest) / 2)
    # Damping projects to sum c (dl/dtheta)^2: squaring the factored rate keeps the
    # radicand a sum of squares, accurate where r is small (expanding it is not).
    e2 = sum((d.coefficient * tidy(reduce(d.length).diff(theta)) ** 2
              for d in mechanism.dampers), sp.S.Zero)
    # The paper writes the static force as e3*sin + e4*cos: the springs' part and the
    # part of gravity and applied forces, each divided by its own factor.
    split = tuple(mechanism.static_split[k].subs(freezer) for k in ("elastic", "load"))
    elastic = reduce(dynamics.elastic_potential).diff(theta)
    load = reduce(dynamics.gravity_potential).diff(theta) - (S.T * reduce(dynamics.applied_forces))[0]
    e3 = tidy(elastic / split[0])
    e4 = tidy(load / split[1])
    return Reduction(
        theta=theta, theta_d=theta_d, theta_dd=theta_dd,
        positions=positions, velocities=S * theta_d, equation=equation,
        e=(e0, e1, e2, e3, e4),
        split=split,
    )
