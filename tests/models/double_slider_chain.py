"""A slider-crank whose slider drives a second slider through a link: a chain of two RRP
dyads, the second's assembly depending on the first's mode, as a user writes it.

Crank O-A (R, m_1, angle theta) about the origin; rod A-B (l_1, m_2, angle psi_1) to the
slider B (m_3) on the line y = 0; link B-C (l_2, m_4, angle psi_2) to the slider C (m_5) on
the vertical line x = d. A spring k (free length l_0) from C to the anchor (x_S, y_S); a
torque T on the crank. Gravity along -Y. Declared: B to the right of the crank pin, C above
the first slide. With B on its other side, C is out of the link's reach for every crank
angle; with the link short, C is out of reach near theta = 180 deg on the declared side too.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Mechanism, Spring, Torque, distance,
                                     parameter)

PARAMETERS = (
    parameter("R", "m", "crank length", "0.1"),
    parameter("l_1", "m", "rod length", "0.3"),
    parameter("l_2", "m", "link length", "0.25"),
    parameter("d", "m", "abscissa of the second slide", "0.5"),
    parameter("m_1", "kg", "crank mass", "0.5"),
    parameter("m_2", "kg", "rod mass", "1"),
    parameter("m_3", "kg", "first slider's mass", "1.5"),
    parameter("m_4", "kg", "link mass", "0.6"),
    parameter("m_5", "kg", "second slider's mass", "1"),
    parameter("k", "N/m", "spring stiffness", "400"),
    parameter("l_0", "m", "spring free length", "0.2"),
    parameter("x_S", "m", "spring anchor abscissa", "0.7"),
    parameter("y_S", "m", "spring anchor ordinate", "0.4"),
    parameter("T", "N m", "torque on the crank", "0.5"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("psi_1", "rad", "rod angle"),
    Coordinate("x", "m", "first slider's position"),
    Coordinate("psi_2", "rad", "link angle"),
    Coordinate("y", "m", "second slider's position"),
)


def build() -> Mechanism:
    R, l_1, l_2, d, m_1, m_2, m_3, m_4, m_5, k, l_0, x_S, y_S, T, g = (
        p.symbol for p in PARAMETERS)
    theta, psi_1, x, psi_2, y = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (R * cos(theta), R * sin(theta))
    B = (x, sp.S.Zero)
    C = (d, y)
    return Mechanism(
        name="double_slider_chain",
        title="a slider-crank driving a second slider through a link",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(A[0] + l_1 * cos(psi_1) - x, A[1] + l_1 * sin(psi_1),
                     x + l_2 * cos(psi_2) - d, l_2 * sin(psi_2) - y),
        bodies=(
            Body("crank", m_1, (A[0] / 2, A[1] / 2), inertia=m_1 * R**2 / 12, angle=theta),
            Body("rod", m_2, ((A[0] + B[0]) / 2, A[1] / 2), inertia=m_2 * l_1**2 / 12,
                 angle=psi_1),
            Body("slider", m_3, B),
            Body("link", m_4, ((x + d) / 2, y / 2), inertia=m_4 * l_2**2 / 12, angle=psi_2),
            Body("second slider", m_5, C),
        ),
        springs=(Spring(k, l_0, distance(C, (x_S, y_S))),),
        dampers=(),
        forces=(),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B, "C": C},
        assembly_modes=(x - A[0], y),
    )
