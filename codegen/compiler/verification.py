"""Every library checked against the model it came from, before a file is written.

The derivation solves the constraints in closed form, eliminates the multipliers and
differentiates along the motion symbolically: one sign taken for granted there gives a
library that agrees with itself and is wrong. This check shares nothing with the derivation
but the model's own expressions. At parameter sets drawn within the model's requirements and
angles over the whole range of the independent coordinate, it
- solves the model's constraints by Newton's method, from a perturbed closed form and then
  along the motion to the neighbouring angles; the closed form must satisfy them and lie in
  the declared assembly mode (the model's ``assembly_modes`` positive);
- takes V from the bodies, springs and loads as the model states them, G = dV/dtheta and
  K = G' by five-point stencils over those solutions;
- takes M and e1 = M'/2 from the bodies' numerical velocities, B from the dampers';
and compares with them the plan's expressions, which are what the printer writes as C: the
dependent state, G, e0, e1, e2, K and thetaddot (on every assembly mode's sign choice), the
assembly-mode conditions the library decides each state's mode by, and sigma at every zero
of G it brackets.
A discrepancy stops generation with one message naming the quantity, the angle, the
parameters and both values. Points next to a singular state (a radicand near zero, a
constraint Jacobian near singular, Newton not converging) are left out: there the stencil
itself is not accurate.
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.pycode import MpmathPrinter

from .emission.plan import CFunction, Plan
from .model import Mechanism

#: Parameter sets: the model's example and sets drawn around it.
SETS = 6
#: Angles per set, spread over the whole range, plus two next to its ends.
ANGLES = 72
#: A drawn parameter is the example's value times exp(U(-SPREAD, SPREAD)); a zero example
#: value is drawn in +-(the mean magnitude of the parameters of its unit).
SPREAD = 0.3
#: The stencils' step [rad]: truncation ~STEP^4, rounding ~eps/STEP^2, both far below the
#: tolerances.
STEP = 2e-3
#: Allowed difference, relative to the sum of the magnitudes of each quantity's terms.
TOLERANCE = {"position": 1e-8, "rate": 1e-6, "G": 1e-6, "K": 1e-5, "e0": 1e-6, "e1": 1e-5,
             "e2": 1e-6, "thetaddot": 1e-5, "sigma": 1e-6, "assembly mode": 0.0,
             "assembly_modes": 1e-8}
#: A point is left out where a radicand is below this fraction of its terms' magnitude.
RADICAND_MARGIN = 1e-3
#: ... or where the constraint Jacobian's condition number exceeds this.
CONDITION_LIMIT = 1e8
SEED = 20261125
NEWTON_STEPS = 40


class VerificationError(ValueError):
    """The generated expressions disagree with the model: one line, what and where."""


@dataclass(frozen=True)
class Report:
    sets: int
    points: int       # angles compared (of sets * (ANGLES + 2))
    zeros: int        # zeros of G at which sigma was checked
    seconds: float


def verify(mechanism: Mechanism, plan: Plan, user: Mechanism | None = None) -> Report:
    """Raise VerificationError unless the plan's expressions equal the model's numerics.
    ``mechanism`` is the one derived, ``user`` the model as written (the same but for
    renamed names, derivation.names), whose names the messages use."""
    start = time.perf_counter()
    model = _ModelNumerics(mechanism)
    sets = parameter_sets(mechanism, np.random.default_rng(SEED))
    checker = _Checker(mechanism, plan, user)
    # the functions of one angle on each other sign choice of the assembly roots, at the
    # states that choice gives (the model's mode conditions are not theirs to meet)
    others = [_Checker(mechanism, plan, user, signs=k, functions=checker.functions)
              for k in _sign_choices(plan)]
    points = zeros = 0
    for params in sets:
        checked, found = checker.check(model, params)
        points += checked
        zeros += found
        for other in others:
            points += other.check(model, params)[0]
    if points < len(sets):
        raise VerificationError(
            f"{mechanism.name}: the library could be compared with the model at only {points} "
            f"angles of {len(sets)} parameter sets (the closed form is undefined or singular "
            "almost everywhere)")
    return Report(len(sets), points, zeros, time.perf_counter() - start)


#: The compiled kernels and the plan's expressions are both evaluated in double: only
#: rounding separates them, relative to each output's typical size over the range (sigma:
#: double-double against 40 digits, relative to its largest coefficient).
COMPILED_TOLERANCE = 1e-8
SIGMA_TOLERANCE = 1e-13
COMPILED = ("dependent_state", "equilibrium_residual", "reduced_coefficients",
            "linearisation", "angular_acceleration", "equilibrium_state", "sigma")

#: call(name, self._user_values(), inputs): the compiled function ``name`` at the parameters ``values``
#: over equal-length arrays of its scalar inputs, one row of its outputs per input (NaN
#: where it reports an error); with no inputs, one row.
Call = Callable[[str, dict, tuple], np.ndarray]


def verify_compiled(mechanism: Mechanism, plan: Plan, call: Call,
                    user: Mechanism | None = None) -> int:
    """Raise VerificationError unless the compiled library gives the plan's values (what the
    printer, the templates and the compiler made of them) at every parameter set and angle
    ``verify`` uses; the number of values compared. ``call`` takes the user's names."""
    checker = _Checker(mechanism, plan, user)
    return sum(checker.check_compiled(values, call) for values in
               parameter_sets(mechanism, np.random.default_rng(SEED)))


