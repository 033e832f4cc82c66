"""A four-bar linkage with a spring from a coupler point to the ground, as data.

Ground pivots O2 = (0, 0) and O4 = (d, 0); crank O2-A (a_2, m_2, angle theta), coupler A-B
(a_3, m_3, angle phi_3), rocker O4-B (a_4, m_4, angle phi_4), uniform bars. The coupler point
C lies u_C along A-B and v_C to its left; a spring k (free length l_0) and a parallel damper b run
from C to the anchor S = (x_S, y_S). A torque T acts on the crank; gravity along -Y.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Requirement, Spring,
                                     Torque, distance, parameter)

PARAMETERS = (
    parameter("d", "m", "distance between the ground pivots", "0.4"),
    parameter("a_2", "m", "crank length", "0.12"),
    parameter("a_3", "m", "coupler length", "0.35"),
    parameter("a_4", "m", "rocker length", "0.3"),
    parameter("u_C", "m", "coupler point along A-B", "0.2"),
    parameter("v_C", "m", "coupler point to the left of A-B", "0.08"),
    parameter("m_2", "kg", "mass of the crank", "0.4"),
    parameter("m_3", "kg", "mass of the coupler", "1"),
    parameter("m_4", "kg", "mass of the rocker", "0.8"),
    parameter("k", "N/m", "spring stiffness", "900"),
    parameter("l_0", "m", "free length of the spring", "0.15"),
    parameter("x_S", "m", "abscissa of the anchor S", "0.05"),
    parameter("y_S", "m", "ordinate of the anchor S", "0.5"),
    parameter("b", "N s/m", "damping along the spring", "20"),
    parameter("T", "N m", "torque on the crank (counter-clockwise positive)", "0.5"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("phi_3", "rad", "coupler angle"),
    Coordinate("phi_4", "rad", "rocker angle"),
)


def build() -> Mechanism:
    (d, a_2, a_3, a_4, u_C, v_C, m_2, m_3, m_4, k, l_0, x_S, y_S, b, T,
     g) = (p.symbol for p in PARAMETERS)
    theta, phi_3, phi_4 = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a_2 * cos(theta), a_2 * sin(theta))
    B = (d + a_4 * cos(phi_4), a_4 * sin(phi_4))
    C = (A[0] + u_C * cos(phi_3) - v_C * sin(phi_3), A[1] + u_C * sin(phi_3) + v_C * cos(phi_3))
    spring = distance(C, (x_S, y_S))
    return Mechanism(
        name="four_bar_coupler_spring",
        title="a four-bar with a spring from a coupler point",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(A[0] + a_3 * cos(phi_3) - B[0], A[1] + a_3 * sin(phi_3) - B[1]),
        bodies=(
            Body("crank", m_2, (A[0] / 2, A[1] / 2), inertia=m_2 * a_2**2 / 12, angle=theta),
            Body("coupler", m_3, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2),
                 inertia=m_3 * a_3**2 / 12, angle=phi_3),
            Body("rocker", m_4, ((d + B[0]) / 2, B[1] / 2), inertia=m_4 * a_4**2 / 12,
                 angle=phi_4),
        ),
        springs=(Spring(k, l_0, spring),),
        dampers=(Damper(b, spring),),
        forces=(),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B, "C": C},
        # B lies to the left of the directed line from A to O4.
        assembly_modes=((d - A[0]) * (B[1] - A[1]) - (0 - A[1]) * (B[0] - A[0]),),
        # the coupler's length divides the coupler point's position: its sign is declared
        requirements=(Requirement(sp.And(d > 0, a_2 > 0, a_3 > 0, a_4 > 0), "LENGTH_NOT_POSITIVE",
                                  "d, a_2, a_3, a_4 must be positive"),),
    )
