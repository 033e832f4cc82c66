"""Table 1 step 7 (position analysis): the dependent coordinates in closed form, with branches.

The position constraints of a planar loop mechanism hold each unknown coordinate in one of
three ways, and each is turned into a linear unknown:
- a plain coordinate (a slider's x) is already linear;
- a polar pair (length, angle), both unknown, enters as length*cos and length*sin: with
  X = length cos(angle), Y = length sin(angle) it is linear, and length = sqrt(X^2 + Y^2),
  a *length* root (only the positive sign is physical);
- an angle of known length enters as cos(angle) and sin(angle): with C, S for them it is
  linear, plus the unit-circle equation C^2 + S^2 = 1.
Linear elimination leaves some unit pairs free. Each free pair meets one line
P C + Q S = W (a solved equation of its own pair, or a solved pair's unit circle minus a
multiple of its own, which cancels the quadratic terms: two circles give their radical
line), so (C, S) = (P W - sigma Q D, Q W + sigma P D) / (P^2 + Q^2) with
D = sqrt(P^2 + Q^2 - W^2): an *assembly-mode* root. Where P^2 + Q^2 - W^2 < 0 the
mechanism cannot be assembled. The sign sigma is the model's declared assembly mode: the
one for which its mode conditions hold.
"""
from __future__ import annotations

import itertools
import random
from dataclasses import dataclass, replace

import sympy as sp

from ..model import Mechanism
from .algebra import TIDY_LIMIT, expand_angle_sums, reduce_trig, tidy


@dataclass(frozen=True)
class Root:
    """sqrt(radicand) in the closed form; ``kind`` is 'assembly' or 'length'."""

    symbol: sp.Symbol       # stands for the non-negative root in ``positions``
    radicand: sp.Expr       # in theta and the parameters (and earlier roots' symbols)
    kind: str
    coordinate: str         # the coordinate whose solution introduced it
    # an assembly root's share of the model's assembly-mode conditions (those its sign
    # decides), in the root symbols: each positive in the declared mode, where this root is
    # +sqrt(radicand); the library evaluates them at run time on each mode
    conditions: tuple[sp.Expr, ...] = ()
    # P^2 + Q^2 + W^2 of an assembly root's radicand P^2 + Q^2 - W^2: the size its rounding
    # is measured against, without expanding a chain's large radicand (None: expand it)
    scale: sp.Expr | None = None
    # the index of each of ``conditions`` in the model's assembly_modes
    condition_sources: tuple[int, ...] = ()


@dataclass(frozen=True)
class Definition:
    """A named intermediate value of a chain of dyads: the cosine or sine of an angle a later
    dyad is driven by, kept a symbol so that the later dyad's closed form stays small."""

    symbol: sp.Symbol
    expr: sp.Expr           # in theta, the parameters and earlier roots' and values' symbols
    after: int              # how many roots precede it (its expr uses those)


def in_order(roots, definitions) -> list:
    """Roots and definitions in the order each may use the ones before it."""
    steps: list = []
    for i, root in enumerate(roots):
        steps += [d for d in definitions if d.after == i] + [root]
    return steps + [d for d in definitions if d.after >= len(roots)]


def write_out(expr, roots, definitions=(), signs=None):
    """expr with every root symbol replaced by signs[i] sqrt(radicand) (+ without signs) and
    every definition by its value, innermost last (nested as needed). A chain of dyads (with
    definitions) is not written out: its expressions stay in the symbols of its branch's
    straight-line program (branch_program), which the library computes once per angle;
    written out, they are too large to print or check in reasonable time."""
    if definitions:
        signs = signs or (1,) * len(roots)
        names = _program_names(roots, definitions, signs)
        return expr.xreplace(_program_symbols(roots, names, signs))
    flip = {r.symbol: s * r.symbol for r, s in zip(roots, signs)} if signs else {}
    result = expr.xreplace(flip)
    for step in reversed(in_order(roots, definitions)):
        value = (sp.sqrt(step.radicand.xreplace(flip)) if isinstance(step, Root)
                 else step.expr.xreplace(flip))
        result = result.xreplace({step.symbol: value})
    return result


def _program_names(roots, definitions, signs) -> dict:
    """Each root and definition symbol -> its name in one branch's program: a step's value
    depends on the signs of the roots before it, which its name spells (NAME_pm for +, -;
    the steps before any root keep their names)."""
    names, before = {}, ""
    for step in in_order(roots, definitions):
        names[step.symbol] = sp.Symbol(f"{step.symbol.name}_{before}" if before
                                       else step.symbol.name, **step.symbol.assumptions0)
        if isinstance(step, Root):
            before += "p" if signs[len(before)] > 0 else "m"
    return names


def _program_symbols(roots, names, signs) -> dict:
    """Each root and definition symbol -> what stands for it on one branch (its program's
    name; a root taken negative there: minus it)."""
    return names | {r.symbol: s * names[r.symbol] for r, s in zip(roots, signs)}