def _sign_choices(plan: Plan) -> list[int]:
    """The sign choices other than 0 that the plan's functions of one angle evaluate on."""
    return list(range(1, len(plan.function("dependent_state").on_signs) + 1))


# --------------------------------------------------------------------------- parameters


def parameter_sets(mechanism: Mechanism, rng: np.random.Generator,
                   count: int = SETS) -> list[dict[str, float]]:
    """The example and count - 1 sets drawn around it that meet every requirement."""
    example = {p.symbol.name: float(p.example_value) for p in mechanism.parameters}
    units = {p.symbol.name: p.unit for p in mechanism.parameters}
    typical = {}
    for name, unit in units.items():
        same = [abs(v) for n, v in example.items() if units[n] == unit and v != 0]
        typical[name] = float(np.mean(same)) if same else 1.0
    holds = [_numeric(mechanism.symbols, [r.condition]) for r in mechanism.requirements]
    sets = [example]
    for attempt in range(200 * count):
        if len(sets) == count:
            break
        vary_zeros = attempt < 100 * count  # then keep zero values at zero
        drawn = {n: v * math.exp(rng.uniform(-SPREAD, SPREAD)) if v else
                 (rng.uniform(-1, 1) * typical[n] if vary_zeros else 0.0)
                 for n, v in example.items()}
        values = [drawn[s.name] for s in mechanism.symbols]
        if all(bool(h(*values)[0]) for h in holds):
            sets.append(drawn)
    return sets


# --------------------------------------------------------------------------- the model


def _numeric(args, exprs):
    """A numpy function of args returning the list of exprs."""
    return sp.lambdify(list(args), list(exprs), modules="numpy")


def potential_parts(m: Mechanism) -> list[sp.Expr]:
    """V's parts as the model states them, one per physical cause: springs, gravity on each
    body, loads (in the coordinates' functions of time)."""
    parts = [s.stiffness * (s.length - s.free_length) ** 2 / 2 for s in m.springs]
    parts += [b.mass * m.gravity * b.centre[1] for b in m.bodies]
    parts += [-(p.force[0] * p.point[0] + p.force[1] * p.point[1]) for p in m.forces]
    parts += [-t.torque * t.angle for t in m.torques]
    return parts


def _broadcast(values, shape) -> np.ndarray:
    return np.stack([np.broadcast_to(np.asarray(v, dtype=float), shape) for v in values],
                    axis=-1) if values else np.zeros(shape + (0,))


