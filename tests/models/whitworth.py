"""A Whitworth crank and slotted lever (inverted slider-crank), as a user writes it.

The crank O-P (radius r, mass m_c, angle theta) turns about O = (0, 0); its pin P slides in a
slotted lever pivoted at Q = (0, -h) below the crank, at distance s along the lever, whose
angle is phi. A torsion-free lever of length l_L and mass m_L; a spring k (free length l_0)
from the lever's tip E to the anchor A = (x_A, y_A); a torque T on the crank. Gravity -Y.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, Requirement, Spring, Torque,
                                     distance, parameter)

PARAMETERS = (
    parameter("r", "m", "crank radius", "0.1"),
    parameter("h", "m", "depth of the lever's pivot below the crank's", "0.25"),
    parameter("l_L", "m", "lever length", "0.6"),
    parameter("m_c", "kg", "crank mass", "0.5"),
    parameter("m_L", "kg", "lever mass", "1.2"),
    parameter("k", "N/m", "spring stiffness", "300"),
    parameter("l_0", "m", "spring free length", "0.2"),
    parameter("x_A", "m", "anchor abscissa", "0.4"),
    parameter("y_A", "m", "anchor ordinate", "0.3"),
    parameter("T", "N m", "torque on the crank", "0.5"),
    parameter("g", "m/s^2", "gravity", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("s", "m", "distance of the pin along the lever"),
    Coordinate("phi", "rad", "lever angle"),
)


def build():
    r, h, l_L, m_c, m_L, k, l_0, x_A, y_A, T, g = (p.symbol for p in PARAMETERS)
    theta, s, phi = (q.function for q in COORDINATES)
    tip = (l_L * sp.cos(phi), -h + l_L * sp.sin(phi))
    return Mechanism(
        name="whitworth", title="a Whitworth crank and slotted lever",
        parameters=PARAMETERS, coordinates=COORDINATES, independent="theta",
        constraints=(r * sp.cos(theta) - s * sp.cos(phi), r * sp.sin(theta) + h - s * sp.sin(phi)),
        bodies=(Body("crank", m_c, (r / 2 * sp.cos(theta), r / 2 * sp.sin(theta)),
                     inertia=m_c * r**2 / 12, angle=theta),
                Body("lever", m_L, (tip[0] / 2, (tip[1] - h) / 2), inertia=m_L * l_L**2 / 12,
                     angle=phi)),
        springs=(Spring(k, l_0, distance(tip, (x_A, y_A))),),
        dampers=(), forces=(), torques=(Torque(T, theta),), gravity=g,
        points={"P": (r * sp.cos(theta), r * sp.sin(theta)), "E": tip},
        polar_pairs=(("s", "phi"),),
        requirements=(Requirement(sp.And(r > 0, h > r, l_L > 0), "GEOMETRY",
                                  "r, l_L must be positive and h > r"),),
    )
