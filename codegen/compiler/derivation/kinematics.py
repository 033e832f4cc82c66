"""Table 1 steps 3-6: constraints at position, velocity and acceleration level, the
velocity-constraint matrix, and the kinematics of the points of interest."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model import TIME, Mechanism


@dataclass(frozen=True)
class Kinematics:
    constraints: sp.Matrix               # f(q) = 0, (4)-(7)
    jacobian: sp.Matrix                  # A = df/dq, (25)
    velocity_constraints: sp.Matrix      # df/dt = A qdot, (8)-(11)
    acceleration_constraints: sp.Matrix  # d2f/dt2 = A qddot + Adot qdot
    point_positions: dict[str, sp.Matrix]
    point_velocities: dict[str, sp.Matrix]


def position_constraints(mechanism: Mechanism) -> sp.Matrix:
    """f(q) as a column (0 x 1 for a mechanism without constraints)."""
    return sp.Matrix(len(mechanism.constraints), 1, list(mechanism.constraints))


def derive_kinematics(mechanism: Mechanism) -> Kinematics:
    f = position_constraints(mechanism)
    positions = {name: sp.Matrix(xy) for name, xy in mechanism.points.items()}
    return Kinematics(
        constraints=f,
        jacobian=f.jacobian(mechanism.q) if f.rows else sp.zeros(0, len(mechanism.q)),
        velocity_constraints=f.diff(TIME),
        acceleration_constraints=f.diff(TIME, 2),
        point_positions=positions,
        point_velocities={name: xy.diff(TIME) for name, xy in positions.items()},
    )