def branch_program(roots, definitions, signs=None) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
    """A chain's roots and definitions on one branch (signs of the roots; all positive
    without) as a straight-line program: (symbol, value in earlier symbols) in order, each
    root the non-negative sqrt of its radicand, its sign carried where it is used."""
    signs = signs or (1,) * len(roots)
    names = _program_names(roots, definitions, signs)
    symbols = _program_symbols(roots, names, signs)
    return tuple((names[step.symbol],
                  sp.sqrt(step.radicand.xreplace(symbols)) if isinstance(step, Root)
                  else step.expr.xreplace(symbols))
                 for step in in_order(roots, definitions))


#: A chain's slopes in more symbols than this are not factored (see PositionSolution.slope).
FACTOR_SYMBOLS = 10


@dataclass(frozen=True)
class PositionSolution:
    theta: sp.Symbol
    coords: tuple[sp.Symbol, ...]
    positions: sp.Matrix            # q(theta), with root symbols
    roots: tuple[Root, ...]         # in order: a root's radicand uses only earlier roots
    trig: dict                      # cos/sin of each dependent angle, with root symbols
    # the parameter sets the model allows (its requirements), where a sign is decided
    requirements: tuple[sp.Basic, ...] = ()
    definitions: tuple[Definition, ...] = ()   # a chain of dyads' intermediate values

    def substitute(self, expr: sp.Expr) -> sp.Expr:
        """An expression of the coordinates as a function of theta and the root symbols:
        cos and sin of dependent angles from the closed form (never cos(atan2(..)))."""
        angles = {a.args[0] for a in self.trig}
        expr = expand_angle_sums(expr, self.coords)
        for root in expr.atoms(sp.Pow):   # a distance: sin^2 + cos^2 = 1 for every angle
            if root.exp == sp.S.Half:
                radicand = root.base
                for angle in angles:
                    radicand = reduce_trig(radicand, angle)
                if sp.sqrt(radicand).has(sp.Abs):   # factored to u^2: keep a root, not |u|
                    radicand = sp.expand(radicand)
                expr = expr.xreplace({root: sp.sqrt(radicand)})
        return expr.xreplace(self.trig).xreplace(dict(zip(self.coords, self.positions)))

    def with_length_roots(self, expr: sp.Expr) -> tuple["PositionSolution", sp.Expr]:
        """Every square root left in expr (a distance of the model) becomes a length root."""
        roots = list(self.roots)
        for radicand in sorted({a.base for a in expr.atoms(sp.Pow) if a.exp == sp.S.Half},
                               key=sp.default_sort_key):
            # sqrt(n / (s^2 d)) = sqrt(n d s^2) / (s^2 d) for d > 0 and any sign of s: the
            # root's radicand stays a polynomial. (sqrt(n d) / (s d) would take |s| = s,
            # the length of the other sign wherever s < 0.)
            n, den = sp.fraction(sp.together(radicand))
            if not den.has(self.theta):
                n, den = radicand, sp.S.One
            coefficient, factors = sp.factor_list(den)
            square = sp.Mul(*(f ** (e // 2) for f, e in factors))
            odd = coefficient * sp.Mul(*(f ** (e % 2) for f, e in factors))
            if den.has(self.theta) and not self._positive(odd, roots):
                unknown = [f for f, e in factors if e % 2 and not self._positive(f, roots)]
                raise NotSolvable(
                    f"cannot tell the sign of {' * '.join(map(str, unknown)) or odd} in a "
                    "length's denominator: declare requirements that make it positive for "
                    "every parameter set (e.g. Requirement(a > 0, ...) for a length a)")
            inside = n * odd * square**2
            known = next((r for r in roots if sp.expand(r.radicand - inside) == 0), None)
            if known is None:
                known = Root(sp.Symbol(f"rho_{len(roots) + 1}", positive=True),
                             sp.factor(inside), "length", "")
                roots.append(known)
            expr = expr.xreplace({sp.sqrt(radicand): known.symbol / (square**2 * odd)})
        return PositionSolution(self.theta, self.coords, self.positions, tuple(roots),
                                self.trig, self.requirements, self.definitions), expr

    def _positive(self, expr: sp.Expr, roots) -> bool:
        return _positive_on_samples(expr, self.theta, [*roots, *self.definitions],
                                    self.requirements)

    @property
    def steps(self) -> list:
        """The roots and definitions in order (see in_order)."""
        return in_order(self.roots, self.definitions)

    def derivative(self, expr: sp.Expr) -> sp.Expr:
        """d/dtheta of an expression in theta and root symbols: d rho/dtheta = R'/(2 rho),
        a definition's by the chain rule."""
        rates: dict[sp.Symbol, sp.Expr] = {}
        for step in self.steps:
            rates[step.symbol] = (self._partial(step.radicand, rates) / (2 * step.symbol)
                                  if isinstance(step, Root) else self._partial(step.expr, rates))
        return self._partial(expr, rates)

    def slope(self, expr: sp.Expr) -> sp.Expr:
        """d/dtheta of expr, factored (tidy), except a chain's slope in more than
        FACTOR_SYMBOLS symbols, which is only cancelled, and kept as derived where that makes
        it larger: factoring a collar on a slotted lever's slopes (11 and 12 symbols) wrote
        each as one fraction eight times its size and took minutes."""
        rate = self.derivative(expr)
        if not self.definitions or len(rate.free_symbols) <= FACTOR_SYMBOLS:
            return tidy(rate)
        cancelled = tidy(rate, sp.cancel)
        return cancelled if sp.count_ops(cancelled) <= sp.count_ops(rate) else rate

    def _partial(self, expr, rates):
        result = expr.diff(self.theta)
        for symbol, rate in rates.items():
            if expr.has(symbol):
                result += expr.diff(symbol) * rate
        return result

    @property
    def substitution(self) -> dict:
        """Root symbols -> sqrt of their radicands, innermost first (apply in order)."""
        return {r.symbol: sp.sqrt(r.radicand) for r in self.roots}

    def explicit(self, expr):
        """expr with every root symbol replaced by its square root and every definition by
        its value (nested as needed)."""
        return write_out(expr, self.roots, self.definitions)


def _positive_on_samples(expr, theta, roots, requirements=()) -> bool:
    """expr > 0 at random angles and parameter sets of either sign that meet every
    requirement (a sum of squares, typically): a sign the model does not guarantee is not
    assumed. A chain's definitions (the cosine and sine of a driving angle: C_x, S_x) are
    sampled as the cosine and sine of any angle, which they are."""
    angles = {}
    for step in roots:
        if isinstance(step, Definition) and step.symbol in expr.free_symbols:
            name = step.symbol.name
            angle = angles.setdefault(name[2:], sp.Dummy(f"angle_{name[2:]}"))
            expr = expr.xreplace({step.symbol: (sp.cos if name[0] == "C" else sp.sin)(angle)})
    if expr.free_symbols & {r.symbol for r in roots}:
        return False
    rng = random.Random(1)
    own = expr.free_symbols - {theta} - set(angles.values())
    conditions = [c for c in requirements if c.free_symbols & own]
    symbols = sorted(own.union(*(c.free_symbols for c in conditions)), key=sp.default_sort_key)
    f = sp.lambdify([theta, *symbols, *angles.values()], expr)
    allowed = sp.lambdify(symbols, sp.And(*conditions)) if conditions else None
    checked = 0
    for _ in range(2000):
        values = [rng.choice((-1, 1)) * rng.uniform(0.1, 2.0) for _ in symbols]
        if allowed is not None and not bool(allowed(*values)):
            continue
        if not f(rng.uniform(-3.2, 3.2), *values,
                 *(rng.uniform(-3.2, 3.2) for _ in angles)) > 0:
            return False
        checked += 1
        if checked == 200:
            return True
    return checked > 0


class NotSolvable(ValueError):
    """The constraints are not of the closed-form kind described in the module docstring."""


def _trig_atoms(expr, angle):
    return {a for a in expr.atoms(sp.cos, sp.sin) if a.args[0] == angle}


def solve_positions(mechanism: Mechanism, coords: tuple[sp.Symbol, ...],
                    constraints: sp.Matrix) -> PositionSolution:
    names = [c.name for c in mechanism.coordinates]
    sym = dict(zip(names, coords))
    theta = sym[mechanism.independent]
    declared, names = names, sorted(names)   # the declaration's order never changes the result
    eqs = [sp.expand(expand_angle_sums(e, coords)) for e in constraints]
    polar = {length: angle for length, angle in mechanism.polar_pairs}
    polar_angles = set(polar.values())
    linear: dict[str, sp.Symbol] = {}        # coordinate -> its linear unknown
    pairs: dict[str, tuple[sp.Symbol, sp.Symbol]] = {}  # angle -> (C, S) or (X, Y)
    unit_pairs: list[str] = []
    for name in names:
        if name == mechanism.independent or name in polar_angles:
            continue
        s = sym[name]
        if name in polar:
            ang = sym[polar[name]]
            X, Y = sp.Symbol(f"X_{name}", real=True), sp.Symbol(f"Y_{name}", real=True)
            eqs = [sp.expand(e.subs({sp.cos(ang): X / s, sp.sin(ang): Y / s})) for e in eqs]
            pairs[polar[name]] = (X, Y)
        elif any(_trig_atoms(e, s) for e in eqs):
            C, S = sp.Symbol(f"C_{name}", real=True), sp.Symbol(f"S_{name}", real=True)
            eqs = [e.subs({sp.cos(s): C, sp.sin(s): S}) for e in eqs]
            pairs[name] = (C, S)
            unit_pairs.append(name)
        else:
            linear[name] = s
    unknowns = list(linear.values()) + [v for p in pairs.values() for v in p]
    eqs, staged = _stage_polar_angles(eqs, polar, sym, pairs)
    polar_symbols = {sym[n] for n in polar}
    nonlinear = [e for e in eqs if not unknowns or not sp.Poly(e, *unknowns).is_linear
                 or e.free_symbols & polar_symbols]
    if any(e.free_symbols & polar_symbols for e in nonlinear):
        raise NotSolvable(_not_linear(nonlinear[0], unknowns, sym, pairs, polar))
    if nonlinear:   # a slide carried by a link a dyad before it moves (PRR): in two stages
        known, roots, angles, definitions = _solve_in_stages(
            mechanism, sym, theta, eqs, nonlinear, linear, pairs, unit_pairs, polar)
    else:
        known, roots, angles, definitions = _solve_angles(mechanism, sym, theta, eqs, linear,
                                                          pairs, unit_pairs, staged)
        slots = {v for n in polar.values() if n not in staged for v in pairs[n]}
        if slots - set(known):   # a slot driven by a point a dyad moves: after that dyad
            known, roots, angles, definitions = _solve_in_stages(
                mechanism, sym, theta, eqs, [e for e in eqs if e.free_symbols & slots],
                linear, pairs, unit_pairs, polar)
    known = _well_conditioned(known, list(linear.values()), eqs, theta)
    result = []
    for name in declared:
        s = sym[name]
        if name == mechanism.independent:
            result.append(s)
        elif name in linear:
            result.append(known.get(s, s))
        elif name in polar:
            X, Y = pairs[polar[name]]
            early = next((r.symbol for r in roots if r.coordinate == name), None)
            if early is None:
                if X not in known or Y not in known:
                    raise NotSolvable(f"the slot of {name}, {polar[name]} is driven by a "
                                      "point whose position needs another dyad's closed "
                                      "form: not supported yet")
                early = sp.Symbol(f"rho_{len(roots) + 1}", positive=True)
                # kept a sum of squares: accurate where the length is small (no cancellation)
                roots.append(Root(early, known[X] ** 2 + known[Y] ** 2, "length", name))
            result.append(early)
        else:
            x, y = angles.get(name, (known[pairs[name][0]], known[pairs[name][1]]))
            result.append(sp.atan2(y, x))
    trig = {}
    defined = {d.symbol for d in definitions}
    for name, (A, B) in pairs.items():
        x, y = angles.get(name, (known[A], known[B]))
        if name in staged:        # cos and sin as the program's steps C_angle, S_angle
            x, y = staged[name][:2]
        elif name in polar_angles:  # cos = X / length, sin = Y / length
            length = next(r.symbol for r in roots if r.coordinate == next(
                l for l, a in polar.items() if a == name))
            x, y = x / length, y / length
        elif name in angles:      # (C, S) as solved (a chain's: their symbols), not the
            x, y = (A, B) if A in defined else (known[A], known[B])   # atan2 numerators
        trig[sp.cos(sym[name])], trig[sp.sin(sym[name])] = x, y
    solution = PositionSolution(theta, tuple(coords), sp.Matrix(result), tuple(roots), trig,
                                tuple(sp.sympify(r.condition).xreplace(mechanism.freezer())
                                      for r in mechanism.requirements), tuple(definitions))
    return _conditions_on_positions(solution, mechanism)


def _conditions_on_positions(solution: PositionSolution, mechanism: Mechanism
                             ) -> PositionSolution:
    """Each assembly root's conditions written on the solution's positions. While solving,
    they were written on the elimination's values, which may divide by a function of theta
    that vanishes (a collar's distance from one component of its bar's direction, 0/0 at
    theta = pi): there the library could not tell the modes apart. The positions are well
    conditioned (_well_conditioned), and so are conditions written on them."""
    frozen = mechanism.freezer()
    roots = tuple(replace(r, conditions=tuple(
        solution.substitute(sp.sympify(mechanism.assembly_modes[k]).subs(frozen))
        for k in r.condition_sources)) if r.conditions else r for r in solution.roots)
    return replace(solution, roots=roots)


def _not_linear(e, unknowns, sym, pairs, polar) -> str:
    """Why a constraint cannot be solved by elimination, in the user's symbols."""
    back = {}
    for name, (u, v) in pairs.items():
        length = next((sym[n] for n, a in polar.items() if a == name), sp.S.One)
        back |= {u: length * sp.cos(sym[name]), v: length * sp.sin(sym[name])}
    products = [t for t in sp.Add.make_args(e)
                if sum(sp.degree(t, u) for u in unknowns if t.has(u)) > 1]
    shown = [sp.sympify(t).xreplace(back) for t in products[:1]] or [e.xreplace(back)]
    return (f"the constraint {sp.sympify(e).xreplace(back)} = 0 has the term {shown[0]}, "
            "a product of two unknown positions that solving the other dyads first does not "
            "make linear (a slide carried by a slotted lever's link): not supported yet")


def _well_conditioned(known: dict, linear: list, eqs: list, theta: sp.Symbol) -> dict:
    """The linear unknowns from the normal equations A^T A u = A^T b of the constraints, once
    every angle is solved, where the elimination left one divided by a function of theta: a
    collar's distance along a bar at angle theta, solved from one component, is 0/0 where
    that component's coefficient vanishes; its projection on the bar is exact everywhere."""
    if not linear or not any(sp.fraction(sp.together(known.get(u, u)))[1].has(theta)
                             for u in linear):
        return known
    rows = [sp.expand(e.xreplace({v: x for v, x in known.items() if v not in linear}))
            for e in eqs]
    A = sp.Matrix([[row.coeff(u) for u in linear] for row in rows])
    b = sp.Matrix([-row.xreplace({u: 0 for u in linear}) for row in rows])
    normal = (A.T * A).applyfunc(lambda x: reduce_trig(x, theta))
    if normal.free_symbols & set(linear) or reduce_trig(normal.det(), theta) == 0:
        return known
    solved = normal.LUsolve(A.T * b)
    return known | {u: reduce_trig(sp.together(x), theta) for u, x in zip(linear, solved)}


def _stage_polar_angles(eqs, polar, sym, pairs):
    """A polar pair's angle in a constraint at another distance than its length (a slotted
    lever whose tip drives a link) enters as X/length: the constraint is not linear. There
    its cosine and sine become symbols C_angle, S_angle, steps of the program once the pair's
    own loop gives X, Y and the length (``_solve_free_pairs``). (eqs, {angle: (C, S, length
    name)}) of the constraints so staged; the rest unchanged."""
    staged = {}
    out = []
    for e in eqs:
        lengths = [n for n in polar if sym[n] in e.free_symbols]
        for name in lengths:
            angle, length = polar[name], sym[name]
            X, Y = pairs[angle]
            C, S = sp.Symbol(f"C_{angle}", real=True), sp.Symbol(f"S_{angle}", real=True)
            staged_e = sp.expand(e.subs({X: C * length, Y: S * length}))
            if length not in staged_e.free_symbols:
                staged[angle] = (C, S, name)
                e = staged_e
        out.append(e)
    return out, staged


def _solve_in_stages(mechanism, sym, theta, eqs, nonlinear, linear, pairs, unit_pairs, polar):
    """The constraints that multiply two unknowns (a collar's distance along a link times
    the link's cosine) wait until the dyads of the others are solved: those dyads' cosines
    and sines, kept symbols of the program, are then known, and what waits is linear in
    the rest (one more dyad, solved after them)."""
    first = [e for e in eqs if e not in nonlinear]

    def unknowns_of(group):
        found = set().union(*(e.free_symbols for e in group))
        return ({n: u for n, u in linear.items() if u in found},
                {n: p for n, p in pairs.items() if set(p) & found})

    linear_a, pairs_a = unknowns_of(first)
    waiting = set().union(*(e.free_symbols for e in nonlinear))
    keep = {n for n, p in pairs_a.items() if set(p) & waiting}
    if not keep or any(n in polar.values() for n in pairs_a) or not first:
        raise NotSolvable(_not_linear(nonlinear[0], [*linear.values(),
                                                     *(v for p in pairs.values() for v in p)],
                                      sym, pairs, polar))
    known, roots, angles, definitions = _solve_angles(
        mechanism, sym, theta, first, linear_a, pairs_a, [n for n in unit_pairs if n in pairs_a],
        keep=keep)
    # the cosines and sines the waiting constraints hold, steps of the program (a pivot of
    # the elimination, solved from its dyad's other pair, is not one yet)
    definitions = list(definitions) + [
        Definition(v, known[v], len(roots)) for n in sorted(keep) for v in pairs[n]
        if v not in {d.symbol for d in definitions}]
    program = {d.symbol for d in definitions}
    given = {u: v for u, v in known.items() if u not in program}
    later = [sp.expand(e.xreplace(given)) for e in nonlinear]
    linear_b = {n: u for n, u in linear.items() if n not in linear_a}
    pairs_b = {n: p for n, p in pairs.items() if n not in pairs_a}
    rest = [*linear_b.values(), *(v for p in pairs_b.values() for v in p)]
    for e in later:
        if not rest or not sp.Poly(e, *rest).is_linear or e.free_symbols & {
                sym[n] for n in polar}:
            raise NotSolvable(_not_linear(e, rest, sym, pairs, polar))
    known_b, roots, angles_b, definitions = _solve_angles(
        mechanism, sym, theta, later, linear_b, pairs_b, [n for n in unit_pairs if n in pairs_b],
        start=(roots, definitions, known, pairs))
    return known | known_b, roots, angles | angles_b, definitions


def _solve_angles(mechanism, sym, theta, eqs, linear, pairs, unit_pairs, staged=None,
                  keep=frozenset(), start=((), (), {}, {})):
    """Every unit pair solved: (known values of the unknowns, roots, atan2 numerators).

    The linear elimination keeps some pairs (its pivots) in terms of the others, the free
    pairs; each free pair is then solved on a line (see _line_of), in the first order in
    which each has one once the pairs before it are solved. A chain of dyads (a six-bar)
    needs the pivots to be one pair of each dyad: the pairs are taken as pivots in every
    order, sorted by name first (a single loop's first order is its only one), until every
    free pair finds its line."""
    refusal = None
    for order in itertools.permutations(unit_pairs):
        pivots_first = [v for name in order for v in pairs[name]]
        unknowns = (list(linear.values()) + pivots_first
                    + [v for name, p in pairs.items() if name not in unit_pairs for v in p])
        solution = sp.linsolve(eqs, unknowns) if unknowns else {()}
        if not solution:
            raise NotSolvable("the constraints have no solution for general parameters")
        (values,) = solution
        known = {u: v for u, v in zip(unknowns, values) if v != u}
        try:
            return _solve_free_pairs(mechanism, sym, theta, known, pairs, unit_pairs, staged,
                                     keep, start)
        except NoLine as no_line:
            refusal = refusal or no_line
    raise refusal


def _solve_free_pairs(mechanism, sym, theta, known, pairs, unit_pairs, staged=None,
                      keep=frozenset(), start=((), (), {}, {})):
    """Each free pair on its line, in turn. Where pairs are still pending after one is solved
    (a chain: the next dyad is driven by this one), its cosine and sine stay symbols,
    Definitions, in the values that wait for the pending pairs: substituted, they would
    multiply the size of every later dyad's closed form. A staged polar pair's length is a
    root first, and its angle's cosine and sine definitions after it. ``keep``: pairs kept
    symbols for a later stage; ``start``: (roots, definitions, known, every pair) of an
    earlier one."""
    roots: list[Root] = list(start[0])
    definitions: list[Definition] = list(start[1])
    earlier, every_pair = start[2], start[3] or pairs
    angles = {}  # angle -> (x, y) with angle = atan2(y, x): numerators of (C, S)
    for angle, (C, S, length) in (staged or {}).items():
        X, Y = pairs[angle]
        pending_unknowns = {v for n in unit_pairs for v in pairs[n] if v not in known}
        if any(v not in known or known[v].free_symbols & pending_unknowns for v in (X, Y)):
            raise NotSolvable(f"the slot of {length}, {angle} is driven by a dyad solved after "
                              "it: not supported yet")
        rho = sp.Symbol(f"rho_{len(roots) + 1}", positive=True)
        roots.append(Root(rho, known[X] ** 2 + known[Y] ** 2, "length", length))
        definitions += [Definition(C, known[X] / rho, len(roots)),
                        Definition(S, known[Y] / rho, len(roots))]
    pending = _free_pairs(unit_pairs, pairs, known)
    while pending:
        program = {s.symbol for s in [*roots, *definitions]}
        for name in pending:
            C, S = pairs[name]
            line, centre = _line_of(C, S, name, unit_pairs, pairs, known, program)
            if line is not None:
                break
        else:
            free = {v for n in pending for v in pairs[n] if v not in known}
            loop = [n for n in unit_pairs if n in pending
                    or any(known[v].free_symbols & free for v in pairs[n])]
            raise NoLine(f"no closed form for the angle{'s' if len(loop) > 1 else ''} "
                         f"{', '.join(loop)}: each dyad (two links, or a link and a slide) "
                         "must join two known joints; a loop of more unknowns (a class-III "
                         "group) has none")
        driving = [r.coordinate for r in roots if any(x.has(r.symbol) for x in line)]
        if driving:   # an assembly root inside a line: its closed form would not stay small
            raise NotSolvable(
                f"the angle {name} belongs to a dyad driven by the dyad of {driving[0]} in a "
                "way not supported yet: its closed form grows too large to derive")
        definitions += [Definition(symbol, value, len(roots)) for symbol, value in centre]
        P, Q, W = _normalised(line, theta)
        rho = sp.Symbol(f"rho_{len(roots) + 1}", positive=True)
        sigma, conditions, sources = _declared_sign(mechanism, sym, theta, earlier | known,
                                                    every_pair, C, S, P, Q, W, rho, roots,
                                                    definitions)
        norm = reduce_trig(P**2 + Q**2, theta)
        roots.append(Root(rho, compact(P**2 + Q**2 - W**2, theta), "assembly", name,
                          conditions, norm + W**2, sources))
        solved = {C: (P * W - sigma * Q * rho) / norm, S: (Q * W + sigma * P * rho) / norm}
        later = {v for n in pending if n != name for v in pairs[n] if v not in known}
        if later or centre or name in keep or any(x.free_symbols & program for x in (P, Q, W)):
            # a dyad of a chain (driving a later one, or driven): its cosine and sine stay
            # symbols in everything solved from them, so each later value is a short form
            # of them (its interval enclosure then stays tight, too)
            definitions += [Definition(v, value, len(roots)) for v, value in solved.items()]
            known = known | solved
        else:
            known = {u: v if v.free_symbols & later else reduce_trig(v.subs(solved), theta)
                     for u, v in known.items()} | solved
        angles[name] = (P * W - sigma * Q * rho, Q * W + sigma * P * rho)
        pending = _free_pairs(unit_pairs, pairs, known)
    return known, roots, angles, definitions


def _free_pairs(unit_pairs, pairs, known):
    """Free pairs (some of C, S not determined by linear elimination), in order."""
    return [n for n in unit_pairs if any(v not in known for v in pairs[n])]


class NoLine(NotSolvable):
    """A free pair meets no line: the pivots of the elimination were not one per dyad."""


def _normalised(line, theta):
    """(P, Q, W) with trig reduced and their common factor divided out."""
    parts = [sp.fraction(sp.together(reduce_trig(x, theta))) for x in line]
    denominator = sp.lcm_list([den for _, den in parts])
    numerators = [sp.cancel(num * denominator / den) for num, den in parts]
    common = sp.gcd_list([x for x in numerators if x != 0])
    return tuple(sp.factor(x / common) for x in numerators)


def compact(expr: sp.Expr, theta: sp.Symbol) -> sp.Expr:
    """The shorter of expr factored as it stands or after reducing sin^2 + cos^2 = 1: a
    product form stays accurate near its zeros (a dyad's limit positions). One beyond
    TIDY_LIMIT operations is not factored, as reduce_trig does not factor it: SymPy's
    multivariate factorisation takes minutes on such radicands."""
    reduced = reduce_trig(expr, theta)
    if sp.count_ops(expr) > TIDY_LIMIT:
        return reduced
    return min((sp.factor(expr), reduced), key=sp.count_ops)


def _line_of(C, S, name, unit_pairs, pairs, known, program=frozenset()):
    """((P, Q, W), centre) with P C + Q S = W, from the free pair's own solved half or a
    radical line; (None, ()) where no line holds the pair yet. ``centre``: the definitions
    (symbol, value) the line is written in, where the circle it comes from is centred on a
    point an earlier dyad of a chain (``program``: its symbols) places."""
    free = {v for n in unit_pairs for v in pairs[n] if v not in known}
    for v in (C, S):
        if v in known and not (known[v].free_symbols & free):
            return ((sp.S.Zero, sp.S.One, known[v]) if v is S
                    else (sp.S.One, sp.S.Zero, known[v])), ()
    for v, w in ((C, S), (S, C)):   # the elimination left one of the pair in terms of the other
        if v in known and known[v].free_symbols & free == {w}:
            line = sp.Poly(sp.expand(v - known[v]), C, S)
            if line.total_degree() == 1:
                return (line.coeff_monomial(C), line.coeff_monomial(S),
                        -line.coeff_monomial(1)), ()
    for other in unit_pairs:
        if other == name or any(v not in known for v in pairs[other]):
            continue
        A, B = pairs[other]
        centre = _centre(name, C, S, (known[A], known[B]), program)
        x, y = (known[A], known[B]) if not centre else (
            _affine(known[A], C, S, centre[0][0]), _affine(known[B], C, S, centre[1][0]))
        circle = sp.expand(x ** 2 + y ** 2 - 1)
        if not circle.free_symbols & {C, S} or circle.free_symbols & (free - {C, S}):
            continue
        poly = sp.Poly(circle, C, S)
        lam = poly.coeff_monomial(C**2)
        is_circle = (lam != 0 and sp.expand(lam - poly.coeff_monomial(S**2)) == 0
                     and poly.coeff_monomial(C * S) == 0)
        if not is_circle:
            continue
        line = sp.Poly(sp.expand(circle - lam * (C**2 + S**2 - 1)), C, S)
        if line.total_degree() > 1:
            continue
        P, Q = line.coeff_monomial(C), line.coeff_monomial(S)
        return tuple(sp.factor(x) for x in (P, Q, -line.coeff_monomial(1))), centre
    return None, ()


def _centre(name, C, S, parts, program) -> tuple:
    """A circle (x, y) affine in (C, S), centred where a chain's earlier dyad puts a joint
    (its constant parts in that dyad's symbols): those parts as definitions U_name, V_name,
    so that the line, and the root's radicand, are short forms of them (written out, they
    are polynomials of thousands of terms whose interval enclosures overestimate ~1e3x);
    () for any other circle."""
    rests = [p.xreplace({C: 0, S: 0}) for p in parts]
    if not any(r.free_symbols & program for r in rests) or not all(
            not (p.diff(v)).free_symbols & {C, S} for p in parts for v in (C, S)):
        return ()
    return tuple((sp.Symbol(f"{letter}_{name}", real=True), rest)
                 for letter, rest in zip("UV", rests))


def _affine(part, C, S, symbol):
    """part, affine in (C, S), with its constant part named by symbol."""
    return symbol + C * part.diff(C) + S * part.diff(S)


def _polar_length(X: sp.Symbol) -> str | None:
    """The length coordinate of a polar pair's first unknown X_length (solve_positions names
    it so), None for a unit pair's cosine."""
    return X.name[2:] if X.name.startswith("X_") else None


def _declared_sign(mechanism, sym, theta, known, pairs, C, S, P, Q, W, rho, roots,
                   definitions=()):
    """(+1 or -1, conditions, their indices in assembly_modes): the sign of the root for
    which the model's assembly-mode conditions hold, and those conditions with the root taken
    as that sign times rho.

    A condition is an expression of the coordinates that is positive in the declared mode.
    It is evaluated (30 digits) at the example parameters, at angles where every radicand so
    far is positive; the answer must be the same at every such angle. (Which sign that is
    may differ for other parameters: the library checks the conditions again for each set.)"""
    import mpmath

    steps = in_order(roots, definitions)
    to_unknowns = {}
    for name, (A, B) in pairs.items():
        length = _polar_length(A)
        if length is None:   # a unit pair: (C, S) themselves
            to_unknowns[sp.cos(sym[name])], to_unknowns[sp.sin(sym[name])] = A, B
            continue
        # a polar pair, (X, Y) = length (cos, sin): the length is its root, the cosine and
        # sine the program's steps C_angle, S_angle where they are (X, Y over the length)
        rho_length = next((r.symbol for r in roots if r.coordinate == length),
                          sp.sqrt(A**2 + B**2))
        unit = {step.symbol.name: step.symbol for step in steps}
        to_unknowns[sym[length]] = rho_length
        to_unknowns[sp.cos(sym[name])] = unit.get(f"C_{name}", A / rho_length)
        to_unknowns[sp.sin(sym[name])] = unit.get(f"S_{name}", B / rho_length)
    norm = P**2 + Q**2
    sign = sp.Dummy("sign")
    cs = {C: (P * W - sign * Q * rho) / norm, S: (Q * W + sign * P * rho) / norm}
    point = {**{u: v.subs(cs) for u, v in known.items()}, **cs}
    coords = tuple(mechanism.freezer().values())
    conditions = [expand_angle_sums(sp.sympify(c).subs(mechanism.freezer()), coords)
                  .subs(to_unknowns).subs(point) for c in mechanism.assembly_modes]
    # a condition on a dyad not solved yet (its unknowns still free) is for a later sign
    decided = {theta, sign, rho, *(s.symbol for s in steps), *mechanism.symbols}
    sources = [k for k, c in enumerate(conditions)
               if c.has(sign) and c.free_symbols <= decided]
    conditions = [conditions[k] for k in sources]
    example = mechanism.example()
    names = [s.symbol for s in steps]
    args = [theta, sign] + names + [rho]
    earlier = [sp.lambdify([theta] + names[:i], (s.radicand if isinstance(s, Root) else s.expr)
                           .subs(example), "mpmath") for i, s in enumerate(steps)]
    own = sp.lambdify([theta] + names, (norm - W**2).subs(example), "mpmath")
    tests = [sp.lambdify(args, c.subs(example), "mpmath") for c in conditions]
    votes = set()
    with mpmath.workdps(30):
        for th in mpmath.linspace(-mpmath.pi, mpmath.pi, 61)[1:]:
            values = []
            for step, value in zip(steps, earlier):
                values.append(value(th, *values))
                if isinstance(step, Root):
                    values[-1] = mpmath.sqrt(values[-1]) if values[-1] > 0 else None
                if values[-1] is None:
                    break
            if None in values or not own(th, *values) > 0:
                continue
            r = mpmath.sqrt(own(th, *values))
            try:
                holds = {s: bool(tests) and all(t(th, s, *values, r) > 0 for t in tests)
                         for s in (1, -1)}
            except ZeroDivisionError:   # a coordinate the elimination divided for: 0/0 here
                continue
            if holds[1] != holds[-1]:
                votes.add(1 if holds[1] else -1)
    if len(votes) != 1:
        state = "ambiguous" if votes else "not decided by any assembly-mode condition"
        raise NotSolvable(f"the assembly mode of {C.name[2:]} is {state}")
    sigma = votes.pop()
    return sigma, tuple(c.xreplace({sign: sigma}) for c in conditions), tuple(sources)
