"""A slider-crank whose slide is inclined at a signed angle alpha, as data (issue 30: an
assembly mode that holds for every parameter set).

Crank O-A (R, m_1, angle theta) pivoted at the origin; connecting rod A-B (l, m_2, angle psi);
slider B (m_3) at a distance s along a slide through O inclined at alpha to X. A spring k
(free length l_0) holds the slider to the anchor S = (x_S, y_S); a damper b acts on the
slide, a torque T on the crank; gravity along -Y. The declared assembly mode is "the slider
below the crank pin": which sign of the rod's square root that is depends on the sign of
alpha, so the library must decide it for each parameter set (alpha = 0: a level slide, where
"below" tells the two modes apart nowhere).
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Spring, Torque,
                                     distance, parameter)

PARAMETERS = (
    parameter("R", "m", "crank length", "0.1"),
    parameter("l", "m", "connecting-rod length", "0.3"),
    parameter("alpha", "rad", "inclination of the slide (counter-clockwise from X)", "1.0"),
    parameter("m_1", "kg", "mass of the crank", "0.5"),
    parameter("m_2", "kg", "mass of the connecting rod", "1.2"),
    parameter("m_3", "kg", "mass of the slider", "2"),
    parameter("k", "N/m", "spring stiffness", "800"),
    parameter("l_0", "m", "free length of the spring", "0.1"),
    parameter("x_S", "m", "abscissa of the anchor S", "0.05"),
    parameter("y_S", "m", "ordinate of the anchor S", "-0.2"),
    parameter("b", "N s/m", "damping on the slide", "30"),
    parameter("T", "N m", "torque on the crank (counter-clockwise positive)", "0.5"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("psi", "rad", "connecting-rod angle"),
    Coordinate("s", "m", "slider position along the slide"),
)


def build() -> Mechanism:
    R, l, alpha, m_1, m_2, m_3, k, l_0, x_S, y_S, b, T, g = (p.symbol for p in PARAMETERS)
    theta, psi, s = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (R * cos(theta), R * sin(theta))
    B = (s * cos(alpha), s * sin(alpha))
    return Mechanism(
        name="inclined_slider_crank",
        title="a slider-crank on an inclined slide",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(A[0] + l * cos(psi) - B[0], A[1] + l * sin(psi) - B[1]),
        bodies=(
            Body("crank", m_1, (A[0] / 2, A[1] / 2), inertia=m_1 * R**2 / 12, angle=theta),
            Body("rod", m_2, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2), inertia=m_2 * l**2 / 12,
                 angle=psi),
            Body("slider", m_3, B),
        ),
        springs=(Spring(k, l_0, distance(B, (x_S, y_S))),),
        dampers=(Damper(b, s),),
        forces=(),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B},
        assembly_modes=(A[1] - B[1],),   # the slider below the crank pin
    )
