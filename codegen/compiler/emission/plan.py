"""The emission plan -- which C functions exist, their inputs, outputs,
expressions, units and the paper's equation each one implements.

The plan reads only the derivation. It is the single list that the printer, the
templates, the Python wrapper and the tests all walk.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ..derivation import Derivation
from ..derivation.algebra import written_out
from .scaling import Scaling, unit_scaling


@dataclass(frozen=True)
class Input:
    """A function argument: a scalar, or an array of ``size`` (a size macro name)."""

    name: str
    symbols: tuple[sp.Symbol, ...]
    description: str
    size: str | None = None  # None: a scalar passed by value


@dataclass(frozen=True)
class Output:
    """An output written through a pointer; arrays are row-major."""

    name: str
    exprs: tuple[sp.Expr, ...]
    description: str
    size: str | None = None  # None: a scalar written through double*


@dataclass(frozen=True)
class CFunction:
    name: str
    summary: str
    equation: str
    inputs: tuple[Input, ...]
    outputs: tuple[Output, ...]
    # A straight-line program the outputs are written in: (symbol, expression) in order.
    definitions: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()
    # "double", or "double-double" where the expressions cancel more digits than double has
    arithmetic: str = "double"
    # The assembly mode of each value (the outputs' values in order) of a function given on
    # every mode: a mode that has no value at the input (a dyad of the chain that cannot be
    # assembled on that mode, or a pole of it) is NaN; the others stand. Empty: all or none.
    slot_modes: tuple[int, ...] = ()
    # A function of one angle evaluated on the sign choice the model's assembly conditions
    # declare at that angle: for sign choices 1, 2, ... the function whose outputs of the
    # same names give this one's (mode_linearisation's at that mode's slot; vibration's from
    # its M, B, K); the function itself is choice 0. Empty: always choice 0.
    on_signs: tuple[str, ...] = ()

    def explicit(self, exprs) -> list[sp.Expr]:
        """Expressions with the program's symbols written out in the inputs."""
        return written_out(self.definitions, exprs)


def loads_of(mechanism) -> tuple[str, ...]:
    """The parameters that are the magnitude of a load (a torque, or one component of a
    force) and nothing else: what a simulator may drive as an input."""
    found = []
    for value in ([t.torque for t in mechanism.torques]
                  + [c for f in mechanism.forces for c in f.force]):
        symbol = sp.sympify(value)
        if symbol.is_Symbol and symbol.name not in found:
            found.append(symbol.name)
    return tuple(found)


@dataclass(frozen=True)
class Status:
    suffix: str   # the C enum name without the PREFIX_ part
    value: int
    message: str
    parameters: tuple[str, ...] = ()  # the parameters a failed requirement is about


#: Codes every library has, in a fixed order so their values never move.
GENERIC_STATUSES = (
    Status("OK", 0, "success"),
    Status("ERR_NULL_POINTER", 1, "a pointer argument is NULL"),
    Status("ERR_NONFINITE", 2, "an input value is NaN or infinite"),
    Status("ERR_ZERO_POLYNOMIAL", 3, "every polynomial coefficient is zero"),
    Status("ERR_NONFINITE_PARAM", 4, "a parameter is NaN or infinite"),
    Status("ERR_SINGULAR_STATE", 5, None),  # message from the mechanism
    Status("ERR_OVERFLOW", 6, "a result is too large to represent"),
    Status("ERR_EVERY_ANGLE", 7, "the equilibrium equation vanishes identically: "
                                 "every angle is an equilibrium"),
    Status("ERR_ARGUMENT", 8, "an argument is out of range (a mode number, an interval whose "
                              "ends are reversed, an integrator option, or output times out of "
                              "order)"),
    Status("ERR_CAPACITY", 9, "more equilibria or uncertain intervals than the result holds"),
    Status("ERR_STEP_BUDGET", 10, "the integrator used up its step budget before the last "
                                  "output time"),
    Status("ERR_STEP_SIZE", 11, "the integrator's step fell below the resolution of time: "
                                "the motion is singular or too stiff there"),
    Status("ERR_MODE_UNDECIDED", 12, "the model's assembly-mode conditions decide no mode "
                                     "at this angle (a dyad between its modes, or a condition "
                                     "that does not tell them apart there)"),
)

