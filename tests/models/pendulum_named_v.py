"""A pendulum with a spring from its tip, one of whose parameters is named ``v``, as data.

A uniform bar (length l, mass m) pivots at the origin at angle theta; a spring k (free length
l_0) runs from its tip to the anchor (u, v). Gravity along -Y. The names are a user's choice.
"""
import sympy as sp

from codegen.model.mechanism import Body, Coordinate, Mechanism, Spring, distance, parameter

PARAMETERS = (
    parameter("l", "m", "length of the bar", "1"),
    parameter("m", "kg", "mass of the bar", "1"),
    parameter("k", "N/m", "spring stiffness", "20"),
    parameter("l_0", "m", "free length of the spring", "1"),
    parameter("u", "m", "abscissa of the anchor", "0.5"),
    parameter("v", "m", "ordinate of the anchor", "1.5"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (Coordinate("theta", "rad", "angle of the bar"),)


def build() -> Mechanism:
    l, m, k, l_0, u, v, g = (p.symbol for p in PARAMETERS)
    (theta,) = (q.function for q in COORDINATES)
    tip = (l * sp.cos(theta), l * sp.sin(theta))
    return Mechanism(
        name="pendulum_named_v",
        title="a pendulum with a parameter named v",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(),
        bodies=(Body("bar", m, (tip[0] / 2, tip[1] / 2), inertia=m * l**2 / 12, angle=theta),),
        springs=(Spring(k, l_0, distance(tip, (u, v))),),
        dampers=(),
        forces=(),
        gravity=g,
        points={"P": tip},
    )
