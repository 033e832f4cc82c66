"""Table 1 steps 3-10 for a mechanism with n independent coordinates theta = (theta_1..n).

The dependent coordinates are eliminated where the constraints are a triangular system:
each solved, in turn, from a constraint linear in it alone (a relative angle, a slider's
position written in the angles). With every position a function of theta, the energies
give the equations of motion directly (Lagrange's equations projected onto the
independent velocities, as (36) is for n = 1):

    M(theta) thetaddot + h(theta, thetadot) + B(theta) thetadot + G(theta) = 0,

    M = sum_bodies m J_c^T J_c + I J_a^T J_a        (T = thetadot^T M thetadot / 2)
    B = sum_dampers c J_l^T J_l                     (D = thetadot^T B thetadot / 2)
    h_i = sum_jk (dM_ij/dtheta_k - dM_jk/dtheta_i / 2) thetadot_j thetadot_k
    G = dV/dtheta - Q,   K = dG/dtheta              (n x n, symmetric: G is a gradient)

with J_c, J_a, J_l the Jacobians of a body's centre, its angle and a damper's length with
respect to theta. For n = 1 these are e0, e1 thetadot^2 and e2 of (37)-(39), and G of (42).
An equilibrium is a zero of G; the linearisation about it is M, B and K there (steps 9-10).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model import Mechanism
from .closures import solve_closures
from .dynamics import contributions
from .names import internal
from .state import StateSymbols


@dataclass(frozen=True)
class Multibody:
    """Every expression the library of an n-coordinate mechanism evaluates, in the symbols
    of theta (and thetadot), the parameters."""

    mechanism: Mechanism       # the derived one (names.internal)
    user: Mechanism
    theta: tuple[sp.Symbol, ...]
    theta_d: tuple[sp.Symbol, ...]
    coords: tuple[sp.Symbol, ...]   # every coordinate, in the model's order
    positions: sp.Matrix       # every coordinate as a function of theta
    mass: sp.Matrix            # M (n x n)
    damping: sp.Matrix         # B (n x n)
    velocity_terms: sp.Matrix  # h (n)
    static_terms: tuple[sp.Matrix, ...]  # G's contributions (one per spring, body, load)
    generalised_force: sp.Matrix  # G (n)
    stiffness: sp.Matrix       # K = dG/dtheta (n x n)
    potential: sp.Expr         # V, up to a constant: springs, gravity, loads' work
    points: dict[str, tuple[sp.Expr, sp.Expr]]
    # the straight-line program (symbol, expression) the expressions above are written in:
    # each dyad's assembly root and the cosine and sine of the angles it fixes (none without)
    program: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()

    @property
    def n(self) -> int:
        return len(self.theta)


#: Each mechanism's derivation, once per process (keyed by the mechanism's identity).
_DERIVED: dict[Mechanism, Multibody] = {}


def derive_multibody(user: Mechanism) -> Multibody:
    """Every expression of the library of a mechanism with n coordinates."""
    if user not in _DERIVED:
        _DERIVED[user] = _derive(user)
    return _DERIVED[user]


def _derive(user: Mechanism) -> Multibody:
    mechanism = internal(user)
    state = StateSymbols.of(mechanism)
    freezer = mechanism.freezer()
    coords = state.coords
    by_name = dict(zip((c.name for c in mechanism.coordinates), zip(state.coords, state.rates)))
    theta = tuple(by_name[n][0] for n in mechanism.independents)
    theta_d = tuple(by_name[n][1] for n in mechanism.independents)
    constraints = [c.subs(freezer) for c in mechanism.constraints]
    closure = solve_closures(mechanism, coords, constraints)
    positions = sp.Matrix([closure.values.get(c, c) for c in coords])

    def along(expr: sp.Expr) -> sp.Expr:
        return closure.along(sp.sympify(expr).subs(freezer))

    def jacobian(expr: sp.Expr) -> sp.Matrix:
        return sp.Matrix([[closure.diff(along(expr), t) for t in theta]])

    n = len(theta)
    mass, damping = sp.zeros(n, n), sp.zeros(n, n)
    for body in mechanism.bodies:
        for inertia, coordinate in ([(body.mass, x) for x in body.centre]
                                    + [(body.inertia, body.angle)]):
            if inertia != 0 and coordinate != 0:
                J = jacobian(coordinate)
                mass += inertia * J.T * J
    for damper in mechanism.dampers:
        J = jacobian(damper.length)
        damping += damper.coefficient * J.T * J
    # a dyad's closed form is left as derived: simplify takes minutes on its square roots
    tidy = sp.simplify if not closure.radicands else (lambda e: e)
    mass, damping = mass.applyfunc(tidy), damping.applyfunc(tidy)
    velocity_terms = sp.Matrix([
        sum((closure.diff(mass[i, j], theta[k]) - closure.diff(mass[j, k], theta[i]) / 2)
            * theta_d[j] * theta_d[k]
            for j in range(n) for k in range(n)) for i in range(n)])
    parts = [along(p) for p in contributions(mechanism)]
    static_terms = tuple(sp.Matrix([closure.diff(p, t) for t in theta]) for p in parts)
    force = sum(static_terms, sp.zeros(n, 1))
    return Multibody(
        mechanism=mechanism, user=user, theta=theta, theta_d=theta_d, coords=coords,
        positions=positions, mass=mass, damping=damping,
        velocity_terms=velocity_terms.applyfunc(sp.expand if not closure.radicands else tidy),
        static_terms=static_terms, generalised_force=force,
        stiffness=(force.jacobian(theta) if not closure.program else
                   sp.Matrix([[closure.diff(g, t) for t in theta] for g in force])),
        potential=sum(parts, sp.S.Zero),
        points={name: (along(x), along(y)) for name, (x, y) in mechanism.points.items()},
        program=closure.program)
