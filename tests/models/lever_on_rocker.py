"""A four-bar whose rocker pin drives a slotted lever: an RRR dyad, then an RPR dyad whose
pin the first dyad moves, as a user writes it.

Crank O-A (a, m_a, angle theta) about O = (0, 0); coupler A-B (b, m_b, angle phi); rocker
D-B (c, m_c, angle psi) about D = (d, 0). The rocker's end B is a pin sliding in the slot of
a lever (length l_L, m_L, angle chi) pivoted at Q = (x_Q, y_Q), at the distance s from Q (a
polar pair). A spring k (free length l_0) from the lever's tip E to the anchor (x_S, y_S); a
torque T on the crank. Gravity -Y. Declared: B above the line from A to D.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, Requirement, Spring, Torque,
                                     distance, parameter)

PARAMETERS = (
    parameter("a", "m", "crank length", "0.1"),
    parameter("b", "m", "coupler length", "0.35"),
    parameter("c", "m", "rocker length", "0.3"),
    parameter("d", "m", "ground link length", "0.3"),
    parameter("m_a", "kg", "crank mass", "0.3"),
    parameter("m_b", "kg", "coupler mass", "0.6"),
    parameter("m_c", "kg", "rocker mass", "0.5"),
    parameter("x_Q", "m", "lever pivot abscissa", "0.7"),
    parameter("y_Q", "m", "lever pivot ordinate", "0"),
    parameter("l_L", "m", "lever length", "0.6"),
    parameter("m_L", "kg", "lever mass", "0.8"),
    parameter("k", "N/m", "spring stiffness", "120"),
    parameter("l_0", "m", "spring free length", "0.15"),
    parameter("x_S", "m", "spring anchor abscissa", "0.3"),
    parameter("y_S", "m", "spring anchor ordinate", "0.6"),
    parameter("T", "N m", "torque on the crank", "0.2"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("phi", "rad", "coupler angle"),
    Coordinate("psi", "rad", "rocker angle"),
    Coordinate("s", "m", "distance of the pin B along the slot from Q"),
    Coordinate("chi", "rad", "lever angle"),
)


def build() -> Mechanism:
    a, b, c, d, m_a, m_b, m_c, x_Q, y_Q, l_L, m_L, k, l_0, x_S, y_S, T, g = (
        p.symbol for p in PARAMETERS)
    theta, phi, psi, s, chi = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a * cos(theta), a * sin(theta))
    B = (d + c * cos(psi), c * sin(psi))
    E = (x_Q + l_L * cos(chi), y_Q + l_L * sin(chi))
    return Mechanism(
        name="lever_on_rocker",
        title="a four-bar whose rocker pin drives a slotted lever",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(A[0] + b * cos(phi) - B[0], A[1] + b * sin(phi) - B[1],
                     B[0] - x_Q - s * cos(chi), B[1] - y_Q - s * sin(chi)),
        bodies=(
            Body("crank", m_a, (A[0] / 2, A[1] / 2), inertia=m_a * a**2 / 12, angle=theta),
            Body("coupler", m_b, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2),
                 inertia=m_b * b**2 / 12, angle=phi),
            Body("rocker", m_c, ((d + B[0]) / 2, B[1] / 2), inertia=m_c * c**2 / 12, angle=psi),
            Body("lever", m_L, ((x_Q + E[0]) / 2, (y_Q + E[1]) / 2), inertia=m_L * l_L**2 / 12,
                 angle=chi),
        ),
        springs=(Spring(k, l_0, distance(E, (x_S, y_S))),),
        dampers=(),
        forces=(),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B, "E": E},
        polar_pairs=(("s", "chi"),),
        assembly_modes=((d - A[0]) * (B[1] - A[1]) - (0 - A[1]) * (B[0] - A[0]),),
        requirements=(Requirement(sp.And(a > 0, b > 0, c > 0, d > 0, l_L > 0), "LENGTH",
                                  "lengths must be positive"),),
    )
