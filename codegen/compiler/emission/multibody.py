"""The emission plan of a mechanism with n coordinates: its kernels (positions, M, B, the
velocity terms, G, K, the energies) as C functions, and G with its Jacobian K as one
interval program over a box of the coordinates, for the certified isolation of the
equilibria (codegen_boxes.h) that the runtime's analysis (codegen_multibody.h) runs.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..derivation.multibody import Multibody
from .interval import IntervalBody, interval_body
from .plan import CFunction, Input, Output, Plan, loads_of

#: Room in an analysis for proven equilibria and for the boxes it cannot decide.
EQUILIBRIUM_CAPACITY = 32
UNCERTAIN_CAPACITY = 16


@dataclass(frozen=True)
class MultibodyPlan(Plan):
    """A Plan whose analysis is over a box of n coordinates."""

    coordinates: tuple[tuple[str, str, str], ...] = ()  # independent: (name, unit, description)
    all_coordinates: tuple[tuple[str, str, str], ...] = ()
    centres: tuple[str, ...] = ()       # each range's centre, in the parameters' symbols
    periodics: tuple[bool, ...] = ()
    box: IntervalBody | None = None     # G (n) then K (n x n, row-major) over a box
    theta_names: tuple[str, ...] = ()   # the independent coordinates' symbols (internal names)

    @property
    def n(self) -> int:
        return len(self.coordinates)


def build_multibody_plan(d: Multibody) -> MultibodyPlan:
    m, user = d.mechanism, d.user
    n = d.n
    described = {c.name: (c.name, c.unit, c.description) for c in user.coordinates}
    independent = tuple(described[name] for name in user.independents)
    units = ", ".join(f"{name} [{unit}]" for name, unit, _ in independent)
    theta = Input("theta", d.theta, f"the independent coordinates: {units}", "N_DOF")
    theta_d = Input("theta_d", d.theta_d, "their rates, same order [unit/s]", "N_DOF")
    every = ", ".join(f"{c.name} [{c.unit}]" for c in user.coordinates)
    kinetic = (sp.Matrix(d.theta_d).T * d.mass * sp.Matrix(d.theta_d))[0] / 2
    square = f"row-major {n}x{n}"

    def function(*args) -> CFunction:   # each written in the dyads' program, if any
        return CFunction(*args, definitions=d.program)

    functions = (
        function("positions", "Every coordinate at the independent ones (the constraints "
                  "solved in turn).", "(30)-(34), n coordinates", (theta,),
                  (Output("coords", tuple(d.positions), f"every coordinate: {every}",
                          "N_COORDS"),)),
        function("mass_matrix", "Mass matrix M(theta): T = thetadot^T M thetadot / 2.",
                  "(37) for n coordinates", (theta,),
                  (Output("M", tuple(d.mass), f"{square}; entry (i, j) in kg times the units "
                          "of length^2 per unit of theta_i theta_j", "N_MATRIX"),)),
        function("damping_matrix", "Damping matrix B(theta): D = thetadot^T B thetadot / 2.",
                  "(39) for n coordinates", (theta,),
                  (Output("B", tuple(d.damping), f"{square}, as M per second", "N_MATRIX"),)),
        function("velocity_terms", "Velocity terms h(theta, thetadot) of M thetaddot + h + "
                  "B thetadot + G = 0 (centripetal and Coriolis).", "(38) for n coordinates",
                  (theta, theta_d), (Output("h", tuple(d.velocity_terms),
                                            "generalised forces [N or N m]", "N_DOF"),)),
        function("generalised_force", "Static generalised force G = dV/dtheta - Q: zero at "
                  "an equilibrium.", "(42) for n coordinates", (theta,),
                  (Output("G", tuple(d.generalised_force), "one per coordinate [N or N m]",
                          "N_DOF"),)),
        function("stiffness_matrix", "Stiffness matrix K = dG/dtheta: the linearisation's "
                  "restoring forces.", "(46)-(53) for n coordinates", (theta,),
                  (Output("K", tuple(d.stiffness), f"{square}; [N or N m per unit of "
                          "theta_j]", "N_MATRIX"),)),
        function("points", f"Positions of the points {', '.join(d.points)} (x, y for each).",
                 "(12), n coordinates", (theta,),
                 (Output("positions", tuple(e for p in d.points.values() for e in p),
                         "x, y of each point [m]", "N_POINT_COORDS"),)),
        function("energies", "Kinetic energy T and potential V (springs, gravity and the "
                  "constant loads' work, up to a constant).", "(16)-(21)", (theta, theta_d),
                  (Output("T", (kinetic,), "kinetic energy [J]"),
                   Output("V", (d.potential,), "potential energy [J]"))),
    )
    names = tuple(symbol for symbol, _ in _fields(d))
    box = interval_body([*d.generalised_force, *d.stiffness], names,
                        {t.name for t in d.theta}, d.program)
    return MultibodyPlan(
        prefix=m.name, title=m.title or m.name, points=tuple(d.points), loads=loads_of(user),
        parameters=tuple((p.symbol.name, p.unit, p.description, p.example_value)
                         for p in user.parameters),
        fields=_fields(d),
        sizes={"N_PARAMS": len(m.parameters), "N_DOF": n, "N_COORDS": len(m.coordinates),
               "N_MATRIX": n * n, "N_EIGENVALUES": 2 * n, "N_POINT_COORDS": 2 * len(d.points),
               "MAX_EQUILIBRIA": EQUILIBRIUM_CAPACITY, "MAX_UNCERTAIN": UNCERTAIN_CAPACITY},
        requirements=m.requirements, singular_state=m.singular_state,
        functions=functions, enclosure=None,
        coordinates=independent,
        all_coordinates=tuple(described[c.name] for c in user.coordinates),
        centres=tuple(str(c) for c in user.centres), periodics=tuple(m.periodics), box=box,
        theta_names=tuple(t.name for t in d.theta))


def _fields(d: Multibody) -> tuple[tuple[str, str], ...]:
    return tuple((p.symbol.name, u.symbol.name)
                 for p, u in zip(d.mechanism.parameters, d.user.parameters))
