"""A library of n coordinates checked against the model it came from, before a file is written.

As for one coordinate (verification.py), the check shares nothing with the derivation but
the model's own expressions. At parameter sets drawn within the model's requirements and
points drawn over the box of the ranges, in 30-digit arithmetic, it
- puts the plan's positions into the model's constraints, which must vanish;
- takes V from the springs, bodies and loads as the model states them, G = dV/dtheta by
  five-point stencils, and K by stencils of G;
- takes T and D from the bodies' and dampers' numerical velocities along a motion through
  the point, for each unit velocity and each pair: M and B entry by entry;
- takes h = dM/dt thetadot - dT/dtheta by stencils;
and compares the plan's positions, G, K, M, B and h with them.
"""
from __future__ import annotations

import mpmath
import numpy as np
import sympy as sp

from .derivation.multibody import Multibody
from .emission.multibody import MultibodyPlan
from .verification import SEED, SETS, VerificationError, parameter_sets, potential_parts

POINTS = 6                 # points per parameter set where every loop closes ...
DRAWS = 10 * POINTS        # ... out of at most this many drawn (one that does not: ~ms)
STEP = mpmath.mpf("1e-6")  # the stencils' step: truncation ~1e-24, rounding ~1e-24 at 30 digits
TOLERANCE = 1e-9           # relative to the size of the quantity's terms
DIGITS = 30


def verify_multibody(d: Multibody, plan: MultibodyPlan) -> int:
    """Raise VerificationError unless the plan's expressions equal the model's numerics; the
    number of values compared."""
    m = d.mechanism
    rng = np.random.default_rng(SEED)
    compared = 0
    with mpmath.workdps(DIGITS):
        model = _Model(d)
        for values in parameter_sets(m, rng, SETS):
            params = {p.symbol: mpmath.mpf(values[p.symbol.name]) for p in m.parameters}
            centres = [mpmath.mpf(float(sp.sympify(c).subs(params))) for c in m.centres]
            p = [params[s] for s in model.symbols]
            for theta in drawn_points(rng, centres, lambda t: model._assembled(p, t)):
                compared += model.check(plan, params, theta)
    if not compared:
        raise VerificationError(f"{d.user.name}: the mechanism cannot be assembled at any of "
                                "the points drawn to check it")
    return compared


def drawn_points(rng: np.random.Generator, centres: list, closes):
    """POINTS points drawn over the box of the ranges about ``centres`` where ``closes``
    (a function of the point); fewer where DRAWS draws do not find them (a loop that closes
    on a small part of the box), so that a set is never searched for long."""
    found = 0
    for _ in range(DRAWS):
        theta = [c + rng.uniform(-3.0, 3.0) for c in centres]
        if closes(theta):
            yield theta
            found += 1
            if found == POINTS:
                return


class NotAssembled(ArithmeticError):
    """A program met a complex value (a dyad's negative radicand): the loop does not close
    there, so there is nothing to evaluate."""


def _real(value):
    """value, unless it is complex (mpmath gives complex roots of negative numbers)."""
    if isinstance(value, (mpmath.mpc, complex)):
        raise NotAssembled
    return value


def in_program(args, program, exprs, module: str):
    """A function of ``args`` evaluating exprs written in a straight-line program's symbols:
    the steps in turn, then the expressions (written out, a dyad's expressions are too large
    to evaluate at 30 digits in reasonable time). In mpmath, it raises NotAssembled where a
    step is complex (in numpy such a step is NaN)."""
    steps = [sp.lambdify(list(args) + [s for s, _ in program[:i]], value, module)
             for i, (_, value) in enumerate(program)]
    final = sp.lambdify(list(args) + [s for s, _ in program], list(exprs), module)

    def evaluate(*values):
        values = list(values)
        for step in steps:
            values.append(_real(step(*values)))
        return [_real(x) for x in final(*values)]
    return evaluate


