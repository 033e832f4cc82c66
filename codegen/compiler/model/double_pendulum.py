"""Two bars on torsional springs (2 DOF), as data: a column that buckles when its springs
are weak.

Bar 1 O-A (length l_1, mass m_1) pivots at the origin at angle theta_1 from +X; bar 2 A-B
(l_2, m_2) hangs from A at the absolute angle theta_2, and a point mass m_t sits at B. A
torsional spring k_1 (free angle alpha_1) with a damper c_1 acts at O on theta_1, a second,
k_2 (free angle alpha_2) with c_2, at A on the relative angle delta = theta_2 - theta_1. A
constant force F_x pushes B along +X; gravity acts along -Y. The independent coordinates are
theta_1 and delta (theta_2 follows from them): the springs wind, so each ranges over a turn
about its spring's free angle, and their box is the range.
"""
import sympy as sp

from .mechanism import (parameter, Body, Coordinate, Damper, Mechanism, PointForce, Requirement,
                        Sketch, Spring)

PARAMETERS = (
    parameter("l_1", "m", "length of bar 1", "1.0"),
    parameter("l_2", "m", "length of bar 2", "0.8"),
    parameter("m_1", "kg", "mass of bar 1", "1.0"),
    parameter("m_2", "kg", "mass of bar 2", "0.8"),
    parameter("m_t", "kg", "point mass at the tip B", "0.5"),
    parameter("k_1", "N m/rad", "stiffness of the torsional spring at O", "30"),
    parameter("k_2", "N m/rad", "stiffness of the torsional spring at A", "15"),
    parameter("alpha_1", "rad", "free angle of the spring at O", "1.5707963267948966"),
    parameter("alpha_2", "rad", "free relative angle of the spring at A", "0"),
    parameter("c_1", "N m s/rad", "damping at O", "0.3"),
    parameter("c_2", "N m s/rad", "damping at A", "0.2"),
    parameter("F_x", "N", "force at the tip B along +X", "0"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (
    Coordinate("theta_1", "rad", "angle of bar 1 from +X"),
    Coordinate("delta", "rad", "angle of bar 2 relative to bar 1"),
    Coordinate("theta_2", "rad", "angle of bar 2 from +X"),
)


def build() -> Mechanism:
    l_1, l_2, m_1, m_2, m_t, k_1, k_2, alpha_1, alpha_2, c_1, c_2, F_x, g = (
        p.symbol for p in PARAMETERS)
    theta_1, delta, theta_2 = (c.function for c in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (l_1 * cos(theta_1), l_1 * sin(theta_1))
    B = (A[0] + l_2 * cos(theta_2), A[1] + l_2 * sin(theta_2))
    return Mechanism(
        name="double_pendulum",
        title="a double pendulum on torsional springs",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent=("theta_1", "delta"),
        constraints=(theta_2 - theta_1 - delta,),
        bodies=(
            Body("bar 1", m_1, (A[0] / 2, A[1] / 2), inertia=m_1 * l_1**2 / 12, angle=theta_1),
            Body("bar 2", m_2, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2),
                 inertia=m_2 * l_2**2 / 12, angle=theta_2),
            Body("tip mass", m_t, B),
        ),
        springs=(Spring(k_1, alpha_1, theta_1), Spring(k_2, alpha_2, delta)),
        dampers=(Damper(c_1, theta_1), Damper(c_2, delta)),
        forces=(PointForce(B, (F_x, sp.S.Zero)),),
        gravity=g,
        points={"A": A, "B": B},
        range_centre=(alpha_1, alpha_2),
        periodic=(False, False),
        sketch=Sketch(points={"O": (sp.S.Zero, sp.S.Zero)}, links=(("O", "A", "B"),),
                      fixed=("O",), angle=("O", sp.S.Zero, theta_1)),
        requirements=(
            Requirement(sp.And(l_1 > 0, l_2 > 0), "LENGTH_NOT_POSITIVE",
                        "l_1 and l_2 must be positive"),
            Requirement(sp.And(m_1 >= 0, m_2 >= 0, m_t >= 0), "MASS_NEGATIVE",
                        "masses m_1, m_2, m_t must not be negative"),
            Requirement(sp.And(k_1 >= 0, k_2 >= 0), "K_NEGATIVE",
                        "k_1 and k_2 must not be negative"),
            Requirement(sp.And(c_1 >= 0, c_2 >= 0), "C_NEGATIVE",
                        "c_1 and c_2 must not be negative"),
        ),
    )