class _ModelNumerics:
    """The model's own expressions as numpy functions of (parameters, coordinates)."""

    def __init__(self, mechanism: Mechanism):
        m = mechanism
        frozen = m.freezer()
        coords = [frozen[c.function] for c in m.coordinates]
        self.independent = [c.name for c in m.coordinates].index(m.independent)
        self.dependent = [i for i in range(len(coords)) if i != self.independent]
        args = list(m.symbols) + coords

        def f(exprs):
            return _numeric(args, [sp.sympify(e).xreplace(frozen) for e in exprs])

        constraints = sp.Matrix(len(m.constraints), 1, list(m.constraints)).xreplace(frozen)
        self.constraints = f(list(constraints))
        self.jacobian = f(list(constraints.jacobian([coords[i] for i in self.dependent]))
                          if m.constraints else [])
        self.shape = (len(m.constraints), len(self.dependent))
        self.potential = f(potential_parts(m))
        # What moves: body centres (x, y) and angles, each with its mass or inertia.
        self.motion = f([x for b in m.bodies for x in (*b.centre, b.angle)])
        self.inertia = f([x for b in m.bodies for x in (b.mass, b.mass, b.inertia)])
        self.dampers = f([d.length for d in m.dampers])
        self.damping = f([d.coefficient for d in m.dampers])
        self.modes = f(list(m.assembly_modes))

    def solve(self, params: list[np.ndarray], theta: np.ndarray, guess: np.ndarray):
        """Newton on the constraints for the dependent coordinates at each theta: (q, ok)."""
        q = np.array(guess, dtype=float)
        ok = np.isfinite(q).all(axis=-1)
        if not self.dependent:
            return q, ok
        q = np.where(ok[..., None], q, 0.0)
        for _ in range(NEWTON_STEPS):
            residual, jac = self._linearised(params, q, theta)
            step = np.einsum("...ij,...j->...i", np.linalg.pinv(jac), residual)
            q = q - step
            if np.all(np.abs(step) <= 1e-15 * (1 + np.abs(q))):
                break
        residual, jac = self._linearised(params, q, theta)
        ok &= np.all(np.abs(step) <= 1e-12 * (1 + np.abs(q)), axis=-1)
        ok &= np.linalg.cond(jac) < CONDITION_LIMIT
        return q, ok & np.isfinite(residual).all(axis=-1)

    def _linearised(self, params, q: np.ndarray, theta: np.ndarray):
        """The constraints' residuals and their Jacobian in the dependent coordinates."""
        full = self._full(q, theta)
        residual = _broadcast(self.constraints(*params, *full), theta.shape)
        jac = _broadcast(self.jacobian(*params, *full), theta.shape).reshape(
            theta.shape + self.shape)
        return residual, jac

    def _full(self, dependent: np.ndarray, theta: np.ndarray) -> list[np.ndarray]:
        """Every coordinate, in the model's order."""
        full = [None] * (len(self.dependent) + 1)
        full[self.independent] = theta
        for k, i in enumerate(self.dependent):
            full[i] = dependent[..., k]
        return full


# --------------------------------------------------------------------------- the comparison


#: Samples around each angle, in steps: the five-point stencils of step STEP use the even
#: ones (-2, -1, 0, 1, 2), those of step STEP / 2 the middle five; the two estimates'
#: difference bounds the error of the finer one (fourth order: ~1/15 of it).
OFFSETS = np.array([-2, -1, -0.5, 0, 0.5, 1, 2]) * STEP
MIDDLE = 3
COARSE, FINE = (0, 1, 3, 5, 6), (1, 2, 3, 4, 5)


def _stencils(f: np.ndarray, picks, h: float) -> tuple[np.ndarray, np.ndarray]:
    """d/dtheta and d2/dtheta2 at the middle of five samples (axis 1) a step h apart."""
    a, b, c, d, e = (f[:, i] for i in picks)
    return (a - 8 * b + 8 * d - e) / (12 * h), (-a + 16 * b - 30 * c + 16 * d - e) / (12 * h * h)


@dataclass(frozen=True)
class _Quantity:
    """A model quantity at each angle, the size of its terms, and the numerical
    differentiation's error bound (the two step sizes' disagreement)."""

    value: np.ndarray
    scale: np.ndarray
    error: np.ndarray


