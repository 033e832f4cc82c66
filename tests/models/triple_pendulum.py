"""A triple pendulum on torsional springs (3 DOF): a user's model file with several
independent coordinates.

Three uniform bars (l_i, m_i) hang in a chain from a pivot at the origin, at absolute angles
theta_i from +X. A torsional spring k_1 (free angle alpha_1) with a damper c_1 acts at the
pivot on theta_1; k_2, c_2 at the first joint on delta_2 = theta_2 - theta_1 (free alpha_2);
k_3, c_3 at the second on delta_3 = theta_3 - theta_2 (free alpha_3). Gravity along -Y. The
independent coordinates are theta_1, delta_2 and delta_3; the springs wind, so each ranges
over a turn about its free angle.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Requirement, Spring,
                                     parameter)

PARAMETERS = (
    parameter("l_1", "m", "length of bar 1", "0.5"),
    parameter("l_2", "m", "length of bar 2", "0.4"),
    parameter("l_3", "m", "length of bar 3", "0.3"),
    parameter("m_1", "kg", "mass of bar 1", "1.0"),
    parameter("m_2", "kg", "mass of bar 2", "0.8"),
    parameter("m_3", "kg", "mass of bar 3", "0.6"),
    parameter("k_1", "N m/rad", "spring at the pivot", "40"),
    parameter("k_2", "N m/rad", "spring at the first joint", "20"),
    parameter("k_3", "N m/rad", "spring at the second joint", "10"),
    parameter("alpha_1", "rad", "free angle of the spring at the pivot", "1.5707963267948966"),
    parameter("alpha_2", "rad", "free relative angle at the first joint", "0"),
    parameter("alpha_3", "rad", "free relative angle at the second joint", "0"),
    parameter("c_1", "N m s/rad", "damping at the pivot", "0.3"),
    parameter("c_2", "N m s/rad", "damping at the first joint", "0.2"),
    parameter("c_3", "N m s/rad", "damping at the second joint", "0.1"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (
    Coordinate("theta_1", "rad", "angle of bar 1 from +X"),
    Coordinate("delta_2", "rad", "angle of bar 2 relative to bar 1"),
    Coordinate("delta_3", "rad", "angle of bar 3 relative to bar 2"),
    Coordinate("theta_2", "rad", "angle of bar 2 from +X"),
    Coordinate("theta_3", "rad", "angle of bar 3 from +X"),
)


def build() -> Mechanism:
    (l_1, l_2, l_3, m_1, m_2, m_3, k_1, k_2, k_3, alpha_1, alpha_2, alpha_3,
     c_1, c_2, c_3, g) = (p.symbol for p in PARAMETERS)
    theta_1, delta_2, delta_3, theta_2, theta_3 = (c.function for c in COORDINATES)
    bars, joint = [], (sp.S.Zero, sp.S.Zero)
    for length, mass, angle in ((l_1, m_1, theta_1), (l_2, m_2, theta_2), (l_3, m_3, theta_3)):
        end = (joint[0] + length * sp.cos(angle), joint[1] + length * sp.sin(angle))
        bars.append(Body(f"bar {len(bars) + 1}", mass, ((joint[0] + end[0]) / 2,
                                                          (joint[1] + end[1]) / 2),
                         inertia=mass * length**2 / 12, angle=angle))
        joint = end
    return Mechanism(
        name="triple_pendulum",
        title="a triple pendulum on torsional springs",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent=("theta_1", "delta_2", "delta_3"),
        constraints=(theta_2 - theta_1 - delta_2, theta_3 - theta_2 - delta_3),
        bodies=tuple(bars),
        springs=(Spring(k_1, alpha_1, theta_1), Spring(k_2, alpha_2, delta_2),
                 Spring(k_3, alpha_3, delta_3)),
        dampers=(Damper(c_1, theta_1), Damper(c_2, delta_2), Damper(c_3, delta_3)),
        forces=(),
        gravity=g,
        points={"tip": joint},
        range_centre=(alpha_1, alpha_2, alpha_3),
        periodic=(False, False, False),
        requirements=(
            Requirement(sp.And(l_1 > 0, l_2 > 0, l_3 > 0), "LENGTH_NOT_POSITIVE",
                        "the lengths must be positive"),
            Requirement(sp.And(m_1 >= 0, m_2 >= 0, m_3 >= 0), "MASS_NEGATIVE",
                        "the masses must not be negative"),
        ),
    )
