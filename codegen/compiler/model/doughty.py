"""Doughty's two-slider mechanism (SPEC, Table 1 steps 1-2), as data.

Slider 1 (m_A) runs on the X axis, slider 2 (m_B) on the Y axis, and a uniform bar
(m_C, length L) joins them. A spring k with a parallel damper b runs from the fixed
point O' = (H, 0) to the point P of the bar at distance a from B; r and phi are its
length and direction. Gravity acts along -Y, a force F pushes slider 2 along +Y.
"""
import sympy as sp

from .mechanism import (parameter, Body, Coordinate, Damper, Mechanism, PointForce, Requirement,
                        Sketch, Spring)



PARAMETERS = (
    parameter("H", "m", "abscissa of the spring's fixed point O'", "0.18"),
    parameter("L", "m", "length of the bar", "0.9"),
    parameter("a", "m", "distance from B to the spring's attachment P", "0.135"),
    parameter("m_A", "kg", "mass of slider 1", "0.194"),
    parameter("m_B", "kg", "mass of slider 2", "0.143"),
    parameter("m_C", "kg", "mass of the bar", "9.124"),
    parameter("k", "N/m", "spring stiffness", "3500"),
    parameter("b", "N s/m", "damping coefficient", "875"),
    parameter("l_ND", "m", "free length of the spring", "0.15"),
    parameter("F", "N", "force on slider 2 along +Y", "110"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (
    Coordinate("p", "m", "position of slider 1 on X"),
    Coordinate("q", "m", "position of slider 2 on Y"),
    Coordinate("r", "m", "length of the spring and damper"),
    Coordinate("theta", "rad", "angle of the bar"),
    Coordinate("phi", "rad", "direction of the spring"),
)


def build() -> Mechanism:
    H, L, a, m_A, m_B, m_C, k, b, l_ND, F, g = (p.symbol for p in PARAMETERS)
    p, q, r, theta, phi = (c.function for c in COORDINATES)
    cos, sin = sp.cos, sp.sin
    bar_centre = (p - L / 2 * cos(theta), L / 2 * sin(theta))
    slider_2 = (sp.S.Zero, q)
    return Mechanism(
        name="doughty",
        title="Doughty's two-slider mechanism",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(  # (4)-(7): the two vector loops O'-P-B and O'-P-A
            a * cos(theta) - H + r * cos(phi),
            q - a * sin(theta) - r * sin(phi),
            p - H - (L - a) * cos(theta) + r * cos(phi),
            (L - a) * sin(theta) - r * sin(phi),
        ),
        bodies=(
            Body("slider 1", m_A, (p, sp.S.Zero)),
            Body("slider 2", m_B, slider_2),
            Body("bar", m_C, bar_centre, inertia=m_C * L**2 / 12, angle=theta),
        ),
        springs=(Spring(k, l_ND, r),),
        dampers=(Damper(b, r),),
        forces=(PointForce(slider_2, (sp.S.Zero, F)),),
        gravity=g,
        points={"A": (p, sp.S.Zero), "B": slider_2, "C": bar_centre},
        requirements=(
            Requirement(L > 0, "L_NOT_POSITIVE", "L must be positive"),
            Requirement(sp.And(a >= 0, a <= L), "A_OUT_OF_RANGE", "a must lie in [0, L]"),
            Requirement(l_ND >= 0, "L_ND_NEGATIVE", "l_ND must not be negative"),
            Requirement(sp.And(m_A >= 0, m_B >= 0, m_C >= 0), "MASS_NEGATIVE",
                        "masses m_A, m_B, m_C must not be negative"),
            Requirement(k >= 0, "K_NEGATIVE", "k must not be negative"),
            Requirement(b >= 0, "B_NEGATIVE", "b must not be negative"),
        ),
        sketch=Sketch(
            points={"O": (sp.S.Zero, sp.S.Zero), "O'": (H, sp.S.Zero),
                    "P": (H - r * cos(phi), r * sin(phi))},
            links=(("A", "B"),), sliders=(("A", sp.S.Zero), ("B", sp.pi / 2)),
            fixed=("O", "O'"), springs=(("O'", "P"),), angle=("A", sp.pi, sp.pi - theta)),
        singular_state="the spring length r is zero, so its direction is undefined",
        polar_pairs=(("r", "phi"),),
        equations={
            "position_constraints": "(4)-(7)",
            "velocity_constraints": "(8)-(11)",
            "constraint_jacobian": "(25)",
            "acceleration_constraints": "Table 1 step 5 (d/dt of (8)-(11))",
            "point_kinematics": "(12)-(14)",
            "energies": "(16)-(22)",
            "lagrange_terms": "(15), (23)-(29)",
            "dependent_state": "(30)-(35)",
            "reduced_coefficients": "(36)-(41)",
            "angular_acceleration": "(36)",
            "equilibrium_residual": "(42)-(43)",
            "equilibrium_branches": "(43), squared into (45)",
            "sigma": "(44)-(45)",
            "linearisation": "(46)-(53)",
            "vibration": "(54)-(55)",
        },
    )
