"""Doughty's mechanism with a flexible bar (2 DOF), as data: the paper's mechanism with its
bar split into two halves joined by a torsional spring.

Slider 1 (m_A, point A) runs on the X axis, slider 2 (m_B, point B) on the Y axis. The bar
B-A (length L, mass m_C) is two uniform halves B-J and J-A, each L/2 long, joined at J by a
revolute joint with a torsional spring k_t (free when the bar is straight) and a damper c_t.
Each half's angle is measured as the paper's theta: theta_1 (B-J) and theta_2 (J-A), so
J = B + (L/2)(cos theta_1, -sin theta_1), A = J + (L/2)(cos theta_2, -sin theta_2). A spring
k (free length l_ND) with a damper b runs from (H, 0) to the point P of the first half at
distance a from B; a force F pushes slider 2 along +Y; gravity acts along -Y. The
independent coordinates are theta_1, periodic, and the bend delta = theta_2 - theta_1 in
(-pi, pi); the sliders' positions follow from them. With delta = 0 it is the paper's.
"""
import sympy as sp

from .doughty import PARAMETERS as RIGID
from .mechanism import (parameter, Body, Coordinate, Damper, Mechanism, PointForce, Requirement,
                        Sketch, Spring, distance)

#: The paper's (Table 2), then the joint's
PARAMETERS = RIGID + (
    parameter("k_t", "N m/rad", "stiffness of the torsional spring at J", "2000"),
    parameter("c_t", "N m s/rad", "damping of the joint at J", "2"),
)

COORDINATES = (
    Coordinate("theta_1", "rad", "angle of the half B-J"),
    Coordinate("delta", "rad", "bend at J: theta_2 - theta_1"),
    Coordinate("theta_2", "rad", "angle of the half J-A"),
    Coordinate("p", "m", "position of slider 1 on X"),
    Coordinate("q", "m", "position of slider 2 on Y"),
)


def build() -> Mechanism:
    H, L, a, m_A, m_B, m_C, k, b, l_ND, F, g, k_t, c_t = (p.symbol for p in PARAMETERS)
    theta_1, delta, theta_2, p, q = (c.function for c in COORDINATES)
    cos, sin = sp.cos, sp.sin
    B = (sp.S.Zero, q)
    J = (L / 2 * cos(theta_1), q - L / 2 * sin(theta_1))
    A = (p, sp.S.Zero)
    P = (a * cos(theta_1), q - a * sin(theta_1))
    half = m_C / 2
    spring = distance((H, sp.S.Zero), P)
    return Mechanism(
        name="flexible_doughty",
        title="Doughty's mechanism with a flexible bar",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent=("theta_1", "delta"),
        constraints=(  # the bend, and the loop B-J-A closing on the X axis
            theta_2 - theta_1 - delta,
            p - L / 2 * (cos(theta_1) + cos(theta_2)),
            q - L / 2 * (sin(theta_1) + sin(theta_2)),
        ),
        bodies=(
            Body("slider 1", m_A, A),
            Body("slider 2", m_B, B),
            Body("half B-J", half, ((B[0] + J[0]) / 2, (B[1] + J[1]) / 2),
                 inertia=half * (L / 2) ** 2 / 12, angle=theta_1),
            Body("half J-A", half, ((J[0] + A[0]) / 2, (J[1] + A[1]) / 2),
                 inertia=half * (L / 2) ** 2 / 12, angle=theta_2),
        ),
        springs=(Spring(k, l_ND, spring), Spring(k_t, sp.S.Zero, delta)),
        dampers=(Damper(b, spring), Damper(c_t, delta)),
        forces=(PointForce(B, (sp.S.Zero, F)),),
        gravity=g,
        points={"A": A, "B": B, "J": J, "P": P},
        range_centre=(sp.S.Zero, sp.S.Zero),
        periodic=(True, False),
        sketch=Sketch(points={"O'": (H, sp.S.Zero)}, links=(("B", "J", "A"),),
                      sliders=(("A", sp.S.Zero), ("B", sp.pi / 2)), fixed=("O'",),
                      springs=(("O'", "P"),)),
        singular_state="the spring's length is zero, so its direction is undefined",
        requirements=(
            Requirement(L > 0, "L_NOT_POSITIVE", "L must be positive"),
            Requirement(sp.And(a >= 0, a <= L / 2), "A_OUT_OF_RANGE", "a must lie in [0, L/2]"),
            Requirement(l_ND >= 0, "L_ND_NEGATIVE", "l_ND must not be negative"),
            Requirement(sp.And(m_A >= 0, m_B >= 0, m_C >= 0), "MASS_NEGATIVE",
                        "masses m_A, m_B, m_C must not be negative"),
            Requirement(sp.And(k >= 0, k_t >= 0), "K_NEGATIVE", "k and k_t must not be negative"),
            Requirement(sp.And(b >= 0, c_t >= 0), "B_NEGATIVE", "b and c_t must not be negative"),
        ),
    )
