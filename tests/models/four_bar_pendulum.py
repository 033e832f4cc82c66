"""A four-bar linkage carrying a pendulum (2 DOF): a user's model with a dyad among several
independent coordinates.

Ground pivots O2 = (0, 0) and O4 = (d, 0). The crank O2-A (a_2, m_2, angle theta), the coupler
A-B (a_3, m_3, angle phi_3) and the rocker O4-B (a_4, m_4, angle phi_4) are uniform bars; the
coupler and rocker close the loop as a dyad (two assembly modes: B above or below the line
O4-A). A torsional spring k_c (free angle alpha) holds the crank. A pendulum, a point mass m_p
on a massless rod of length l_p at absolute angle psi from +X, hangs from B. Gravity along -Y.
The independent coordinates are theta and psi.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Requirement, Spring,
                                     parameter)

PARAMETERS = (
    parameter("d", "m", "distance between the ground pivots O2 and O4", "0.4"),
    parameter("a_2", "m", "crank length", "0.12"),
    parameter("a_3", "m", "coupler length", "0.35"),
    parameter("a_4", "m", "rocker length", "0.3"),
    parameter("m_2", "kg", "mass of the crank", "0.4"),
    parameter("m_3", "kg", "mass of the coupler", "1.0"),
    parameter("m_4", "kg", "mass of the rocker", "0.8"),
    parameter("l_p", "m", "pendulum length", "0.25"),
    parameter("m_p", "kg", "pendulum mass", "0.5"),
    parameter("k_c", "N m/rad", "torsional spring on the crank", "2"),
    parameter("alpha", "rad", "free angle of the crank's spring", "1.0"),
    parameter("c_c", "N m s/rad", "damping on the crank", "0.05"),
    parameter("c_p", "N m s/rad", "damping at the pendulum's pivot", "0.01"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)

COORDINATES = (
    Coordinate("theta", "rad", "crank angle"),
    Coordinate("psi", "rad", "pendulum angle from +X"),
    Coordinate("phi_3", "rad", "coupler angle"),
    Coordinate("phi_4", "rad", "rocker angle"),
)


def build() -> Mechanism:
    d, a_2, a_3, a_4, m_2, m_3, m_4, l_p, m_p, k_c, alpha, c_c, c_p, g = (
        p.symbol for p in PARAMETERS)
    theta, psi, phi_3, phi_4 = (c.function for c in COORDINATES)
    cos, sin = sp.cos, sp.sin
    A = (a_2 * cos(theta), a_2 * sin(theta))
    B = (d + a_4 * cos(phi_4), a_4 * sin(phi_4))
    P = (B[0] + l_p * cos(psi), B[1] + l_p * sin(psi))
    return Mechanism(
        name="four_bar_pendulum",
        title="a four-bar linkage carrying a pendulum",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent=("theta", "psi"),
        constraints=(A[0] + a_3 * cos(phi_3) - B[0], A[1] + a_3 * sin(phi_3) - B[1]),
        bodies=(
            Body("crank", m_2, (A[0] / 2, A[1] / 2), inertia=m_2 * a_2**2 / 12, angle=theta),
            Body("coupler", m_3, ((A[0] + B[0]) / 2, (A[1] + B[1]) / 2),
                 inertia=m_3 * a_3**2 / 12, angle=phi_3),
            Body("rocker", m_4, ((d + B[0]) / 2, B[1] / 2), inertia=m_4 * a_4**2 / 12,
                 angle=phi_4),
            Body("bob", m_p, P),
        ),
        springs=(Spring(k_c, alpha, theta),),
        dampers=(Damper(c_c, theta), Damper(c_p, psi - phi_4)),
        forces=(),
        gravity=g,
        points={"A": A, "B": B, "P": P},
        # B on the left of O4 -> A: the mode with the rocker above the line of centres
        assembly_modes=((A[0] - d) * (B[1] - 0) - (A[1] - 0) * (B[0] - d),),
        range_centre=(alpha, -sp.pi / 2),
        periodic=(True, True),
        requirements=(
            Requirement(sp.And(d > 0, a_2 > 0, a_3 > 0, a_4 > 0, l_p > 0),
                        "LENGTH_NOT_POSITIVE", "the lengths must be positive"),
            Requirement(sp.And(m_2 >= 0, m_3 >= 0, m_4 >= 0, m_p >= 0), "MASS_NEGATIVE",
                        "the masses must not be negative"),
            Requirement(k_c >= 0, "K_NEGATIVE", "k_c must not be negative"),
        ),
    )
