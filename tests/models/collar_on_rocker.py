"""A four-bar whose rocker carries a collar held by a link from a ground pin: an RRR dyad,
then a PRR dyad whose slide is the rocker itself, as a user writes it.

Crank O-A (a, m_a, angle theta) about O = (0, 0); coupler A-B (b, m_b, angle phi); rocker
D-B (c, m_c, angle psi) about D = (d, 0). A collar K (m_K) slides along the rocker at the
distance s from D; a link of length L (m_L, angle chi) joins it to the ground pin G =
(x_G, y_G). A spring k (free length l_0) along the rocker from D to the collar; a torque T on
the crank. Gravity -Y. Declared: the coupler's joint B above the line from A to D (the
usual crank-rocker), and the collar beyond the foot of the perpendicular from G.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, Requirement, Spring, Torque,
                                     parameter)

PARAMETERS = (
    parameter("a", "m", "crank length", "0.1"),
    parameter("b", "m", "coupler length", "0.35"),
    parameter("c", "m", "rocker length", "0.3"),
    parameter("d", "m", "ground link length", "0.3"),
    parameter("m_a", "kg", "crank mass", "0.3"),
    parameter("m_b", "kg", "coupler mass", "0.6"),
    parameter("m_c", "kg", "rocker mass", "0.5"),
    parameter("m_K", "kg", "collar mass", "0.4"),
    parameter("L", "m", "length of the collar's link", "0.25"),
    parameter("m_L", "kg", "mass of the collar's link", "0.2"),
    parameter("x_G", "m", "ground pin abscissa", "0.35"),
    parameter("y_G", "m", "ground pin ordinate", "0.2"),
    parameter("k", "N/m", "spring stiffness", "150"),
    parameter("l_0", "m", "spring free length", "0.1"),
    parameter("T", "N m", "torque on the crank", "0.3"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("phi", "rad", "coupler angle"),
    Coordinate("psi", "rad", "rocker angle"),
    Coordinate("s", "m", "collar distance along the rocker from D"),
    Coordinate("chi", "rad", "angle of the collar's link"),
)


def build() -> Mechanism:
    a, b, c, d, m_a, m_b, m_c, m_K, L, m_L, x_G, y_G, k, l_0, T, g = (
        p.symbol for p in PARAMETERS)
    theta, phi, psi, s, chi = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a * cos(theta), a * sin(theta))
    B = (d + c * cos(psi), c * sin(psi))
    K = (d + s * cos(psi), s * sin(psi))
    return Mechanism(
        name="collar_on_rocker",
        title="a four-bar whose rocker carries a collar held by a link",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(A[0] + b * cos(phi) - B[0], A[1] + b * sin(phi) - B[1],
                     K[0] - x_G - L * cos(chi), K[1] - y_G - L * sin(chi)),
        bodies=(
            Body("crank", m_a, (A[0] / 2, A[1] / 2), inertia=m_a * a**2 / 12, angle=theta),
            Body("coupler", m_b, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2),
                 inertia=m_b * b**2 / 12, angle=phi),
            Body("rocker", m_c, ((d + B[0]) / 2, B[1] / 2), inertia=m_c * c**2 / 12, angle=psi),
            Body("collar", m_K, K),
            Body("link", m_L, ((K[0] + x_G) / 2, (K[1] + y_G) / 2), inertia=m_L * L**2 / 12,
                 angle=chi),
        ),
        springs=(Spring(k, l_0, s),),
        dampers=(),
        forces=(),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B, "K": K},
        assembly_modes=(
            (d - A[0]) * (B[1] - A[1]) - (0 - A[1]) * (B[0] - A[0]),   # B left of A->D
            s - ((x_G - d) * cos(psi) + y_G * sin(psi)),
        ),
        requirements=(Requirement(sp.And(a > 0, b > 0, c > 0, d > 0, L > 0), "LENGTH",
                                  "lengths must be positive"),),
    )