class _Checker:
    """The plan's functions as numpy functions, compared with the model's numerics."""

    def __init__(self, mechanism: Mechanism, plan: Plan, user: Mechanism | None,
                 signs: int = 0, functions: dict[str, Callable] | None = None):
        self.mechanism = mechanism
        self.plan = plan
        self.signs = signs   # the sign choice of the assembly roots checked (0: as derived)
        self.symbols = mechanism.symbols
        user = user or mechanism
        # the user's name of each parameter and coordinate, for messages and the library
        self.labels = {s.name: u.name for s, u in zip(mechanism.symbols, user.symbols)}
        self.coordinates = [c.name for c in user.coordinates]
        self.name = user.independent
        self.functions: dict[str, Callable] = {} if functions is None else functions
        # sigma's coefficients cancel up to ~13 digits (the library evaluates them in
        # double-double): evaluated here in 40 digits.
        self.sigma = self._compiled(plan.function("sigma"), "mpmath") if plan.has(
            "sigma") else None
        self.centre = _numeric(self.symbols, [mechanism.range_centre])

    def _compiled(self, f: CFunction, modules: str = "numpy"):
        inputs = [s for a in f.inputs for s in a.symbols]
        exprs = [e for o in f.outputs for e in o.exprs]
        definitions = list(f.definitions)

        def cse(e):
            """A straight-line program is evaluated statement by statement, as the C is; the
            expressions share their subtrees through a quick CSE (printing the trees whole
            takes seconds for a four-bar), except sigma's, in the program's own steps."""
            if f.arithmetic == "double-double":
                return definitions, e
            replacements, reduced = sp.cse(e, symbols=sp.numbered_symbols("_shared"),
                                           order="none")
            return definitions + replacements, reduced

        printer = (MpmathPrinter if modules == "mpmath" else NumPyPrinter)(
            {"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True,
             "user_functions": {}, "order": "none"})
        return sp.lambdify(list(self.symbols) + inputs, exprs, modules=modules, cse=cse,
                           printer=printer)

    def _call(self, name, params, *inputs) -> np.ndarray:
        if self.signs:
            return self._call_on_signs(name, params, *inputs)
        return self._evaluate(name, params, *inputs)

    def _evaluate(self, name, params, *inputs) -> np.ndarray:
        """The plan's function ``name`` (compiled once for every checker of the plan)."""
        if name not in self.functions:
            self.functions[name] = self._compiled(self.plan.function(name))
        shape = np.broadcast(*inputs).shape if inputs else ()
        with np.errstate(all="ignore"):
            return _broadcast(self.functions[name](*params, *inputs), shape)

    def _call_on_signs(self, name, params, *inputs) -> np.ndarray:
        """The public function ``name`` on this checker's sign choice: its source (motion_
        signs<k>, or mode_linearisation), compiled once, and the outputs of its names
        (Plan.on_sign_choice)."""
        f = self.plan.function(name)
        source, at = self.plan.sign_choice_source(name, self.signs)
        picks = [at[o.name] + i for o in f.outputs for i in range(len(o.exprs))]
        rate = [np.zeros_like(inputs[0])] * (len(source.inputs) - len(inputs))
        return self._evaluate(source.name, params, *inputs, *rate)[..., picks]

    def _sigma(self, params) -> np.ndarray:
        with mpmath.workdps(40):
            return np.array([float(c) for c in self.sigma(*(mpmath.mpf(float(x))
                                                            for x in params))])

    def _angles(self, params) -> np.ndarray:
        """ANGLES spread over the range (none on a multiple of pi / 2), and two next to its
        ends."""
        centre = float(self.centre(*params)[0])
        fractions = (np.arange(ANGLES) + 0.3819660112501051) / ANGLES
        return centre - math.pi + 2 * math.pi * np.concatenate([fractions, [0.004, 0.996]])

    def _clear_of_singular_states(self, params, angles) -> np.ndarray:
        """Where every radicand is well above zero at every angle of a row."""
        if not self.plan.has("radicands"):
            return np.ones(angles.shape[0], dtype=bool)
        rad = self._call("radicands", params, angles)
        k = rad.shape[-1] // 2
        return np.all(rad[..., :k] > RADICAND_MARGIN * rad[..., k:],
                      axis=tuple(range(1, angles.ndim + 1)))

    def check_compiled(self, values: dict[str, float], call: Call) -> int:
        """The compiled functions against the plan's expressions at one parameter set."""
        self.values = values
        params = [np.float64(values[s.name]) for s in self.symbols]
        theta = self._angles(params)
        rate = np.random.default_rng(SEED).uniform(-3, 3, theta.shape)
        clear = self._clear_of_singular_states(params, theta[:, None])
        compared = 0
        for name in COMPILED:
            if not self.plan.has(name):
                continue
            f = self.plan.function(name)
            if name == "sigma":
                mine, theirs = self._sigma(params)[None, :], call(name, self._user_values(), ())
                allowed = SIGMA_TOLERANCE * np.abs(mine).max() + 0 * mine
                th = theta[:1]
            else:
                inputs = tuple(theta if a.symbols[0] == self.plan.enclosure.theta else rate
                               for a in f.inputs)
                mine, theirs = self._call(name, params, *inputs), call(name, self._user_values(), inputs)
                mine, theirs, th = mine[clear], theirs[clear], theta[clear]
                # each output where its expression is finite (another mode's, or another
                # branch's, may not exist at an angle where this one does); the library
                # reports an error (a row of NaN) exactly where one is not
                failed = np.isnan(theirs).all(-1) & ~np.isfinite(mine).all(-1)
                finite = np.isfinite(mine) & ~failed[:, None]
                squares = np.where(finite, mine, 0.0) ** 2
                typical = np.sqrt(squares.sum(axis=0) / np.maximum(finite.sum(axis=0), 1))
                allowed = np.where(finite, COMPILED_TOLERANCE * (np.abs(mine) + typical), np.inf)
            bad = np.argwhere(~(np.abs(theirs - mine) <= allowed) & np.isfinite(allowed))
            if bad.size:
                i, k = bad[0]
                self._fail(f"output {k} of {name}", th[i], f"the compiled library gives "
                           f"{theirs[i, k]:.15g}, its expression {mine[i, k]:.15g}",
                           (abs(theirs[i, k] - mine[i, k]), allowed[i, k]),
                           "the compiled library disagrees with the derivation")
            compared += int(np.isfinite(allowed).sum())
        return compared

    def check(self, model: _ModelNumerics, values: dict[str, float]) -> tuple[int, int]:
        """Compare at every angle of one parameter set: (angles compared, zeros of G)."""
        self.values = values
        params = [np.float64(values[s.name]) for s in self.symbols]
        theta = self._angles(params)
        angles = theta[:, None] + OFFSETS[None, :]
        state = self._call("dependent_state", params, angles, np.ones_like(angles))
        n = len(self.mechanism.coordinates)
        usable = np.isfinite(state).all(axis=(1, 2))
        usable &= self._clear_of_singular_states(params, angles)
        solved, ok = self._solve(model, params, angles, state[..., :n])
        usable &= ok
        if not usable.any():
            return 0, 0
        th, state = theta[usable], state[usable][:, MIDDLE]
        full = np.stack(model._full(solved[usable], angles[usable]), axis=-1)
        middle = full[:, MIDDLE]
        self._compare("position", state[:, :n], middle, th,
                      np.abs(middle) + np.sqrt(np.mean(middle ** 2, axis=0)), 0)
        if self.signs:   # another sign choice: no mode conditions to meet, no sigma to check
            self._compare_dynamics(params, th, state[:, n:],
                                   self._model_quantities(model, params, full))
            return int(usable.sum()), 0
        self._check_modes(model, params, middle, th)
        self._check_conditions(model, params, middle, th)
        quantities = self._model_quantities(model, params, full)
        self._compare_dynamics(params, th, state[:, n:], quantities)
        return int(usable.sum()), self._check_sigma(params, th, quantities["G"])

    @staticmethod
    def _solve(model, params, angles, closed):
        """The model's constraints solved at every sample: Newton from the closed form
        (perturbed) at the middle angle, then outwards along the motion."""
        dep = model.dependent
        guess = closed[:, MIDDLE][:, dep]
        guess = guess * (1 + 1e-6 * np.random.default_rng(SEED).uniform(-1, 1, guess.shape))
        solved = np.empty(angles.shape + (len(dep),))
        solved[:, MIDDLE], ok = model.solve(params, angles[:, MIDDLE], guess)
        for side in (range(MIDDLE + 1, len(OFFSETS)), range(MIDDLE - 1, -1, -1)):
            previous = solved[:, MIDDLE]
            for j in side:
                previous, good = model.solve(params, angles[:, j], previous)
                solved[:, j] = previous
                ok &= good
        return solved, ok

    def _check_modes(self, model, params, middle, th):
        modes = _broadcast(model.modes(*params, *middle.T), th.shape)
        for j in range(modes.shape[-1]):
            bad = np.flatnonzero(~(modes[:, j] > 0))
            if bad.size:
                i = bad[0]
                self._fail(f"the assembly mode (assembly_modes[{j}] > 0)", th[i],
                           f"the closed form's state gives {modes[i, j]:.10g}", None)

    def _check_conditions(self, model, params, middle, th):
        """The plan's assembly_conditions on the declared mode (which the library decides
        each state's mode by, for every set) equal the model's assembly_modes at the model's
        own states."""
        if not self.plan.has("assembly_conditions"):
            return
        modes = _broadcast(model.modes(*params, *middle.T), th.shape)
        mine = self._call("assembly_conditions", params, th)
        for k, source in enumerate(self.plan.condition_sources):
            want = modes[:, source]
            self._compare(f"assembly_modes[{source}]", mine[:, k], want, th,
                          np.abs(want) + np.sqrt(np.mean(want ** 2)))

    @staticmethod
    def _model_quantities(model, params, full) -> dict[str, _Quantity]:
        """G, K, e0, e1, e2 and the coordinates' rates from the model at each angle, by the
        fine stencils, with the coarse ones' disagreement as their error bound."""
        coords = list(np.moveaxis(full, -1, 0))
        shape = full.shape[:-1]
        parts = _broadcast(model.potential(*params, *coords), shape)
        motion = _broadcast(model.motion(*params, *coords), shape)
        weights = _broadcast(model.inertia(*params, *coords), shape)[:, MIDDLE]
        lengths = _broadcast(model.dampers(*params, *coords), shape)
        damping = _broadcast(model.damping(*params, *coords), shape)[:, MIDDLE]

        def estimate(picks, h):
            slope, curvature = _stencils(parts, picks, h)
            v, acc = _stencils(motion, picks, h)
            terms = {"G": slope, "K": curvature, "e0": weights * v * v,
                     "e1": weights * v * acc, "e2": damping * _stencils(lengths, picks, h)[0] ** 2}
            rates = _stencils(full, picks, h)[0]
            return terms, rates

        (coarse, coarse_rates), (fine, rates) = estimate(COARSE, STEP), estimate(FINE, STEP / 2)
        quantities = {k: _Quantity(fine[k].sum(-1), np.abs(fine[k]).sum(-1),
                                   np.abs(fine[k].sum(-1) - coarse[k].sum(-1))) for k in fine}
        quantities["rates"] = _Quantity(rates, np.abs(rates) + np.sqrt(np.mean(rates ** 2, axis=0)),
                                        np.abs(rates - coarse_rates))
        return quantities

    def _compare_dynamics(self, params, th, rates, q: dict[str, _Quantity]) -> None:
        self._compare("rate", rates, q["rates"].value, th, q["rates"].scale, q["rates"].error)
        G = q["G"]
        self._compare("G", self._call("equilibrium_residual", params, th)[:, 0], G.value, th,
                      G.scale, G.error)
        e = self._call("reduced_coefficients", params, th)
        for k in range(3):
            x = q[f"e{k}"]
            self._compare(f"e{k}", e[:, k], x.value, th, x.scale, x.error)
        K = q["K"]
        self._compare("K", self._call("linearisation", params, th)[:, 2], K.value, th,
                      K.scale, K.error)
        # thetaddot = -(e1 thetadot^2 + e2 thetadot + G) / e0 at a random rate
        e0, e1, e2 = q["e0"], q["e1"], q["e2"]
        moving = np.abs(e0.value) > 1e-6 * e0.scale.max(initial=0)
        rate = np.random.default_rng(SEED).uniform(-3, 3, th.shape)
        mass = np.where(moving, e0.value, 1.0)
        expected = -(e1.value * rate**2 + e2.value * rate + G.value) / mass
        size = (e1.scale * rate**2 + e2.scale * np.abs(rate) + G.scale) / np.abs(mass)
        error = (e1.error * rate**2 + e2.error * np.abs(rate) + G.error
                 + np.abs(expected) * e0.error) / np.abs(mass)
        accel = self._call("angular_acceleration", params, th, rate)[:, 0]
        self._compare("thetaddot", accel[moving], expected[moving], th[moving], size[moving],
                      error[moving])

    def _check_sigma(self, params, th, G: _Quantity) -> int:
        """sigma vanishes at each zero of G bracketed by neighbouring angles."""
        if self.sigma is None:
            return 0
        order = np.argsort(th)
        th, scale, G = th[order], G.scale[order], G.value[order]
        spacing = 2 * math.pi / ANGLES * 1.5
        brackets = np.flatnonzero((np.sign(G[:-1]) * np.sign(G[1:]) < 0)
                                  & (np.diff(th) < spacing))
        if not brackets.size:
            return 0
        lo, hi = th[brackets].copy(), th[brackets + 1].copy()
        g_lo = self._call("equilibrium_residual", params, lo)[:, 0]
        for _ in range(60):  # bisection on the library's G, compared with the model's above
            mid = (lo + hi) / 2
            g = self._call("equilibrium_residual", params, mid)[:, 0]
            left = np.sign(g) == np.sign(g_lo)
            lo, hi = np.where(left, mid, lo), np.where(left, hi, mid)
            g_lo = np.where(left, g, g_lo)
        # a sign change across a pole (a singular state between two samples) is no zero
        zero = np.abs(g_lo) <= 1e-8 * np.maximum(scale[brackets], scale[brackets + 1])
        zeros = ((lo + hi) / 2)[zero]
        if not zeros.size:
            return 0
        sigma = self._sigma(params)
        tau = np.tan(zeros / 2)
        # sum sigma_i tau^i / (1 + tau^2)^(degree/2): bounded as tau grows (theta near pi)
        powers = tau[:, None] ** np.arange(len(sigma))[None, :]
        norm = (1 + tau**2) ** ((len(sigma) - 1) / 2)
        value = (powers * sigma).sum(-1) / norm
        size = (np.abs(powers * sigma)).sum(-1) / norm
        self._compare("sigma", value, np.zeros_like(value), zeros, size)
        return len(zeros)

    def _compare(self, quantity, generated, model, th, scale, error=0.0):
        """generated = model within TOLERANCE * scale + error, at every angle th."""
        generated, model = np.asarray(generated), np.asarray(model)
        error = np.broadcast_to(error, model.shape)
        if generated.ndim > 1:
            for k in range(generated.shape[-1]):
                self._compare(f"{quantity} of {self._coordinate(k)}", generated[:, k],
                              model[:, k], th, scale[:, k], error[:, k])
            return
        allowed = TOLERANCE[quantity.split(" of ")[0].split("[")[0]] * scale + error + 1e-300
        bad = np.flatnonzero(~(np.abs(generated - model) <= allowed))
        if bad.size:
            i = bad[np.argmax(np.abs(generated - model)[bad] / allowed[bad])] if np.isfinite(
                generated[bad]).all() else bad[0]
            self._fail(quantity, th[i], f"the library gives {generated[i]:.12g}, the model "
                       f"{model[i]:.12g}", (abs(generated[i] - model[i]), allowed[i]))

    def _coordinate(self, k: int) -> str:
        return self.coordinates[k]

    def _user_values(self) -> dict[str, float]:
        return {self.labels[n]: v for n, v in self.values.items()}

    def _fail(self, quantity, angle, values, difference,
              what="the derivation disagrees with the model"):
        setting = ", ".join(f"{n}={v:.6g}" for n, v in self._user_values().items())
        gap = (f" (difference {difference[0]:.3g}, allowed {difference[1]:.3g})"
               if difference else "")
        on = f" on sign choice {self.signs} of the assembly roots" if self.signs else ""
        raise VerificationError(
            f"{self.mechanism.name}: {what}: {quantity}{on} at "
            f"{self.name} = {math.degrees(angle):.6f} deg: {values}{gap}; parameters "
            f"{setting}")
