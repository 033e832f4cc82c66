"""A four-bar linkage with a spring (and parallel damper) on the coupler-rocker joint, as data.

Ground pivots O2 = (0, 0) and O4 = (d, 0). The crank O2-A (length a_2, mass m_2, angle theta),
the coupler A-B (a_3, m_3, angle phi_3) and the rocker O4-B (a_4, m_4, angle phi_4) are uniform
bars. A spring k of free length l_0 with a parallel damper b runs from the fixed point
S = (x_S, y_S) to B. A torque T acts on the crank; gravity along -Y.
"""
import sympy as sp

from .mechanism import (parameter, Body, Coordinate, Damper, Mechanism, Requirement, Sketch,
                        Spring, Torque, distance)



PARAMETERS = (
    parameter("d", "m", "distance between the ground pivots O2 and O4", "0.4"),
    parameter("a_2", "m", "crank length", "0.12"),
    parameter("a_3", "m", "coupler length", "0.35"),
    parameter("a_4", "m", "rocker length", "0.3"),
    parameter("m_2", "kg", "mass of the crank", "0.4"),
    parameter("m_3", "kg", "mass of the coupler", "1.0"),
    parameter("m_4", "kg", "mass of the rocker", "0.8"),
    parameter("k", "N/m", "spring stiffness", "1500"),
    parameter("l_0", "m", "free length of the spring", "0.2"),
    parameter("x_S", "m", "abscissa of the spring's fixed point S", "0.1"),
    parameter("y_S", "m", "ordinate of the spring's fixed point S", "0.45"),
    parameter("b", "N s/m", "damping coefficient of the spring's damper", "30"),
    parameter("T", "N m", "torque on the crank (counter-clockwise positive)", "0"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("phi_3", "rad", "coupler angle"),
    Coordinate("phi_4", "rad", "rocker angle"),
)


def build() -> Mechanism:
    d, a_2, a_3, a_4, m_2, m_3, m_4, k, l_0, x_S, y_S, b, T, g = (p.symbol for p in PARAMETERS)
    theta, phi_3, phi_4 = (c.function for c in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a_2 * cos(theta), a_2 * sin(theta))
    B = (d + a_4 * cos(phi_4), a_4 * sin(phi_4))
    spring = distance(B, (x_S, y_S))
    return Mechanism(
        name="four_bar",
        title="a four-bar linkage with a spring on the coupler-rocker joint",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(  # the loop O2-A-B-O4 closes
            A[0] + a_3 * cos(phi_3) - B[0],
            A[1] + a_3 * sin(phi_3) - B[1],
        ),
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
        points={"A": A, "B": B},
        # B lies to the left of the directed line from A to O4: (O4 - A) x (B - A) > 0.
        assembly_modes=((d - A[0]) * (B[1] - A[1]) - (0 - A[1]) * (B[0] - A[0]),),
        requirements=(
            Requirement(sp.And(d > 0, a_2 > 0, a_3 > 0, a_4 > 0), "LENGTH_NOT_POSITIVE",
                        "d, a_2, a_3, a_4 must be positive"),
            Requirement(l_0 >= 0, "L_0_NEGATIVE", "l_0 must not be negative"),
            Requirement(sp.And(m_2 >= 0, m_3 >= 0, m_4 >= 0), "MASS_NEGATIVE",
                        "masses m_2, m_3, m_4 must not be negative"),
            Requirement(k >= 0, "K_NEGATIVE", "k must not be negative"),
            Requirement(b >= 0, "B_NEGATIVE", "b must not be negative"),
        ),
        sketch=Sketch(
            points={"O2": (sp.S.Zero, sp.S.Zero), "O4": (d, sp.S.Zero), "S": (x_S, y_S)},
            links=(("O2", "A", "B", "O4"),), fixed=("O2", "O4", "S"), springs=(("S", "B"),),
            angle=("O2", sp.S.Zero, theta)),
        singular_state="the coupler and rocker are aligned (a limit position) or the spring "
                       "length is zero",
    )
