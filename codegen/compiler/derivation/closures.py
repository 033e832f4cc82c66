"""Table 1 step 7 for n independent coordinates: every dependent coordinate in closed form.

The constraints are solved one unknown (or one dyad) at a time, in an order found from which
unknowns each constraint still holds, never from the order they are declared in:
- a constraint linear in one unknown (a slider's position, a relative angle) gives it;
- two constraints linear in the cosine and sine of one angle (C, S) give both, by Cramer's rule;
- one constraint P C + Q S = W in one angle (a crank pin on a line: a slider-crank's
  closure) gives (C, S) = (P W - sigma Q D, Q W + sigma P D) / (P^2 + Q^2), with
  D = sqrt(P^2 + Q^2 - W^2) an *assembly-mode* root;
- two constraints in the cosines and sines of two angles (a dyad of two bars: two circles)
  give, with the second angle's (C, S) eliminated, their radical line in the first: as above;
- two constraints in one angle and one linear unknown (a dyad with a slider) give, with the
  linear unknown eliminated, one line in the angle: as above.
Each angle is atan2(S, C); elsewhere its cosine and sine are C and S themselves. D, C and S
are kept symbols of a straight-line program (``Closure.program``), which the library
computes once per call, and derivatives follow them by the chain rule (``Closure.diff``):
written out, a dyad's expressions and their derivatives grow a hundredfold. Where
P^2 + Q^2 - W^2 < 0 the mechanism cannot be assembled there: the root is NaN in the
kernels, and the interval programs flag the boxes it makes undefined.

Each root's sign sigma is the assembly mode the model declares (``assembly_modes``: each
expression positive in the mode meant): the one combination of signs under which every
declared expression is positive wherever the mechanism is assembled, at the example
parameters over the box of the ranges. A declaration that no combination, or more than one,
satisfies is refused with the coordinate it concerns.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp

from ..model import Mechanism, ModelError
from .algebra import expand_angle_sums, reduce_trig, written_out

#: Points of the box at which the declared assembly modes are evaluated.
SAMPLES = 400
#: A declared expression this small against its terms' size is taken as undecided there.
MARGIN = 1e-9


@dataclass(frozen=True)
class Closure:
    """Every dependent coordinate (``values``) and the cosine and sine of each angle solved
    from a dyad (``trig``), in the independent coordinates and the parameters; the assembly
    roots' radicands (each >= 0 where the mechanism can be assembled)."""

    coords: tuple[sp.Symbol, ...]
    values: dict[sp.Symbol, sp.Expr]
    trig: dict[sp.Expr, sp.Expr]
    radicands: tuple[sp.Expr, ...]
    # (symbol, expression) in order: each assembly root D = sqrt(radicand), and the cosine and
    # sine of each angle a dyad fixes, in the parameters, theta and earlier symbols
    program: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()
    theta: tuple[sp.Symbol, ...] = ()

    def diff(self, expr: sp.Expr, t: sp.Symbol) -> sp.Expr:
        """d expr / d t (t one of theta), the program's symbols followed by the chain rule."""
        if not self.program:
            return expr.diff(t)
        return _partial(expr, t, self._rates()[t])

    def _rates(self) -> dict:
        if "rates" not in self.__dict__:
            rates = {}
            for t in self.theta:
                rates[t] = {}
                for symbol, value in self.program:
                    if isinstance(value, sp.Pow) and value.exp == sp.S.Half:   # D = sqrt(R)
                        rate = _partial(value.base, t, rates[t]) / (2 * symbol)
                    else:
                        rate = _partial(value, t, rates[t])
                    rates[t][symbol] = rate
            object.__setattr__(self, "rates", rates)
        return self.__dict__["rates"]

    def written_out(self, exprs) -> list[sp.Expr]:
        """Expressions with the program's symbols written out."""
        return written_out(self.program, exprs)

    def along(self, expr: sp.Expr) -> sp.Expr:
        """expr (in every coordinate) in the independent ones."""
        expr = sp.sympify(expr)
        if self.trig:   # cos and sin of a sum hold a solved angle's own cos and sin
            expr = expand_angle_sums(expr, self.coords).xreplace(self.trig)
        return expr.xreplace(self.values)


def _partial(expr: sp.Expr, t: sp.Symbol, rates: dict) -> sp.Expr:
    result = expr.diff(t)
    for symbol, rate in rates.items():
        if expr.has(symbol):
            result += expr.diff(symbol) * rate
    return result


