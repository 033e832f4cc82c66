"""A bar on a torsional spring, as data: its statics hold theta beside sin and cos.

A uniform bar O-P (length l, mass m) pivots at the origin at angle theta, with a point mass
m_t at its tip P. A torsional spring k_t (free angle theta_0) with a parallel torsional
damper c acts at the pivot; a constant horizontal force F_x acts at the tip. The spring
winds, so theta ranges over (theta_0 - pi, theta_0 + pi]. There are no constraints.
"""
import sympy as sp

from .mechanism import (parameter, Body, Coordinate, Damper, Mechanism, PointForce, Requirement,
                        Sketch, Spring)



PARAMETERS = (
    parameter("l", "m", "length of the bar", "1.0"),
    parameter("m", "kg", "mass of the bar", "1.0"),
    parameter("m_t", "kg", "point mass at the tip", "2.0"),
    parameter("k_t", "N m/rad", "torsional spring stiffness", "20"),
    parameter("theta_0", "rad", "free angle of the torsional spring", "1.5707963267948966"),
    parameter("c", "N m s/rad", "torsional damping coefficient", "0.5"),
    parameter("F_x", "N", "horizontal force at the tip along +X", "0"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (Coordinate("theta", "rad", "angle of the bar"),)


def build() -> Mechanism:
    l, m, m_t, k_t, theta_0, c, F_x, g = (p.symbol for p in PARAMETERS)
    (theta,) = (c_.function for c_ in COORDINATES)
    tip = (l * sp.cos(theta), l * sp.sin(theta))
    return Mechanism(
        name="torsion_pendulum",
        title="a bar on a torsional spring",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(),
        bodies=(
            Body("bar", m, (tip[0] / 2, tip[1] / 2), inertia=m * l**2 / 12, angle=theta),
            Body("tip mass", m_t, tip),
        ),
        springs=(Spring(k_t, theta_0, theta),),
        dampers=(Damper(c, theta),),
        forces=(PointForce(tip, (F_x, sp.S.Zero)),),
        gravity=g,
        points={"P": tip},
        range_centre=theta_0,
        sketch=Sketch(points={"O": (sp.S.Zero, sp.S.Zero)}, links=(("O", "P"),), fixed=("O",),
                      angle=("O", sp.S.Zero, theta)),
        periodic=False,
        requirements=(
            Requirement(l > 0, "L_NOT_POSITIVE", "l must be positive"),
            Requirement(sp.And(m >= 0, m_t >= 0), "MASS_NEGATIVE",
                        "masses m, m_t must not be negative"),
            Requirement(k_t >= 0, "K_T_NEGATIVE", "k_t must not be negative"),
            Requirement(c >= 0, "C_NEGATIVE", "c must not be negative"),
        ),
    )
