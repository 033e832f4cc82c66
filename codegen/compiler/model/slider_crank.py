"""An offset slider-crank with a return spring anchored off the slide, as data.

Crank O-A (length R, mass m_1, angle theta) turns about the origin; the connecting rod A-B
(length l, mass m_2, angle psi) drives the slider B (mass m_3) along the line y = e. A spring
k of free length l_0 runs from the fixed point S = (x_S, y_S) to B: its length is a second
square root, holding the first (the rod's) inside it. A damper b acts on the slide, a force F
on the slider along +X, a torque T on the crank. Gravity along -Y.
"""
import sympy as sp

from .mechanism import (parameter, Body, Coordinate, Damper, Mechanism, PointForce, Requirement,
                        Sketch, Spring, Torque, distance)



PARAMETERS = (
    parameter("R", "m", "crank length", "0.1"),
    parameter("l", "m", "connecting-rod length", "0.3"),
    parameter("e", "m", "offset of the slide (the slider moves on y = e)", "0.02"),
    parameter("m_1", "kg", "mass of the crank", "0.5"),
    parameter("m_2", "kg", "mass of the connecting rod", "1.2"),
    parameter("m_3", "kg", "mass of the slider", "2.0"),
    parameter("k", "N/m", "spring stiffness", "2000"),
    parameter("l_0", "m", "free length of the spring", "0.25"),
    parameter("x_S", "m", "abscissa of the spring's fixed point S", "0.45"),
    parameter("y_S", "m", "ordinate of the spring's fixed point S", "0.2"),
    parameter("b", "N s/m", "damping coefficient on the slide", "40"),
    parameter("F", "N", "force on the slider along +X", "-30"),
    parameter("T", "N m", "torque on the crank (counter-clockwise positive)", "0"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("psi", "rad", "connecting-rod angle"),
    Coordinate("x", "m", "slider position along the slide"),
)


def build() -> Mechanism:
    R, l, e, m_1, m_2, m_3, k, l_0, x_S, y_S, b, F, T, g = (p.symbol for p in PARAMETERS)
    theta, psi, x = (c.function for c in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (R * cos(theta), R * sin(theta))
    B = (x, e)
    return Mechanism(
        name="slider_crank",
        title="an offset slider-crank with a return spring anchored off the slide",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(  # the loop O-A-B closes on the slide
            A[0] + l * cos(psi) - x,
            A[1] + l * sin(psi) - e,
        ),
        bodies=(
            Body("crank", m_1, (A[0] / 2, A[1] / 2), inertia=m_1 * R**2 / 12, angle=theta),
            Body("rod", m_2, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2), inertia=m_2 * l**2 / 12,
                 angle=psi),
            Body("slider", m_3, B),
        ),
        springs=(Spring(k, l_0, distance(B, (x_S, y_S))),),
        dampers=(Damper(b, x),),
        forces=(PointForce(B, (F, sp.S.Zero)),),
        torques=(Torque(T, theta),),
        gravity=g,
        points={"A": A, "B": B},
        # The slider lies to the right of the crank pin: x_B = R cos(theta) + sqrt(...).
        assembly_modes=(x - A[0],),
        requirements=(
            Requirement(sp.And(R > 0, l > 0), "LENGTH_NOT_POSITIVE", "R and l must be positive"),
            Requirement(l_0 >= 0, "L_0_NEGATIVE", "l_0 must not be negative"),
            Requirement(sp.And(m_1 >= 0, m_2 >= 0, m_3 >= 0), "MASS_NEGATIVE",
                        "masses m_1, m_2, m_3 must not be negative"),
            Requirement(k >= 0, "K_NEGATIVE", "k must not be negative"),
            Requirement(b >= 0, "B_NEGATIVE", "b must not be negative"),
        ),
        sketch=Sketch(
            points={"O": (sp.S.Zero, sp.S.Zero), "S": (x_S, y_S)},
            links=(("O", "A", "B"),), sliders=(("B", sp.S.Zero),), fixed=("O", "S"),
            springs=(("S", "B"),), angle=("O", sp.S.Zero, theta)),
        singular_state="the connecting rod is perpendicular to the slide (a limit position) "
                       "or the spring length is zero",
    )
