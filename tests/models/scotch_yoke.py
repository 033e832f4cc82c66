"""A Scotch yoke with a return spring, as data.

A crank (radius R, mass m_c, angle theta) carries a pin at P = (R cos theta, R sin theta)
that slides in the vertical slot of a yoke (mass m_y); the yoke moves on the horizontal
line y = 0, its slot at x. A spring k (free length l_0) runs from the yoke's lug
L = (x + x_L, y_L) to the anchor S = (x_S, y_S); a damper b acts on x, a force F pushes the
yoke along +X. Gravity along -Y.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, PointForce, Spring,
                                     distance, parameter)

PARAMETERS = (
    parameter("R", "m", "crank radius", "0.1"),
    parameter("m_c", "kg", "mass of the crank", "0.6"),
    parameter("m_y", "kg", "mass of the yoke", "1.5"),
    parameter("x_L", "m", "lug of the yoke, along X from the slot", "0.15"),
    parameter("y_L", "m", "lug of the yoke, ordinate", "0.05"),
    parameter("k", "N/m", "spring stiffness", "800"),
    parameter("l_0", "m", "free length of the spring", "0.2"),
    parameter("x_S", "m", "abscissa of the anchor S", "0.45"),
    parameter("y_S", "m", "ordinate of the anchor S", "0.12"),
    parameter("b", "N s/m", "damping on the yoke", "15"),
    parameter("F", "N", "force on the yoke along +X", "20"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("x", "m", "position of the yoke's slot"),
)


def build() -> Mechanism:
    R, m_c, m_y, x_L, y_L, k, l_0, x_S, y_S, b, F, g = (p.symbol for p in PARAMETERS)
    theta, x = (q.function for q in COORDINATES)
    lug = (x + x_L, y_L)
    return Mechanism(
        name="scotch_yoke",
        title="a Scotch yoke with a return spring",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(x - R * sp.cos(theta),),   # the pin stays in the slot
        bodies=(
            Body("crank", m_c, (R / 2 * sp.cos(theta), R / 2 * sp.sin(theta)),
                 inertia=m_c * R**2 / 12, angle=theta),
            Body("yoke", m_y, (x, sp.S.Zero)),
        ),
        springs=(Spring(k, l_0, distance(lug, (x_S, y_S))),),
        dampers=(Damper(b, x),),
        forces=(PointForce((x, sp.S.Zero), (F, sp.S.Zero)),),
        gravity=g,
        points={"L": lug},
    )
