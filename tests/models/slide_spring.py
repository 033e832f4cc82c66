"""A slider-crank whose return spring lies along its slide, as data.

Crank O-A (R, m_1, angle theta), connecting rod A-B (l, m_2, angle psi), slider B (m_3) on
the line y = e. The spring k (free length l_0) runs from B to the anchor S = (x_S, e) on the
slide's own line, so its length is |x - x_S|: one axis, the other difference exactly zero. A
damper b between the same two points, a force F on the slider along +X, a torque T on the
crank. Gravity along -Y.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, PointForce, Spring,
                                     Torque, distance, parameter)

PARAMETERS = (
    parameter("R", "m", "crank length", "0.1"),
    parameter("l", "m", "connecting-rod length", "0.3"),
    parameter("e", "m", "offset of the slide", "0.02"),
    parameter("m_1", "kg", "mass of the crank", "0.5"),
    parameter("m_2", "kg", "mass of the connecting rod", "1.2"),
    parameter("m_3", "kg", "mass of the slider", "2"),
    parameter("k", "N/m", "spring stiffness", "800"),
    parameter("l_0", "m", "free length of the spring", "0.25"),
    parameter("x_S", "m", "the anchor S on the slide's line, its abscissa", "0.6"),
    parameter("b", "N s/m", "damping between the slider and S", "30"),
    parameter("F", "N", "force on the slider along +X", "-20"),
    parameter("T", "N m", "torque on the crank (counter-clockwise positive)", "1"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("psi", "rad", "connecting-rod angle"),
    Coordinate("x", "m", "slider position"),
)


def build() -> Mechanism:
    R, l, e, m_1, m_2, m_3, k, l_0, x_S, b, F, T, g = (p.symbol for p in PARAMETERS)
    theta, psi, x = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (R * cos(theta), R * sin(theta))
    B = (x, e)
    S = (x_S, e)
    return Mechanism(
        name="slide_spring",
        title="a slider-crank with its spring along the slide",
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
        springs=(Spring(k, l_0, distance(B, S)),),
        dampers=(Damper(b, distance(B, S)),),
        forces=(PointForce(B, (F, sp.S.Zero)),),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B},
        assembly_modes=(x - A[0],),   # the slider to the right of the crank pin
    )