class _Model:
    def __init__(self, d: Multibody):
        self.d, m = d, d.mechanism
        self.symbols = list(m.symbols)
        coords = [sp.Symbol(c.name, real=True) for c in m.coordinates]
        self.coords = coords
        freeze = m.freezer()

        def fn(exprs):
            return sp.lambdify(self.symbols + coords,
                               [sp.sympify(e).subs(freeze) for e in exprs], modules="mpmath")

        self.constraints = fn(m.constraints)
        self.positions = in_program(self.symbols + list(d.theta), d.program, d.positions,
                                    "mpmath")
        self.potential = fn([sum(potential_parts(m), sp.S.Zero)])
        moving = [(b.mass, x) for b in m.bodies for x in b.centre]
        moving += [(b.inertia, b.angle) for b in m.bodies]
        self.inertias = fn([w for w, _ in moving])
        self.motions = fn([x for _, x in moving])
        self.dampers = fn([dm.coefficient for dm in m.dampers])
        self.lengths = fn([dm.length for dm in m.dampers])
        args = self.symbols + list(d.theta) + list(d.theta_d)
        self.plan = {name: in_program(args, d.program, expr, "mpmath") for name, expr in (
            ("G", d.generalised_force), ("K", d.stiffness), ("M", d.mass), ("B", d.damping),
            ("h", d.velocity_terms))}

    def check(self, plan: MultibodyPlan, params: dict, theta: list) -> int:
        """The number of values compared at theta: none where the loop does not close at
        theta or at a point its stencils reach."""
        p = [params[s] for s in self.symbols]
        if not self._assembled(p, theta):
            return 0
        try:
            return self._compare_all(plan, params, p, theta)
        except NotAssembled:  # a stencil's diagonal step just beyond a dead point
            return 0

    def _compare_all(self, plan: MultibodyPlan, params: dict, p: list, theta: list) -> int:
        n = len(theta)
        full = self.positions(*p, *theta)
        residual = self.constraints(*p, *full)
        scale = max([1] + [abs(x) for x in full])
        if residual and max(abs(r) for r in residual) > TOLERANCE * scale:
            self._fail("positions (the constraints do not vanish)", theta, params,
                       max(abs(r) for r in residual))

        def at(t, name, rates=None):
            """The plan's ``name`` (G, K, M, B or h) at t."""
            return [mpmath.mpf(v) for v in self.plan[name](*p, *t, *(rates or [0] * n))]

        def along(f, k, t):
            """d f(theta)/d theta_k by the five-point stencil."""
            def shifted(s):
                moved = list(t)
                moved[k] += s * STEP
                return f(moved)
            return (shifted(-2) - 8 * shifted(-1) + 8 * shifted(1) - shifted(2)) / (12 * STEP)

        def V(t):
            return self.potential(*p, *self.positions(*p, *t))[0]

        G = [along(V, k, theta) for k in range(n)]
        self._compare("G", at(theta, "G"), G, theta, params)
        K = [along(lambda t, i=i: at(t, "G")[i], k, theta) for i in range(n) for k in range(n)]
        self._compare("K", at(theta, "K"), K, theta, params)
        M = self._quadratic(p, theta, self._kinetic)
        self._compare("M", at(theta, "M"), M, theta, params)
        B = self._quadratic(p, theta, self._dissipation)
        self._compare("B", at(theta, "B"), B, theta, params)
        rates = [mpmath.mpf(x) for x in np.random.default_rng(n).uniform(-1, 1, n)]

        def momentum(t):  # M(theta) thetadot along the motion theta + s thetadot
            Mt = at(t, "M")
            return [sum(Mt[i * n + j] * rates[j] for j in range(n)) for i in range(n)]

        h = []
        for i in range(n):
            forward = [x + STEP * r for x, r in zip(theta, rates)]
            backward = [x - STEP * r for x, r in zip(theta, rates)]
            rate = (momentum(forward)[i] - momentum(backward)[i]) / (2 * STEP)
            h.append(rate - along(lambda t: self._kinetic(p, t, rates), i, theta))
        self._compare("h", at(theta, "h", rates), h, theta, params, tolerance=1e-6)
        return n + 3 * n * n + n

    def _assembled(self, p, theta) -> bool:
        """Whether every position is real at theta and the points its stencils reach (a
        dyad cannot be assembled everywhere: where it cannot, there is nothing to check)."""
        for k in range(len(theta)):
            for s in (-2, 2):
                moved = list(theta)
                moved[k] += s * STEP
                if not self._closes(p, moved):
                    return False
        return self._closes(p, theta)

    def _closes(self, p, theta) -> bool:
        try:
            self.positions(*p, *theta)
        except NotAssembled:
            return False
        return True

    def _speeds(self, p, theta, rates, motion) -> list:
        """Rates of each of ``motion``'s values moving theta at ``rates``, by central
        differences at 30 digits."""
        forward = motion(*p, *self.positions(*p, *[x + STEP * r for x, r in zip(theta, rates)]))
        backward = motion(*p, *self.positions(*p, *[x - STEP * r for x, r in zip(theta, rates)]))
        return [(a - b) / (2 * STEP) for a, b in zip(forward, backward)]

    def _kinetic(self, p, theta, rates):
        weights = self.inertias(*p, *self.positions(*p, *theta))
        return sum(w * v**2 / 2 for w, v in zip(weights, self._speeds(p, theta, rates,
                                                                     self.motions)))

    def _dissipation(self, p, theta, rates):
        weights = self.dampers(*p, *self.positions(*p, *theta))
        return sum(c * v**2 / 2 for c, v in zip(weights, self._speeds(p, theta, rates,
                                                                     self.lengths)))

    @staticmethod
    def _quadratic(p, theta, form) -> list:
        """The symmetric matrix A of form(rates) = rates^T A rates / 2, entry by entry."""
        n = len(theta)

        def unit(*indices):
            return [sum(1 for i in indices if i == k) for k in range(n)]

        diagonal = [2 * form(p, theta, unit(i)) for i in range(n)]
        return [diagonal[i] if i == j else
                form(p, theta, unit(i, j)) - (diagonal[i] + diagonal[j]) / 2
                for i in range(n) for j in range(n)]

    def _compare(self, name, generated, model, theta, params, tolerance=TOLERANCE) -> None:
        scale = 1 + max(abs(x) for x in model)
        worst = max(abs(a - b) for a, b in zip(generated, model))
        if worst > tolerance * scale:
            self._fail(name, theta, params, worst, generated, model)

    def _fail(self, name, theta, params, difference, generated=(), model=()) -> None:
        at = ", ".join(f"{t.name} = {float(x):.6g}" for t, x in zip(self.d.theta, theta))
        values = ", ".join(f"{s.name} = {float(v):.6g}" for s, v in params.items())
        raise VerificationError(
            f"{self.d.user.name}: {name} disagrees with the model by {float(difference):.3g} at "
            f"{at} ({values})" + (f": generated {[float(x) for x in generated]}, model "
                                  f"{[float(x) for x in model]}" if generated else ""))


