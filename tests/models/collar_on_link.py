"""A collar on a pendulum, held by a link of fixed length from a ground pin.

The pendulum (length l, mass m, angle theta from +X) pivots at O = (0, 0); the collar C
(mass m_C) slides along it at distance s; a link of length L (massless) joins C to the ground
pin G = (x_G, y_G), at angle psi; a bracket on the link carries a mass m_B at L_B from G, at
psi + beta (an angle written as a sum: the derivation expands it). A spring k (free length
l_0) along the pendulum from O to C. Gravity -Y; torque T on the pendulum.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, Requirement, Spring, Torque,
                                     parameter)

PARAMETERS = (
    parameter("l", "m", "pendulum length", "1"),
    parameter("m", "kg", "pendulum mass", "2"),
    parameter("m_C", "kg", "collar mass", "0.5"),
    parameter("L", "m", "link length", "0.5"),
    parameter("x_G", "m", "ground pin abscissa", "0.2"),
    parameter("y_G", "m", "ground pin ordinate", "-0.3"),
    parameter("m_B", "kg", "mass on the link's bracket", "0.3"),
    parameter("L_B", "m", "distance of the bracket's mass from G", "0.25"),
    parameter("beta", "rad", "angle of the bracket from the link", "0.7"),
    parameter("k", "N/m", "spring stiffness", "200"),
    parameter("l_0", "m", "spring free length", "0.4"),
    parameter("T", "N m", "torque on the pendulum", "0"),
    parameter("g", "m/s^2", "gravity", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "pendulum angle"),
    Coordinate("s", "m", "collar distance along the pendulum"),
    Coordinate("psi", "rad", "link angle"),
)


def build():
    l, m, m_C, L, x_G, y_G, m_B, L_B, beta, k, l_0, T, g = (p.symbol for p in PARAMETERS)
    theta, s, psi = (q.function for q in COORDINATES)
    C = (s * sp.cos(theta), s * sp.sin(theta))
    return Mechanism(
        name="collar_on_link", title="a collar on a pendulum held by a link",
        parameters=PARAMETERS, coordinates=COORDINATES, independent="theta",
        constraints=(C[0] - x_G - L * sp.cos(psi), C[1] - y_G - L * sp.sin(psi)),
        bodies=(Body("pendulum", m, (l / 2 * sp.cos(theta), l / 2 * sp.sin(theta)),
                     inertia=m * l**2 / 12, angle=theta),
                Body("collar", m_C, C),
                Body("bracket", m_B, (x_G + L_B * sp.cos(psi + beta), y_G + L_B * sp.sin(psi + beta)))),
        springs=(Spring(k, l_0, s),),
        dampers=(), forces=(), torques=(Torque(T, theta),), gravity=g,
        points={"C": C},
        # the collar beyond the foot of the perpendicular from G: s greater than G's projection
        assembly_modes=(s - (x_G * sp.cos(theta) + y_G * sp.sin(theta)),),
        requirements=(Requirement(L > 0, "LINK", "L must be positive"),),
    )
