"""A quick-return shaper: a Whitworth crank and slotted lever whose tip drives a ram through
a link (an RPR dyad followed by an RRP dyad), as a user writes it.

The crank O-P (radius r, angle theta) about O = (0, 0); its pin P slides in a lever pivoted
at Q = (0, -h), at distance s along it, the lever at angle phi, length l_L. The link E-R
(length l, angle psi) from the lever's tip E to the ram R = (x, y_R) on a horizontal slide.
A spring k (free length l_0) from the ram to the anchor W = (x_W, y_W); a torque T on the
crank; a cutting force F on the ram along -X. Gravity -Y. The ram is ahead of the link's
upper end: x > E_x.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, PointForce, Requirement,
                                     Spring, Torque, distance, parameter)

PARAMETERS = (
    parameter("r", "m", "crank radius", "0.1"),
    parameter("h", "m", "depth of the lever's pivot below the crank's", "0.25"),
    parameter("l_L", "m", "lever length", "0.6"),
    parameter("l", "m", "link length", "0.3"),
    parameter("y_R", "m", "height of the ram's slide", "0.3"),
    parameter("m_c", "kg", "crank mass", "0.5"),
    parameter("m_L", "kg", "lever mass", "1.2"),
    parameter("m_l", "kg", "link mass", "0.4"),
    parameter("m_R", "kg", "ram mass", "3.0"),
    parameter("k", "N/m", "spring stiffness", "300"),
    parameter("l_0", "m", "spring free length", "0.5"),
    parameter("x_W", "m", "spring anchor abscissa", "0.8"),
    parameter("y_W", "m", "spring anchor ordinate", "0.1"),
    parameter("T", "N m", "torque on the crank", "0.5"),
    parameter("F", "N", "cutting force on the ram (along -X)", "5"),
    parameter("g", "m/s^2", "gravity", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("s", "m", "distance of the pin along the lever"),
    Coordinate("phi", "rad", "lever angle"),
    Coordinate("psi", "rad", "link angle"),
    Coordinate("x", "m", "ram position"),
)


def build():
    r, h, l_L, l, y_R, m_c, m_L, m_l, m_R, k, l_0, x_W, y_W, T, F, g = (p.symbol for p in PARAMETERS)
    theta, s, phi, psi, x = (q.function for q in COORDINATES)
    tip = (l_L * sp.cos(phi), -h + l_L * sp.sin(phi))
    ram = (x, y_R)
    return Mechanism(
        name="quick_return_shaper", title="a quick-return shaper",
        parameters=PARAMETERS, coordinates=COORDINATES, independent="theta",
        constraints=(r * sp.cos(theta) - s * sp.cos(phi), r * sp.sin(theta) + h - s * sp.sin(phi),
                     tip[0] + l * sp.cos(psi) - x, tip[1] + l * sp.sin(psi) - y_R),
        bodies=(Body("crank", m_c, (r / 2 * sp.cos(theta), r / 2 * sp.sin(theta)),
                     inertia=m_c * r**2 / 12, angle=theta),
                Body("lever", m_L, (tip[0] / 2, (tip[1] - h) / 2), inertia=m_L * l_L**2 / 12,
                     angle=phi),
                Body("link", m_l, ((tip[0] + x) / 2, (tip[1] + y_R) / 2), inertia=m_l * l**2 / 12,
                     angle=psi),
                Body("ram", m_R, ram)),
        springs=(Spring(k, l_0, distance(ram, (x_W, y_W))),),
        dampers=(), forces=(PointForce(ram, (-F, 0)),), torques=(Torque(T, theta),), gravity=g,
        points={"P": (r * sp.cos(theta), r * sp.sin(theta)), "E": tip, "R": ram},
        polar_pairs=(("s", "phi"),),
        assembly_modes=(x - tip[0],),
        requirements=(Requirement(sp.And(r > 0, h > r, l_L > 0, l > 0), "GEOMETRY",
                                  "r, l_L, l must be positive and h > r"),),
    )