@dataclass
class _Elimination:
    mechanism: Mechanism
    coords: tuple[sp.Symbol, ...]
    unknown: list[sp.Symbol]
    values: dict
    trig: dict
    roots: list          # (sign symbol, radicand, the coordinate's name)
    program: list        # (symbol, expression) in order

    def current(self, expr: sp.Expr) -> sp.Expr:
        if self.trig:   # cos and sin of a sum hold a solved angle's own cos and sin
            expr = expand_angle_sums(expr, self.coords).xreplace(self.trig)
        return expr.xreplace(self.values)

    def is_zero(self, expr: sp.Expr) -> bool:
        """Whether expr vanishes identically: by simplify while it holds no square root (fast
        there), else numerically at 30 digits at points of the box where it is real (simplify
        takes minutes on a dyad's closed form, and seldom proves it)."""
        if expr == 0:
            return True
        if not self.program or not expr.has(*(s for s, _ in self.program)):
            return sp.simplify(expr) == 0
        if self.left(expr):   # an unknown left: not zero (nor can it be evaluated)
            return False
        return _vanishes(self.mechanism, written_out(self.program, [expr])[0],
                         [s for s, _, _ in self.roots])

    def left(self, eq: sp.Expr) -> list[sp.Symbol]:
        return [u for u in self.unknown if u not in self.values and eq.has(u)]

    def linear(self, eq: sp.Expr, u: sp.Symbol) -> sp.Expr | None:
        """u's coefficient if eq is linear in u alone with it free of every unknown."""
        c = eq.diff(u)
        return c if c != 0 and not c.has(*self.unknown) else None

    def circular(self, eq: sp.Expr, u: sp.Symbol) -> tuple[sp.Expr, sp.Expr, sp.Expr] | None:
        """(P, Q, rest) with eq = P cos(u) + Q sin(u) + rest, P, Q free of every unknown and
        rest free of u; None if eq is not of that form."""
        C, S = sp.Dummy("C"), sp.Dummy("S")
        held = sp.expand(expand_angle_sums(eq, self.coords).xreplace({sp.cos(u): C,
                                                                       sp.sin(u): S}))
        if held.has(u):
            return None
        P, Q = held.diff(C), held.diff(S)
        rest = sp.expand(held - P * C - Q * S)
        if P.has(C, S, *self.unknown) or Q.has(C, S, *self.unknown) or rest.has(C, S):
            return None
        return P, Q, rest

    def set_angle(self, u: sp.Symbol, c: sp.Expr, s: sp.Expr) -> None:
        """cos u = c and sin u = s, as the program's symbols C_u and S_u."""
        C, S = (sp.Symbol(f"{k}_{u.name}", real=True) for k in "CS")
        self.program += [(C, _tidy(c, self.theta)), (S, _tidy(s, self.theta))]
        self.trig |= {sp.cos(u): C, sp.sin(u): S}
        self.values = {k: v.xreplace({sp.cos(u): C, sp.sin(u): S}) for k, v in
                       self.values.items()} | {u: sp.atan2(S, C)}

    @property
    def theta(self) -> list[sp.Symbol]:
        return [sp.Symbol(n, real=True) for n in self.mechanism.independents]

    def from_line(self, u: sp.Symbol, P: sp.Expr, Q: sp.Expr, W: sp.Expr) -> None:
        """(cos u, sin u) on the line P C + Q S = W and the unit circle: an assembly root."""
        P, Q, W = (_tidy(x, self.theta) for x in (P, Q, W))
        sigma = sp.Symbol(f"sigma_{u.name}", real=True)
        radicand = _tidy(sp.expand(P**2 + Q**2 - W**2), self.theta)
        D = sp.Symbol(f"D_{u.name}", nonnegative=True)
        self.program.append((D, sp.sqrt(radicand)))
        norm = P**2 + Q**2
        self.roots.append((sigma, radicand, u.name))
        self.set_angle(u, (P * W - sigma * Q * D) / norm, (Q * W + sigma * P * D) / norm)


