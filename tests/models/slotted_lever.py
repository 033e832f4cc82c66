"""A slotted lever driving a block on a vertical rail, as data (issue 26's model).

A uniform bar (length l, mass m) pivots at the origin at angle theta. A collar at distance s
along it is pinned to a block (mass m_b) on the vertical rail x = d, at height y. A spring
k of free length l_0 runs from the block to the anchor A = (x_A, y_A); a damper c acts on y.
Gravity along -Y. Where cos(theta) < 0 the collar is behind the pivot (s < 0); at theta =
+-90 deg the block is at infinity.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Spring, distance,
                                     parameter)

PARAMETERS = (
    parameter("l", "m", "length of the bar", "1"),
    parameter("m", "kg", "mass of the bar", "2"),
    parameter("m_b", "kg", "mass of the block", "1"),
    parameter("d", "m", "abscissa of the rail", "0.4"),
    parameter("k", "N/m", "spring stiffness", "400"),
    parameter("l_0", "m", "free length of the spring", "0.3"),
    parameter("x_A", "m", "abscissa of the anchor A", "0.9"),
    parameter("y_A", "m", "ordinate of the anchor A", "0.2"),
    parameter("c", "N s/m", "damping coefficient on the rail", "5"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "angle of the bar"),
    Coordinate("s", "m", "position of the collar along the bar"),
    Coordinate("y", "m", "height of the block"),
)


def build() -> Mechanism:
    l, m, m_b, d, k, l_0, x_A, y_A, c, g = (p.symbol for p in PARAMETERS)
    theta, s, y = (q.function for q in COORDINATES)
    block = (d, y)
    return Mechanism(
        name="slotted_lever",
        title="a slotted lever driving a block on a vertical rail",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(s * sp.cos(theta) - d, s * sp.sin(theta) - y),
        bodies=(
            Body("bar", m, (l / 2 * sp.cos(theta), l / 2 * sp.sin(theta)), inertia=m * l**2 / 12,
                 angle=theta),
            Body("block", m_b, block),
        ),
        springs=(Spring(k, l_0, distance(block, (x_A, y_A))),),
        dampers=(Damper(c, y),),
        forces=(),
        gravity=g,
        points={"C": block},
    )
