"""Table 1 step 7: energies and Lagrange's equations with multipliers, (15)-(29).

    d/dt(dL/dqdot) - dL/dq + A^T lambda + V_D = Q_nc
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model import TIME, Mechanism
from ..model.mechanism import Torque


@dataclass(frozen=True)
class Dynamics:
    kinetic: sp.Expr          # T, (16)-(19)
    gravity_potential: sp.Expr  # V_G, (20)
    elastic_potential: sp.Expr  # V_E, (21)
    lagrangian: sp.Expr       # L = T - V_G - V_E, (22)
    dt_dL_dqdot: sp.Matrix    # (23)
    dL_dq: sp.Matrix          # (24)
    constraint_forces: sp.Matrix  # A^T lambda, (27)
    applied_forces: sp.Matrix     # Q_nc, (28)
    dissipative_forces: sp.Matrix  # V_D = dD/dqdot, (29)

    def residual(self) -> sp.Matrix:
        """Left side minus right side of (15): zero along every motion."""
        return (self.dt_dL_dqdot - self.dL_dq + self.constraint_forces
                + self.dissipative_forces - self.applied_forces)


def kinetic_energy(mechanism: Mechanism) -> sp.Expr:
    """Translation of each centre of mass plus rotation about it."""
    total = sp.S.Zero
    for body in mechanism.bodies:
        v = sp.Matrix(body.centre).diff(TIME)
        total += body.mass * v.dot(v) / 2 + body.inertia * sp.diff(body.angle, TIME) ** 2 / 2
    return total


def gravity_potential(mechanism: Mechanism) -> sp.Expr:
    return sum((b.mass * mechanism.gravity * b.centre[1] for b in mechanism.bodies), sp.S.Zero)


def elastic_potential(mechanism: Mechanism) -> sp.Expr:
    return sum((s.stiffness * (s.length - s.free_length) ** 2 / 2 for s in mechanism.springs),
               sp.S.Zero)


def rayleigh_dissipation(mechanism: Mechanism) -> sp.Expr:
    return sum((d.coefficient * sp.diff(d.length, TIME) ** 2 / 2 for d in mechanism.dampers),
               sp.S.Zero)


def force_on(mechanism: Mechanism, load) -> sp.Matrix:
    """Generalised force of one PointForce or Torque by virtual work: Q_i = F . dpoint/dq_i,
    or T dangle/dq_i."""
    q = mechanism.q
    if isinstance(load, Torque):
        return sp.Matrix([load.angle]).jacobian(q).T * load.torque
    return sp.Matrix(load.point).jacobian(q).T * sp.Matrix(load.force)


def applied_forces(mechanism: Mechanism) -> sp.Matrix:
    """Generalised forces of every constant force and torque, by virtual work."""
    return sum((force_on(mechanism, f) for f in mechanism.forces + mechanism.torques),
               sp.zeros(len(mechanism.q), 1))


def contributions(mechanism: Mechanism) -> tuple[sp.Expr, ...]:
    """The potential of each spring, body (gravity) and constant load (-F.p, -T angle), in
    the coordinates: G is the sum of their slopes along the motion, one physical cause each."""
    parts = [s.stiffness * (s.length - s.free_length) ** 2 / 2 for s in mechanism.springs]
    parts += [b.mass * mechanism.gravity * b.centre[1] for b in mechanism.bodies if b.mass != 0]
    parts += [-(f.force[0] * f.point[0] + f.force[1] * f.point[1]) for f in mechanism.forces]
    parts += [-t.torque * t.angle for t in mechanism.torques]
    return tuple(p.subs(mechanism.freezer()) for p in parts)


def derive_dynamics(mechanism: Mechanism, jacobian: sp.Matrix,
                    multipliers: tuple[sp.Symbol, ...]) -> Dynamics:
    q = mechanism.q
    qdot = q.diff(TIME)
    T = kinetic_energy(mechanism)
    V_G, V_E = gravity_potential(mechanism), elastic_potential(mechanism)
    lagrangian = T - V_G - V_E
    dL_dqdot = sp.Matrix([lagrangian.diff(v) for v in qdot])
    D = rayleigh_dissipation(mechanism)
    return Dynamics(
        kinetic=T,
        gravity_potential=V_G,
        elastic_potential=V_E,
        lagrangian=lagrangian,
        dt_dL_dqdot=dL_dqdot.diff(TIME),
        dL_dq=sp.Matrix([lagrangian.diff(c) for c in q]),
        constraint_forces=(jacobian.T * sp.Matrix(multipliers) if multipliers
                           else sp.zeros(len(q), 1)),
        applied_forces=applied_forces(mechanism),
        dissipative_forces=sp.Matrix([D.diff(v) for v in qdot]),
    )