#: Room in an analysis for roots where no polynomial bounds their number, and for the
#: intervals the certified isolation cannot decide: at least these, and PER_MODE_CAPACITY
#: for each assembly mode (a chain's modes each have their own limit positions).
ISOLATION_CAPACITY = 32
UNCERTAIN_CAPACITY = 16
PER_MODE_CAPACITY = 8


@dataclass(frozen=True)
class Enclosure:
    """G and its slope G' on each assembly mode, for their interval extension: what the
    certified isolation of G's zeros evaluates."""

    theta: sp.Symbol
    residuals: tuple[sp.Expr, ...]  # G on mode k, roots written out
    slopes: tuple[sp.Expr, ...]     # dG/dtheta on mode k (K_EQ's expression)
    equation: str = ""
    # the straight-line program the expressions are written in (a chain's; see CFunction)
    definitions: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()


@dataclass(frozen=True)
class Plan:
    prefix: str
    title: str
    parameters: tuple[tuple[str, str, str, str], ...]  # (name, unit, description, example)
    sizes: dict[str, int]
    requirements: tuple                            # model.Requirement
    singular_state: str
    functions: tuple[CFunction, ...]
    enclosure: Enclosure               # G and G' of every mode, for the certified isolation
    root_kinds: tuple[str, ...] = ()   # 'assembly' or 'length', for each square root
    mode_of_branch: tuple[int, ...] = ()  # the assembly mode (mode_linearisation) of each branch
    condition_bits: tuple[int, ...] = ()  # the mode bit each assembly-mode condition decides
    condition_sources: tuple[int, ...] = ()  # each one's index in the model's assembly_modes
    range_centre: str = "0"            # the coordinate ranges over (centre - pi, centre + pi]
    periodic: bool = True              # theta and theta + 2 pi are the same state
    # Each parameter's symbol in the expressions and its field of PREFIX_params (the name
    # the user gave it), in order; they differ where the user's name clashes (derivation/names)
    fields: tuple[tuple[str, str], ...] = ()
    points: tuple[str, ...] = ()       # the named points, in the order of their outputs
    loads: tuple[str, ...] = ()        # the parameters that are a load's magnitude (inputs)
    # motion_signs<j>: the functions of one angle on sign choice j > 0 in one kernel, which
    # the public ones take their outputs from there (CFunction.on_signs); not public
    mode_functions: tuple[CFunction, ...] = ()
    # the units the analysis divides out and multiplies back (None: it keeps the user's)
    scaling: Scaling | None = None

    @property
    def reads(self) -> tuple[tuple[str, str], ...]:
        """(symbol, struct field) of each parameter, in order."""
        return self.fields or tuple((p[0], p[0]) for p in self.parameters)

    def field(self, symbol: str) -> str:
        """The struct field a parameter's symbol is read from."""
        return dict(self.reads).get(symbol, symbol)

    def function(self, name: str) -> CFunction:
        """A function of the plan, public or of another sign choice (mode_functions)."""
        return next(f for f in self.functions + self.mode_functions if f.name == name)

    def has(self, name: str) -> bool:
        return any(f.name == name for f in self.functions)

    def sign_choice_source(self, name: str, k: int) -> tuple[CFunction, dict[str, int]]:
        """The function the public ``name`` takes its outputs from on sign choice k > 0
        (CFunction.on_signs), and where each of its outputs starts in that function's out[]
        (at slot k of a function given on every mode)."""
        source = self.function(self.function(name).on_signs[k - 1])
        at, start = {}, 0
        for o in source.outputs:
            at[o.name] = start + (k if source.slot_modes else 0)
            start += len(o.exprs)
        return source, at

    def on_sign_choice(self, name: str, k: int) -> CFunction:
        """The public function ``name`` as it evaluates on sign choice k (CFunction.on_signs):
        its outputs' expressions taken from its source's outputs of the same names (at slot k
        of a function given on every mode), vibration's from M, B, K there."""
        f = self.function(name)
        if k == 0 or not f.on_signs:
            return f
        source = self.function(f.on_signs[k - 1])
        given = {o.name: o.exprs[k:k + 1] if source.slot_modes else o.exprs
                 for o in source.outputs}
        if "M" in given and "omega_n_squared" not in given:   # vibration from M, B, K
            (M,), (B,), (K,) = given["M"], given["B"], given["K"]
            given |= {"omega_n_squared": (K / M,), "zeta_omega_n": (B / (2 * M),)}
        return replace(f, outputs=tuple(replace(o, exprs=given[o.name]) for o in f.outputs),
                       definitions=source.definitions, on_signs=())

    @property
    def statuses(self) -> tuple[Status, ...]:
        generic = tuple(Status(s.suffix, s.value, s.message or self.singular_state)
                        for s in GENERIC_STATUSES)
        order = [p[0] for p in self.parameters]
        return generic + tuple(
            Status(f"ERR_{r.code}", len(generic) + i, r.message,
                   tuple(sorted((self.field(s.name) for s in r.condition.free_symbols),
                                key=order.index)))
            for i, r in enumerate(self.requirements))