def solve_closures(mechanism: Mechanism, coords: tuple[sp.Symbol, ...],
                   constraints: list[sp.Expr]) -> Closure:
    """Every dependent coordinate in the independent ones (see the module docstring);
    ModelError naming the unknowns left where the constraints are of none of its kinds."""
    independent = {sp.Symbol(n, real=True) for n in mechanism.independents}
    unknown = sorted((c for c in coords if c not in independent), key=lambda c: c.name)
    work = _Elimination(mechanism, coords, unknown, {}, {}, [], [])
    pending = list(constraints)
    while True:
        eqs = [e for e in (work.current(c) for c in pending)
               if not work.is_zero(e)]   # redundant once the rest is known
        if not eqs:
            break
        used = _step(work, eqs)
        if used is None:
            left = [u.name for u in unknown if u not in work.values]
            raise ModelError(
                f"{mechanism.name}: a mechanism with several independent coordinates needs "
                "its constraints solvable one unknown or one dyad at a time (a constraint "
                "linear in one unknown; or in the cosine and sine of one angle; a pair of them "
                "in two angles, or an angle and a slider): "
                + (f"{', '.join(left)} cannot be solved that way" if left
                   else "a constraint is left over once every coordinate is solved"))
        pending = [e for i, e in enumerate(eqs) if i not in used]
    missing = [u.name for u in unknown if u not in work.values]
    if missing:
        raise ModelError(f"{mechanism.name}: no constraint fixes {', '.join(missing)}")
    signs = _assembly_signs(work)
    return Closure(tuple(coords), work.values, work.trig,
                   tuple(r.xreplace(signs) for _, r, _ in work.roots),
                   tuple((s, v.xreplace(signs)) for s, v in work.program), tuple(work.theta))


def _step(work: _Elimination, eqs: list[sp.Expr]) -> set[int] | None:
    """Solves one unknown (or the first angle of a dyad); the equations it used up."""
    lefts = [work.left(e) for e in eqs]
    for i, (eq, left) in enumerate(zip(eqs, lefts)):      # linear in one unknown
        if len(left) == 1 and (c := work.linear(eq, left[0])) is not None:
            u = left[0]
            value = u - eq / c
            value = (sp.simplify(value) if not work.program
                     else _tidy(sp.together(value), work.theta))
            work.values = {k: v.xreplace({u: value}) for k, v in work.values.items()} | {
                u: value}
            return {i}
    singles = [(i, left[0]) for i, left in enumerate(lefts) if len(left) == 1]
    for (i, u), (j, v) in itertools.combinations(singles, 2):   # two lines in one angle
        if u == v and (a := work.circular(eqs[i], u)) and (b := work.circular(eqs[j], u)):
            det = sp.expand(a[0] * b[1] - a[1] * b[0])
            if not work.is_zero(det):
                c = (-a[2] * b[1] + a[1] * b[2]) / det
                s = (-a[0] * b[2] + a[2] * b[0]) / det
                work.set_angle(u, c, s)
                return {i, j}
    for i, u in singles:                                       # one line in one angle
        if (a := work.circular(eqs[i], u)) is not None:
            work.from_line(u, a[0], a[1], -a[2])
            return {i}
    for i, j in itertools.combinations(range(len(eqs)), 2):   # a dyad
        pair = sorted(set(lefts[i]) | set(lefts[j]), key=lambda s: s.name)
        if len(pair) == 2 and set(lefts[i]) == set(lefts[j]) == set(pair):
            for u, v in (pair, pair[::-1]):
                if _dyad(work, eqs[i], eqs[j], u, v):
                    return set()   # both equations stay: they give v next
    return None


def _dyad(work: _Elimination, e1: sp.Expr, e2: sp.Expr, u: sp.Symbol, v: sp.Symbol) -> bool:
    """u from the dyad e1, e2 in u and v (v an angle, or a linear unknown), if of that kind."""
    if work.circular(e1, u) is None or work.circular(e2, u) is None:
        return False
    c1, c2 = work.linear(e1, v), work.linear(e2, v)
    if c1 is not None and c2 is not None and not e1.diff(v).has(v):   # v slides
        line = work.circular(sp.expand(e1 * c2 - e2 * c1), u)
        if line is None or (line[0] == 0 and line[1] == 0):
            return False
        work.from_line(u, line[0], line[1], -line[2])
        return True
    a, b = work.circular(e1, v), work.circular(e2, v)
    if a is None or b is None:
        return False
    det = sp.expand(a[0] * b[1] - a[1] * b[0])
    if work.is_zero(det):
        return False
    C, S = sp.Dummy("C"), sp.Dummy("S")   # v's cosine and sine as affine functions of u's
    r1, r2 = (r.xreplace({sp.cos(u): C, sp.sin(u): S}) for r in (a[2], b[2]))
    cv, sv = (-r1 * b[1] + a[1] * r2) / det, (-a[0] * r2 + r1 * b[0]) / det
    circle = sp.expand(sp.numer(sp.together(cv**2 + sv**2 - 1)))
    k = circle.coeff(C, 2).coeff(S, 0)
    if not work.is_zero(sp.expand(k - circle.coeff(S, 2).coeff(C, 0))) or not work.is_zero(
            circle.coeff(C, 1).coeff(S, 1)) or k == 0:
        return False
    line = sp.expand(circle - k * (C**2 + S**2 - 1))   # the radical line P C + Q S - W
    P, Q = line.coeff(C, 1).coeff(S, 0), line.coeff(S, 1).coeff(C, 0)
    W = -line.coeff(C, 0).coeff(S, 0)
    if line.has(C**2) or (P == 0 and Q == 0):
        return False
    work.from_line(u, P, Q, W)
    return True


