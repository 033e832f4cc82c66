"""An eight-bar: the Stephenson-III six-bar whose output rocker drives a slider through a
third dyad (RRP), as a user writes it. Three nested assembly modes, eight in all.

Loop 1: the crank O2-A (a_2, angle theta) about O2 = (0, 0), the coupler A-B (a_3, phi_3),
the rocker O4-B (a_4, phi_4) about O4 = (d, 0); P lies on the line A-B, a_3p from A.
Loop 2: the link P-E (a_5, phi_5) and the output rocker O6-E (a_6, phi_6) about
O6 = (x_6, y_6); F lies on the rocker's line, a_6f from O6. Loop 3: the rod F-G (a_7,
phi_7) and the slider G = (s, y_8) on a horizontal slide. Uniform bars; the slider a point
mass; a spring k (free length l_0) from E to the anchor S = (x_S, y_S) and a spring k_8
(free length l_8) from G to the anchor W = (x_W, y_W); a torque T on the crank, a force F_8
along the slide on G; gravity along -Y. Modes: B left of the line from A to O4, E left of
the line from P to O6, G ahead of F along the slide.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, PointForce, Requirement,
                                     Spring, Torque, distance, parameter)

PARAMETERS = (
    parameter("d", "m", "distance O2-O4", "0.4"),
    parameter("a_2", "m", "crank", "0.12"),
    parameter("a_3", "m", "coupler A-B", "0.35"),
    parameter("a_3p", "m", "coupler point P from A along A-B", "0.5"),
    parameter("a_4", "m", "rocker", "0.3"),
    parameter("a_5", "m", "link P-E", "0.35"),
    parameter("a_6", "m", "output rocker O6-E", "0.25"),
    parameter("a_6f", "m", "output rocker point F from O6", "0.35"),
    parameter("a_7", "m", "rod F-G", "0.5"),
    parameter("x_6", "m", "abscissa of O6", "0.5"),
    parameter("y_6", "m", "ordinate of O6", "0.55"),
    parameter("y_8", "m", "ordinate of the slide", "0.6"),
    parameter("m_2", "kg", "crank mass", "0.3"),
    parameter("m_3", "kg", "coupler mass", "0.9"),
    parameter("m_4", "kg", "rocker mass", "0.6"),
    parameter("m_5", "kg", "link mass", "0.5"),
    parameter("m_6", "kg", "output rocker mass", "0.4"),
    parameter("m_7", "kg", "rod mass", "0.3"),
    parameter("m_8", "kg", "slider mass", "1.2"),
    parameter("k", "N/m", "spring E-S stiffness", "500"),
    parameter("l_0", "m", "spring E-S free length", "0.1"),
    parameter("x_S", "m", "anchor S abscissa", "0.7"),
    parameter("y_S", "m", "anchor S ordinate", "0.3"),
    parameter("k_8", "N/m", "spring G-W stiffness", "300"),
    parameter("l_8", "m", "spring G-W free length", "0.2"),
    parameter("x_W", "m", "anchor W abscissa", "1.4"),
    parameter("y_W", "m", "anchor W ordinate", "0.7"),
    parameter("T", "N m", "torque on the crank", "0.4"),
    parameter("F_8", "N", "force on the slider along the slide", "-2"),
    parameter("g", "m/s^2", "gravity", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("phi_3", "rad", "coupler angle"),
    Coordinate("phi_4", "rad", "rocker angle"),
    Coordinate("phi_5", "rad", "link angle"),
    Coordinate("phi_6", "rad", "output rocker angle"),
    Coordinate("phi_7", "rad", "rod angle"),
    Coordinate("s", "m", "slider position"),
)


def build():
    (d, a_2, a_3, a_3p, a_4, a_5, a_6, a_6f, a_7, x_6, y_6, y_8, m_2, m_3, m_4, m_5, m_6, m_7,
     m_8, k, l_0, x_S, y_S, k_8, l_8, x_W, y_W, T, F_8, g) = (p.symbol for p in PARAMETERS)
    theta, phi_3, phi_4, phi_5, phi_6, phi_7, s = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a_2 * cos(theta), a_2 * sin(theta))
    B = (d + a_4 * cos(phi_4), a_4 * sin(phi_4))
    P = (A[0] + a_3p * cos(phi_3), A[1] + a_3p * sin(phi_3))
    E = (x_6 + a_6 * cos(phi_6), y_6 + a_6 * sin(phi_6))
    F = (x_6 + a_6f * cos(phi_6), y_6 + a_6f * sin(phi_6))
    G = (s, y_8)

    def bar(name, m, p, q, length, angle):
        return Body(name, m, ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2), inertia=m * length**2 / 12,
                    angle=angle)

    return Mechanism(
        name="eight_bar", title="an eight-bar (a Stephenson six-bar driving a slider)",
        parameters=PARAMETERS, coordinates=COORDINATES, independent="theta",
        constraints=(A[0] + a_3 * cos(phi_3) - B[0], A[1] + a_3 * sin(phi_3) - B[1],
                     P[0] + a_5 * cos(phi_5) - E[0], P[1] + a_5 * sin(phi_5) - E[1],
                     F[0] + a_7 * cos(phi_7) - G[0], F[1] + a_7 * sin(phi_7) - G[1]),
        bodies=(bar("crank", m_2, (0, 0), A, a_2, theta), bar("coupler", m_3, A, B, a_3, phi_3),
                bar("rocker", m_4, (d, 0), B, a_4, phi_4), bar("link", m_5, P, E, a_5, phi_5),
                bar("output", m_6, (x_6, y_6), F, a_6f, phi_6),
                bar("rod", m_7, F, G, a_7, phi_7), Body("slider", m_8, G)),
        springs=(Spring(k, l_0, distance(E, (x_S, y_S))),
                 Spring(k_8, l_8, distance(G, (x_W, y_W)))),
        dampers=(), forces=(PointForce(G, (F_8, 0)),), torques=(Torque(T, theta),), gravity=g,
        points={"A": A, "B": B, "P": P, "E": E, "F": F, "G": G},
        assembly_modes=((d - A[0]) * (B[1] - A[1]) - (0 - A[1]) * (B[0] - A[0]),
                        (x_6 - P[0]) * (E[1] - P[1]) - (y_6 - P[1]) * (E[0] - P[0]),
                        G[0] - F[0]),
        requirements=(Requirement(sp.And(d > 0, a_2 > 0, a_3 > 0, a_4 > 0, a_3p > 0, a_5 > 0,
                                         a_6 > 0, a_6f > 0, a_7 > 0),
                                  "LENGTH", "lengths must be positive"),),
    )