def _units(coords) -> str:
    return ", ".join(f"{c.name} [{c.unit}]" for c in coords)


@dataclass(frozen=True)
class _Scope:
    """What each group of functions is declared from: the derivation, the arguments the
    functions share, and how a mechanism with several assembly modes qualifies them."""

    d: Derivation
    units: str                 # the coordinates with their units, for doc comments
    coords: Input
    rates: Input
    accels: Input
    multipliers: Input
    theta: Input
    theta_d: Input
    theta_e: Input
    per_mode: bool             # several assembly modes: a mode without a value reads NaN
    on_every_mode: str         # the doc sentence that says so
    declared: str              # the doc sentence of functions on the declared mode
    others: range              # the sign choices other than 0 the conditions may pick
    program: tuple             # a chain's straight-line program its expressions are written in

    @classmethod
    def of(cls, d: Derivation) -> "_Scope":
        s, red = d.state, d.reduction
        units = _units(d.user.coordinates)
        per_mode = len(d.linearisation.modes) > 1
        # Where the model declares its modes by conditions, the public functions of one
        # angle evaluate on the sign choice the conditions hold on, for each set and angle:
        # choice 0 by their own kernels, another by one fused kernel of that choice
        # (everything of one angle but the linearisation, which mode_linearisation has on
        # every choice).
        chosen = per_mode and bool(d.linearisation.condition_bits)
        return cls(
            d=d, units=units,
            coords=Input("coords", s.coords, f"generalised coordinates: {units}", "N_COORDS"),
            rates=Input("rates", s.rates, "their time derivatives, same order [unit/s]",
                        "N_COORDS"),
            accels=Input("accels", s.accels, "their second derivatives, same order "
                         "[unit/s^2]", "N_COORDS"),
            multipliers=Input("multipliers", s.multipliers,
                              "Lagrange multipliers lambda_1.. (one per constraint)",
                              "N_CONSTRAINTS"),
            theta=Input(red.theta.name, (red.theta,),
                        f"independent coordinate {d.user.independent} [rad]"),
            theta_d=Input(red.theta_d.name, (red.theta_d,), "its rate [rad/s]"),
            theta_e=Input(red.theta.name, (red.theta,), "equilibrium angle theta_E [rad]"),
            per_mode=per_mode,
            on_every_mode=(" A mode that has no value at theta (its dyads cannot be "
                           "assembled there, or it is singular) reads NaN; the failure only "
                           "where no mode has one." if per_mode else ""),
            declared=(" On the assembly mode the model declares: the sign choice its "
                      "conditions hold on at theta, for each parameter set." if chosen else ""),
            others=range(1, len(d.linearisation.modes)) if chosen else range(0),
            program=d.program)

    def fn(self, key: str, summary: str, inputs, outputs, definitions=None,
           arithmetic="double", parts=(), slot_modes=(), on_signs=()) -> CFunction:
        """A function, written in the chain's program unless given another; one fused from
        others (parts) implements their equations."""
        equations = self.d.mechanism.equations
        equation = ", ".join(e for e in (equations.get(k, "") for k in parts or (key,)) if e)
        return CFunction(key, summary, equation, tuple(inputs), tuple(outputs),
                         tuple(self.program if definitions is None else definitions),
                         arithmetic, tuple(slot_modes), tuple(on_signs))

    def one(self, key, summary, inputs, outputs, source="") -> CFunction:
        """A public function of one angle; on sign choice j > 0 its outputs are those of
        the same names of ``source``, or of motion_signs<j> (CFunction.on_signs)."""
        return self.fn(key, summary + self.declared, inputs, outputs, on_signs=tuple(
            source or f"motion_signs{j}" for j in self.others))

    def vec(self, M) -> tuple:
        return tuple(self.d.frozen(e) for e in M)

    def mode_of_branch(self) -> tuple[int, ...]:
        eq, lin = self.d.equilibrium, self.d.linearisation
        return tuple(_mode_of(branch.signs, lin.modes, eq.roots) for branch in eq.branches)