def _tidy(expr: sp.Expr, theta: list[sp.Symbol]) -> sp.Expr:
    """expr with sin^2 t + cos^2 t = 1 used for each independent angle t, and factored while
    small (see algebra.reduce_trig)."""
    for t in theta:
        if expr.has(sp.cos(t), sp.sin(t)):
            expr = reduce_trig(expr, t)
    return expr


def _box_points(mechanism: Mechanism, count: int, seed: int) -> tuple[dict, np.ndarray]:
    """The example parameters, and ``count`` points drawn over the box of the ranges."""
    example = {p.symbol: sp.sympify(p.example_value) for p in mechanism.parameters}
    centres = np.array([float(sp.sympify(c).xreplace(example)) for c in mechanism.centres])
    rng = np.random.default_rng(seed)
    return example, centres + rng.uniform(-np.pi, np.pi, (count, len(centres)))


def _vanishes(mechanism: Mechanism, expr: sp.Expr, sigmas: list[sp.Symbol]) -> bool:
    """expr ~ 0 (relative to its terms, at 30 digits) at every one of several points of the
    box where it is real, at the example parameters and every root's sign +1."""
    theta = [sp.Symbol(n, real=True) for n in mechanism.independents]
    example, points = _box_points(mechanism, 60, 11)
    held = expr.xreplace(example).xreplace({s: 1 for s in sigmas})
    terms = sp.Add.make_args(held)
    f = sp.lambdify(theta, [held, *terms], "mpmath")
    real = 0
    with mpmath.workdps(30):
        for point in points:
            values = f(*(mpmath.mpf(float(x)) for x in point))
            if any(isinstance(v, mpmath.mpc) and v.imag != 0 for v in values):
                continue
            values = [mpmath.re(v) for v in values]
            if abs(values[0]) > mpmath.mpf("1e-20") * (1 + max(abs(v) for v in values[1:])):
                return False
            real += 1
            if real == 6:
                return True
    return False


def _assembly_signs(work: _Elimination) -> dict:
    """Each root's sign: the one combination under which every declared assembly mode is
    positive wherever the mechanism is assembled (see the module docstring)."""
    if not work.roots:
        return {}
    m = work.mechanism
    names = ", ".join(name for _, _, name in work.roots)
    if not m.assembly_modes:
        raise ModelError(
            f"{m.name}: {names} {'is' if len(work.roots) == 1 else 'are'} fixed by a dyad, "
            "which closes in two assembly modes: declare assembly_modes=(expression, ...), "
            "each positive in the mode you mean (e.g. the cross product of two of its bars)")
    freezer = m.freezer()
    conditions = written_out(work.program, [
        expand_angle_sums(sp.sympify(c).subs(freezer), work.coords)
        .xreplace(work.trig).xreplace(work.values) for c in m.assembly_modes])
    theta = [sp.Symbol(n, real=True) for n in m.independents]
    sigmas = [s for s, _, _ in work.roots]
    example, points = _box_points(m, SAMPLES, 7)
    args = [*theta, *sigmas]

    def numeric(exprs):
        return sp.lambdify(args, [sp.sympify(e).xreplace(example) for e in exprs], "numpy")

    radicands = numeric(written_out(work.program, [r for _, r, _ in work.roots]))
    held = numeric(conditions)
    fits = []
    for signs in itertools.product((1.0, -1.0), repeat=len(sigmas)):
        assembled = decided = 0
        good = True
        with np.errstate(all="ignore"):
            for point in points:
                if not np.all(np.array(radicands(*point, *signs), dtype=float) >= 0):
                    continue
                assembled += 1
                values = np.array(held(*point, *signs), dtype=float)
                scale = 1 + np.abs(values).max()
                if np.any(np.abs(values) <= MARGIN * scale) or not np.all(np.isfinite(values)):
                    continue
                decided += 1
                good &= bool(np.all(values > 0))
        if good and decided:
            fits.append(signs)
    if len(fits) != 1:
        raise ModelError(
            f"{m.name}: the declared assembly_modes "
            + ("hold in no assembly mode of " if not fits else "do not tell the assembly modes of ")
            + f"{names} apart over the box of the ranges at the example parameters: declare "
            "expressions that are positive in exactly one of its modes")
    return dict(zip(sigmas, (sp.Integer(int(s)) for s in fits[0])))