#: The compiled kernels against the plan's expressions, both in double.
COMPILED_TOLERANCE = 1e-8
COMPILED = {"generalised_force": "generalised_force", "stiffness_matrix": "stiffness",
            "mass_matrix": "mass", "damping_matrix": "damping", "positions": "positions"}


def verify_compiled_multibody(d: Multibody, library) -> int:
    """Raise VerificationError unless the compiled library (a loaded Library) gives the
    plan's values at parameter sets and points drawn as ``verify_multibody`` draws them; the
    number of values compared."""
    m = d.mechanism
    rng = np.random.default_rng(SEED)
    args = list(m.symbols) + list(d.theta)
    expected = {name: in_program(args, d.program, getattr(d, field), "numpy")
                for name, field in COMPILED.items()}
    compared = 0
    for values in parameter_sets(m, rng, SETS):
        user = dict(zip((p.symbol.name for p in d.user.parameters),
                        (values[p.symbol.name] for p in m.parameters)))
        centres = [float(sp.sympify(c).subs({s: values[s.name] for s in m.symbols}))
                   for c in m.centres]
        numbers = [values[s.name] for s in m.symbols]

        def closes(theta):
            return _finite(expected["positions"], numbers, theta)

        for theta in drawn_points(rng, centres, closes):
            for name, f in expected.items():
                with np.errstate(all="ignore"):  # at a dead point G divides by zero
                    want = np.array(f(*numbers, *theta), dtype=float)
                if not np.all(np.isfinite(want)):
                    continue
                try:
                    got = np.array(library.FUNCTIONS[name](user, theta), dtype=float).ravel()
                except ValueError:   # a singular state the library reports: not compared
                    continue
                scale = 1 + np.abs(want).max()
                if not np.abs(got - want).max() <= COMPILED_TOLERANCE * scale:  # NaN too
                    at = ", ".join(f"{t.name} = {x:.6g}" for t, x in zip(d.theta, theta))
                    raise VerificationError(
                        f"{d.user.name}: the compiled {name} differs from its expression at "
                        f"{at}: {got.tolist()} against {want.tolist()}")
                compared += want.size
    return compared


def _finite(f, numbers: list, theta: list) -> bool:
    """Whether f (a numpy program) is finite at theta: NaN where a loop does not close."""
    with np.errstate(invalid="ignore"):
        return bool(np.all(np.isfinite(np.array(f(*numbers, *theta), dtype=float))))
