"""A pendulum held by two springs from two anchors, as data.

A uniform bar O-P (length l, mass m) pivots at the origin at angle theta, a point mass m_t at
its tip P. Springs k_1 (free length l_1) and k_2 (l_2) run from P to the anchors A_1 and A_2;
a torsional damper c acts at the pivot, a damper c_1 along the first spring. Gravity along -Y.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Spring, distance,
                                     parameter)

PARAMETERS = (
    parameter("l", "m", "length of the bar", "1"),
    parameter("m", "kg", "mass of the bar", "1.5"),
    parameter("m_t", "kg", "point mass at the tip", "0.5"),
    parameter("k_1", "N/m", "stiffness of the first spring", "60"),
    parameter("l_1", "m", "free length of the first spring", "0.8"),
    parameter("x_1", "m", "abscissa of the first anchor", "-0.6"),
    parameter("y_1", "m", "ordinate of the first anchor", "1.2"),
    parameter("k_2", "N/m", "stiffness of the second spring", "35"),
    parameter("l_2", "m", "free length of the second spring", "0.5"),
    parameter("x_2", "m", "abscissa of the second anchor", "1.1"),
    parameter("y_2", "m", "ordinate of the second anchor", "-0.4"),
    parameter("c", "N m s/rad", "torsional damping at the pivot", "0.3"),
    parameter("c_1", "N s/m", "damping along the first spring", "2"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (Coordinate("theta", "rad", "angle of the bar"),)


def build() -> Mechanism:
    l, m, m_t, k_1, l_1, x_1, y_1, k_2, l_2, x_2, y_2, c, c_1, g = (p.symbol for p in PARAMETERS)
    (theta,) = (q.function for q in COORDINATES)
    tip = (l * sp.cos(theta), l * sp.sin(theta))
    first = distance(tip, (x_1, y_1))
    return Mechanism(
        name="two_spring_pendulum",
        title="a pendulum held by two springs",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(),
        bodies=(Body("bar", m, (tip[0] / 2, tip[1] / 2), inertia=m * l**2 / 12, angle=theta),
                Body("tip mass", m_t, tip)),
        springs=(Spring(k_1, l_1, first), Spring(k_2, l_2, distance(tip, (x_2, y_2)))),
        dampers=(Damper(c, theta), Damper(c_1, first)),
        forces=(),
        gravity=g,
        points={"P": tip},
    )
