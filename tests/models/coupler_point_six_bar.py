"""A six-bar whose coupler point drives a second dyad, as a user writes it (issue 48: the
Watt-II six-bar "crank, coupler, rocker, a second dyad on the coupler").

Loop 1: the crank O2-A (a_2, angle theta) about O2 = (0, 0), the coupler A-B (a_3, phi_3),
the rocker O4-B (a_4, phi_4) about O4 = (d, 0). The coupler carries the point C at distance c
from A, at the angle gamma from A-B (off the bar's line). Loop 2: the link C-D (a_5, phi_5)
and the output rocker O6-D (a_6, phi_6) about O6 = (x_6, y_6). Uniform bars; a spring k (free
length l_0) from D to the anchor S = (x_S, y_S); a torque T on the crank; gravity along -Y.
Each dyad has two assembly modes: B left of the line from A to O4, and D left of the line
from C to O6.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, Requirement, Spring, Torque,
                                     distance, parameter)

PARAMETERS = (
    parameter("d", "m", "distance O2-O4", "0.4"),
    parameter("a_2", "m", "crank", "0.12"),
    parameter("a_3", "m", "coupler", "0.35"),
    parameter("a_4", "m", "rocker", "0.3"),
    parameter("c", "m", "coupler point's distance from A", "0.25"),
    parameter("gamma", "rad", "coupler point's angle from A-B", "0.6"),
    parameter("a_5", "m", "second link C-D", "0.4"),
    parameter("a_6", "m", "output rocker O6-D", "0.3"),
    parameter("x_6", "m", "abscissa of O6", "0.6"),
    parameter("y_6", "m", "ordinate of O6", "0.45"),
    parameter("m_2", "kg", "crank mass", "0.3"),
    parameter("m_3", "kg", "coupler mass", "0.8"),
    parameter("m_4", "kg", "rocker mass", "0.6"),
    parameter("m_5", "kg", "second link mass", "0.7"),
    parameter("m_6", "kg", "output rocker mass", "0.5"),
    parameter("k", "N/m", "spring stiffness", "400"),
    parameter("l_0", "m", "spring free length", "0.15"),
    parameter("x_S", "m", "anchor abscissa", "0.9"),
    parameter("y_S", "m", "anchor ordinate", "0.2"),
    parameter("T", "N m", "torque on the crank", "0.5"),
    parameter("g", "m/s^2", "gravity", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("phi_3", "rad", "coupler angle"),
    Coordinate("phi_4", "rad", "rocker angle"),
    Coordinate("phi_5", "rad", "second link angle"),
    Coordinate("phi_6", "rad", "output rocker angle"),
)


def build():
    (d, a_2, a_3, a_4, c, gamma, a_5, a_6, x_6, y_6, m_2, m_3, m_4, m_5, m_6, k, l_0, x_S,
     y_S, T, g) = (p.symbol for p in PARAMETERS)
    theta, phi_3, phi_4, phi_5, phi_6 = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a_2 * cos(theta), a_2 * sin(theta))
    B = (d + a_4 * cos(phi_4), a_4 * sin(phi_4))
    C = (A[0] + c * cos(phi_3 + gamma), A[1] + c * sin(phi_3 + gamma))
    D = (x_6 + a_6 * cos(phi_6), y_6 + a_6 * sin(phi_6))

    def bar(name, m, p, q, length, angle):
        return Body(name, m, ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2), inertia=m * length**2 / 12,
                    angle=angle)

    return Mechanism(
        name="coupler_point_six_bar", title="a six-bar whose coupler point drives a second dyad",
        parameters=PARAMETERS, coordinates=COORDINATES, independent="theta",
        constraints=(A[0] + a_3 * cos(phi_3) - B[0], A[1] + a_3 * sin(phi_3) - B[1],
                     C[0] + a_5 * cos(phi_5) - D[0], C[1] + a_5 * sin(phi_5) - D[1]),
        bodies=(bar("crank", m_2, (0, 0), A, a_2, theta), bar("coupler", m_3, A, B, a_3, phi_3),
                bar("rocker", m_4, (d, 0), B, a_4, phi_4), bar("link", m_5, C, D, a_5, phi_5),
                bar("output", m_6, (x_6, y_6), D, a_6, phi_6)),
        springs=(Spring(k, l_0, distance(D, (x_S, y_S))),),
        dampers=(), forces=(), torques=(Torque(T, theta),), gravity=g,
        points={"A": A, "B": B, "C": C, "D": D},
        assembly_modes=((d - A[0]) * (B[1] - A[1]) - (0 - A[1]) * (B[0] - A[0]),
                        (x_6 - C[0]) * (D[1] - C[1]) - (y_6 - C[1]) * (D[0] - C[0])),
        requirements=(Requirement(sp.And(d > 0, a_2 > 0, a_3 > 0, a_4 > 0, c > 0, a_5 > 0,
                                         a_6 > 0), "LENGTH", "lengths must be positive"),),
    )