def _state_outputs(sc: _Scope, q) -> tuple[Output, ...]:
    """The state and the reduced equation's coefficients at one angle (steps 4-6)."""
    return (Output("coords", q.positions, f"coordinates: {sc.units}", "N_COORDS"),
            Output("rates", q.velocities, "their rates [unit/s]", "N_COORDS"),
            Output("e", q.e, "e0 [kg m^2], e1 [kg m^2], e2 [N m s]", "N_REDUCED"),
            Output("theta_dd", (q.angular_acceleration,), "[rad/s^2]"),
            Output("residual", (q.residual,), "G [N m]"),
            Output("scale", (q.scale,), "[N m]"),
            Output("values", q.radicands, "[unit^2]", "N_ROOTS"),
            Output("scales", q.radicand_scales, "[unit^2]", "N_ROOTS"))


def _one_angle_functions(sc: _Scope) -> dict[str, CFunction]:
    """The public functions of the independent angle alone (steps 4-8), on mode 0."""
    kinds = ", ".join(f"{r.kind}" for r in sc.d.equilibrium.roots)
    q = sc.d.on_mode(0)
    out = {o.name: o for o in _state_outputs(sc, q)}
    theta, theta_d, theta_e = sc.theta, sc.theta_d, sc.theta_e
    return {f.name: f for f in (
        sc.one("dependent_state",
               "All coordinates and rates from the independent angle and its rate.",
               [theta, theta_d], [out["coords"], out["rates"]]),
        sc.one("reduced_coefficients",
               "Coefficients of e0 thetaddot + e1 thetadot^2 + e2 thetadot + G(theta) = 0.",
               [theta], [out["e"]]),
        sc.one("angular_acceleration", "thetaddot from the reduced equation of motion.",
               [theta, theta_d], [out["theta_dd"]]),
        sc.one("equilibrium_residual",
               "Static generalised force G(theta) = dV/dtheta - Q_theta (zero at equilibria), "
               "and the sum of the magnitudes of its contributions (springs, gravity, loads).",
               [theta], [out["residual"], out["scale"]]),
        sc.one("radicands",
               f"The radicands under the square roots of the position analysis ({kinds}), and "
               "the sum of the magnitudes of their terms. An assembly radicand below zero: the "
               "mechanism cannot be assembled at theta; a radicand zero: a singular state (a "
               "limit position or a vanishing length).",
               [theta], [out["values"], out["scales"]]),
        sc.one("linearisation", "Coefficients of M thetaddot_p + B thetadot_p + K theta_p = 0.",
               [theta_e], [Output("M", (q.mass,), "M_EQ [kg m^2]"),
                           Output("B", (q.damping,), "B_EQ [N m s]"),
                           Output("K", (q.stiffness,), "K_EQ [N m]")],
               source="mode_linearisation"),
        sc.one("vibration", "omega_n^2 = K/M and zeta*omega_n = B/(2M); "
                            "omega_n = sqrt(K/M), zeta = B/(2 M omega_n).",
               [theta_e], [Output("omega_n_squared", (q.omega_n_squared,), "[rad^2/s^2]"),
                           Output("zeta_omega_n", (q.zeta_omega_n,), "[1/s]")],
               source="mode_linearisation"),
    )}


def _sign_choice_kernels(sc: _Scope) -> tuple[CFunction, ...]:
    """Everything of one angle but the linearisation, on each sign choice k > 0 the
    conditions may pick, in one kernel (its outputs named as the public functions' are)."""
    return tuple(
        sc.fn(f"motion_signs{k}",
              f"The state, the reduced equation's coefficients, G and the radicands on "
              f"sign choice {k} of the assembly roots (mode_linearisation's mode {k}).",
              [sc.theta, sc.theta_d], _state_outputs(sc, sc.d.on_mode(k)),
              parts=("dependent_state", "reduced_coefficients", "angular_acceleration",
                     "equilibrium_residual", "radicands"))
        for k in sc.others)


