"""An offset slider-crank with its spring on the connecting rod, as data.

Crank O-A (R, m_1, angle theta), connecting rod A-B (l, m_2, angle psi), slider B (m_3) on
the line y = e. A spring k (free length l_0) runs from the rod's point D, a distance f from A,
to the anchor S = (x_S, y_S); a damper b acts on the slide, a torque T on the crank. Gravity
along -Y. Where |R sin(theta) - e| > l the mechanism cannot be assembled: with a short rod
(l < R + |e|) the crank cannot turn fully and the range holds two limit positions.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Spring, Torque,
                                     distance, parameter)

PARAMETERS = (
    parameter("R", "m", "crank length", "0.1"),
    parameter("l", "m", "connecting-rod length", "0.3"),
    parameter("e", "m", "offset of the slide", "0.02"),
    parameter("f", "m", "spring attachment D along the rod from A", "0.12"),
    parameter("m_1", "kg", "mass of the crank", "0.5"),
    parameter("m_2", "kg", "mass of the connecting rod", "1.2"),
    parameter("m_3", "kg", "mass of the slider", "2"),
    parameter("k", "N/m", "spring stiffness", "1500"),
    parameter("l_0", "m", "free length of the spring", "0.18"),
    parameter("x_S", "m", "abscissa of the anchor S", "0.1"),
    parameter("y_S", "m", "ordinate of the anchor S", "0.25"),
    parameter("b", "N s/m", "damping on the slide", "40"),
    parameter("T", "N m", "torque on the crank (counter-clockwise positive)", "1.5"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("psi", "rad", "connecting-rod angle"),
    Coordinate("x", "m", "slider position"),
)


def build() -> Mechanism:
    R, l, e, f, m_1, m_2, m_3, k, l_0, x_S, y_S, b, T, g = (p.symbol for p in PARAMETERS)
    theta, psi, x = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (R * cos(theta), R * sin(theta))
    B = (x, e)
    D = (A[0] + f * cos(psi), A[1] + f * sin(psi))
    return Mechanism(
        name="slider_crank_rod_spring",
        title="a slider-crank with its spring on the connecting rod",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(A[0] + l * cos(psi) - x, A[1] + l * sin(psi) - e),
        bodies=(
            Body("crank", m_1, (A[0] / 2, A[1] / 2), inertia=m_1 * R**2 / 12, angle=theta),
            Body("rod", m_2, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2), inertia=m_2 * l**2 / 12,
                 angle=psi),
            Body("slider", m_3, B),
        ),
        springs=(Spring(k, l_0, distance(D, (x_S, y_S))),),
        dampers=(Damper(b, x),),
        forces=(),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B, "D": D},
        assembly_modes=(x - A[0],),   # the slider to the right of the crank pin
    )