def _constraint_functions(sc: _Scope) -> tuple[CFunction, ...]:
    """The constraints and their derivatives in the coordinates (step 2)."""
    kin, n, c = sc.d.kinematics, len(sc.d.mechanism.coordinates), len(sc.d.mechanism.constraints)
    if not c:
        return ()
    coords, rates, accels = sc.coords, sc.rates, sc.accels
    return (
        sc.fn("position_constraints",
              "Position constraints f(q) = 0 (zero on the mechanism).",
              [coords], [Output("f", sc.vec(kin.constraints), "constraint values [m]",
                                "N_CONSTRAINTS")]),
        sc.fn("constraint_jacobian", "Velocity-constraint matrix A = df/dq, so that A qdot = 0.",
              [coords], [Output("A", sc.vec(kin.jacobian),
                                f"row-major {c}x{n}; column j has the unit m per unit of q_j",
                                "N_JACOBIAN")]),
        sc.fn("velocity_constraints", "Velocity constraints A(q) qdot = 0.",
              [coords, rates], [Output("f_d", sc.vec(kin.velocity_constraints),
                                       "values [m/s]", "N_CONSTRAINTS")]),
        sc.fn("acceleration_constraints", "Acceleration constraints A qddot + Adot qdot = 0.",
              [coords, rates, accels],
              [Output("f_dd", sc.vec(kin.acceleration_constraints), "values [m/s^2]",
                      "N_CONSTRAINTS")]),
    )


def _lagrange_functions(sc: _Scope) -> tuple[CFunction, ...]:
    """The points, the energies and Lagrange's equations in all coordinates (step 3)."""
    kin, dyn, fr = sc.d.kinematics, sc.d.dynamics, sc.d.frozen
    points, vec = kin.point_positions, sc.vec
    constrained = bool(sc.d.mechanism.constraints)
    return (
        sc.fn("point_kinematics",
              f"Positions and velocities of the points {', '.join(points)} (x, y for each).",
              [sc.coords, sc.rates],
              [Output("positions", tuple(fr(e) for p in points.values() for e in p),
                      "x, y of each point [m]", "N_POINT_COORDS"),
               Output("velocities", tuple(fr(e) for p in kin.point_velocities.values()
                                          for e in p),
                      "vx, vy of each point [m/s]", "N_POINT_COORDS")]),
        sc.fn("energies", "Kinetic and potential energies and the Lagrangian L = T - V_G - V_E.",
              [sc.coords, sc.rates],
              [Output("T", (fr(dyn.kinetic),), "kinetic energy [J]"),
               Output("V_G", (fr(dyn.gravity_potential),), "gravitational potential energy [J]"),
               Output("V_E", (fr(dyn.elastic_potential),), "elastic potential energy [J]"),
               Output("lagrangian", (fr(dyn.lagrangian),), "Lagrangian [J]")]),
        sc.fn("lagrange_terms",
              "Terms of Lagrange's equations with multipliers, one entry per coordinate; "
              "residual = d/dt(dL/dqdot) - dL/dq + A^T lambda + V_D - Q_nc vanishes on a "
              "motion.",
              [sc.coords, sc.rates, sc.accels] + ([sc.multipliers] if constrained else []),
              [Output("dt_dL_dqdot", vec(dyn.dt_dL_dqdot), "d/dt (dL/dqdot) [N or N m]",
                      "N_COORDS"),
               Output("dL_dq", vec(dyn.dL_dq), "dL/dq [N or N m]", "N_COORDS"),
               Output("constraint_forces", vec(dyn.constraint_forces), "A^T lambda",
                      "N_COORDS"),
               Output("dissipative_forces", vec(dyn.dissipative_forces), "V_D", "N_COORDS"),
               Output("applied_forces", vec(dyn.applied_forces), "Q_nc", "N_COORDS"),
               Output("residual", vec(dyn.residual()), "left minus right side of (15)",
                      "N_COORDS")]),
    )


def _branch_functions(sc: _Scope, one_angle) -> tuple[CFunction, ...]:
    """The radicands and G on every sign choice of the square roots (step 7)."""
    eq = sc.d.equilibrium
    if not eq.roots:
        return ()
    return (
        one_angle["radicands"],
        sc.fn("equilibrium_branches",
              f"G on each of the {2 ** len(eq.roots)} branches (sign choices of the square "
              "roots; branch j takes root i negative when bit i of j is set; branch 0 is the "
              "mechanism as declared). A root of the polynomial zeroes G on one branch."
              + sc.on_every_mode,
              [sc.theta], [Output("residuals", tuple(b.residual for b in eq.branches), "[N m]",
                                  "N_BRANCHES")],
              slot_modes=sc.mode_of_branch() if sc.per_mode else ()),
    )


def _polynomial_functions(sc: _Scope) -> tuple[CFunction, ...]:
    """sigma, the polynomial in tan(theta/2) whose real roots hold every equilibrium
    (step 7), where the elimination gives one."""
    poly = sc.d.equilibrium.polynomial
    if not poly:
        return ()
    return (
        sc.fn("sigma",
              f"Coefficients sigma_0..sigma_{poly.degree} of sum sigma_i tau^i "
              f"(tau = tan(theta/2)), which vanishes wherever G does on some branch: the "
              f"numerator of G with every square root eliminated, times (1+tau^2)^"
              f"{poly.weight}{_divided(poly.divided)}. Evaluated in "
              "double-double arithmetic: squaring out the roots cancels up to ~13 digits.",
              [], [Output("sigma", poly.coefficients, "[as derived]", "N_SIGMA")],
              poly.definitions, arithmetic="double-double"),
        sc.fn("sigma_fast",
              "sigma in working precision, as plain straight-line code computes it (tens of "
              "times faster); where a coefficient's terms cancel, its error can far exceed "
              "rounding of the largest coefficient: the analysis uses sigma.",
              [], [Output("sigma", poly.coefficients, "[as derived]", "N_SIGMA")],
              poly.definitions, parts=("sigma",)),
    )


def _assembly_mode_functions(sc: _Scope) -> tuple[CFunction, ...]:
    """M, B, K on every assembly mode, and the conditions that tell the modes apart
    (steps 8-9), where the mechanism has several modes."""
    lin = sc.d.linearisation
    if not sc.per_mode:
        return ()
    n_modes, n_conditions = len(lin.modes), len(lin.condition_bits)
    every_mode = sc.fn(
        "mode_linearisation",
        "M, B, K (as linearisation) of every assembly mode: mode j flips the i-th assembly "
        "root when bit i of j is set; mode 0 is the mechanism as declared." + sc.on_every_mode,
        [sc.theta_e], [Output(name, tuple(getattr(mode, attr) for mode in lin.modes), unit,
                              "N_MODES")
                       for name, attr, unit in (("M", "mass", "M_EQ [kg m^2]"),
                                                ("B", "damping", "B_EQ [N m s]"),
                                                ("K", "stiffness", "K_EQ [N m]"))],
        slot_modes=tuple(range(n_modes)) * 3)
    if not n_conditions:
        return (every_mode,)
    conditions = sc.fn(
        "assembly_conditions",
        "The model's assembly-mode conditions on every mode (values[j * N_CONDITIONS + k]: "
        "condition k on mode j, numbered as mode_linearisation's), each positive where its "
        "dyad is assembled as declared, and the sizes of their terms: which mode a state "
        "is in, as declared, for any parameter set." + sc.on_every_mode,
        [sc.theta], [Output("values", tuple(c for mode in lin.modes for c in mode.conditions),
                            "[as declared]", "N_MODE_CONDITIONS"),
                     Output("scales", tuple(c for mode in lin.modes
                                            for c in mode.condition_scales),
                            "[as declared]", "N_MODE_CONDITIONS")],
        slot_modes=tuple(j for j in range(n_modes) for _ in range(n_conditions)) * 2)
    return (every_mode, conditions)


def _equilibrium_state(sc: _Scope) -> CFunction:
    """Everything the analysis evaluates at a root, fused: one CSE over it, so that it pays
    for the trigonometry, the square roots and their shared terms once per angle."""
    eq, lin = sc.d.equilibrium, sc.d.linearisation
    branched = bool(eq.roots)
    return sc.fn(
        "equilibrium_state",
        "Everything the analysis evaluates at one angle, in one pass: G and the size of "
        "its terms (as equilibrium_residual), M, B, K (as linearisation)"
        + (", G on every branch (as equilibrium_branches) and the radicands with their "
           "scales (as radicands)" if branched else "") + ".",
        [sc.theta_e],
        [Output("residual", (eq.residual,), "G [N m]"),
         Output("scale", (eq.branches[0].scale,), "[N m]"),
         Output("M", (lin.mass,), "M_EQ [kg m^2]"),
         Output("B", (lin.damping,), "B_EQ [N m s]"),
         Output("K", (lin.stiffness,), "K_EQ [N m]")]
        + ([Output("branch_residuals", tuple(b.residual for b in eq.branches), "[N m]",
                   "N_BRANCHES"),
            Output("radicands", tuple(eq.radicands), "[unit^2]", "N_ROOTS"),
            Output("radicand_scales", tuple(eq.radicand_scales), "[unit^2]", "N_ROOTS")]
           if branched else []),
        parts=("equilibrium_residual", "linearisation", "equilibrium_branches", "radicands"))


def _sizes(d: Derivation) -> dict[str, int]:
    """The size macros of the library: its arrays' lengths and the result's capacities."""
    m, eq, lin = d.mechanism, d.equilibrium, d.linearisation
    n, c = len(m.coordinates), len(m.constraints)
    n_roots, n_modes = len(eq.roots), len(lin.modes)
    n_conditions = len(lin.condition_bits)
    sizes = {"N_PARAMS": len(m.parameters), "N_COORDS": n, "N_CONSTRAINTS": c,
             "N_JACOBIAN": n * c, "N_POINT_COORDS": 2 * len(d.kinematics.point_positions),
             "N_REDUCED": len(d.reduction.e), "N_ROOTS": n_roots, "N_BRANCHES": 2 ** n_roots,
             "N_MODES": n_modes, "N_CONDITIONS": n_conditions,
             "N_MODE_CONDITIONS": n_conditions * n_modes}
    per_modes = PER_MODE_CAPACITY * n_modes
    sizes |= {"MAX_ROOTS": eq.polynomial.degree if eq.polynomial
              else max(ISOLATION_CAPACITY, per_modes),
              "MAX_UNCERTAIN": max(UNCERTAIN_CAPACITY, per_modes)}
    if eq.polynomial:
        sizes |= {"DEGREE": eq.polynomial.degree, "N_SIGMA": eq.polynomial.degree + 1}
    return sizes


def build_plan(d: Derivation) -> Plan:
    """The library's functions, group by group in the order of the method, and what the
    templates need beside them."""
    m, eq, lin = d.mechanism, d.equilibrium, d.linearisation
    sc = _Scope.of(d)
    one_angle = _one_angle_functions(sc)
    reduced = tuple(one_angle[k] for k in ("dependent_state", "reduced_coefficients",
                                           "angular_acceleration", "equilibrium_residual"))
    at_rest = (one_angle["linearisation"], one_angle["vibration"])
    return Plan(
        prefix=m.name,
        title=m.title or m.name,
        points=tuple(d.kinematics.point_positions),
        loads=loads_of(d.user),
        parameters=tuple((p.symbol.name, p.unit, p.description, p.example_value)
                         for p in d.user.parameters),
        fields=tuple((p.symbol.name, u.symbol.name)
                     for p, u in zip(m.parameters, d.user.parameters)),
        sizes=_sizes(d),
        requirements=m.requirements,
        singular_state=m.singular_state,
        root_kinds=tuple(r.kind for r in eq.roots),
        mode_of_branch=sc.mode_of_branch(),
        condition_bits=lin.condition_bits,
        condition_sources=lin.condition_sources,
        range_centre=str(d.user.range_centre),
        periodic=m.periodic,
        enclosure=Enclosure(d.reduction.theta,
                            tuple(eq.branch(mode.signs).residual for mode in lin.modes),
                            tuple(mode.stiffness for mode in lin.modes),
                            m.equations.get("equilibrium_residual", ""), sc.program),
        mode_functions=_sign_choice_kernels(sc),
        scaling=unit_scaling(d),
        functions=(_constraint_functions(sc) + _lagrange_functions(sc) + reduced
                   + _branch_functions(sc, one_angle) + _polynomial_functions(sc) + at_rest
                   + _assembly_mode_functions(sc) + (_equilibrium_state(sc),)),
    )


def _mode_of(signs, modes, roots) -> int:
    """The mode whose assembly roots have the signs a branch gives them."""
    assembly = [i for i, r in enumerate(roots) if r.kind == "assembly"]
    return next(k for k, mode in enumerate(modes)
                if all(mode.signs[i] == signs[i] for i in assembly))


def _divided(factors) -> str:
    """The denominator factors divided out of sigma, for its doc comment."""
    if not factors:
        return ""
    return ", divided by " + " * ".join(f"({sp.sstr(f)})^{k}" for f, k in factors) + \
        " (factors of G's denominator, where G has no zero)"
