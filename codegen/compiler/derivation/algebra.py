"""Small algebraic helpers shared by the derivation steps.

Global ``simplify`` is slow and unpredictable on these expressions; instead, square
roots are frozen into symbols and the rational function around them is cancelled.
"""
from __future__ import annotations

from collections.abc import Callable

import sympy as sp


def square_roots(expr: sp.Expr) -> list[sp.Expr]:
    """The distinct radicands b of sqrt(b) (any power b**(n/2)) in expr, in a stable order."""
    found = {a.base for a in expr.atoms(sp.Pow) if a.exp.is_Rational and a.exp.q == 2}
    return sorted(found, key=sp.default_sort_key)


#: Larger expressions are left as derived: factoring them costs seconds and rarely helps.
TIDY_LIMIT = 400


def tidy(expr: sp.Expr, step: Callable[[sp.Expr], sp.Expr] = sp.factor) -> sp.Expr:
    """Apply ``step`` with every square root held as an opaque symbol (up to TIDY_LIMIT
    operations, so the cost is bounded and the result still deterministic)."""
    if sp.count_ops(expr) > TIDY_LIMIT:
        return expr
    roots = {sp.sqrt(b): sp.Dummy(f"root{i}", positive=True)
             for i, b in enumerate(square_roots(expr))}
    held = expr.xreplace(roots)  # outermost first: a nested root is one opaque symbol
    return sp.factor_terms(step(held)).xreplace({v: k for k, v in roots.items()})


def reduce_trig(expr: sp.Expr, theta: sp.Symbol) -> sp.Expr:
    """A rational function of cos(theta), sin(theta) with sin^2 replaced by 1 - cos^2 in its
    numerator and denominator (so each is at most linear in sin), then factored up to
    TIDY_LIMIT operations (beyond, a chain of dyads' nested expressions, factoring takes
    minutes)."""
    c, s = sp.Dummy("c"), sp.Dummy("s")
    held = sp.together(expr.subs({sp.cos(theta): c, sp.sin(theta): s}))
    num, den = sp.fraction(held)
    unit = sp.Poly(s**2 + c**2 - 1, s)
    factor = sp.factor if sp.count_ops(expr) <= TIDY_LIMIT else (lambda e: e)

    def reduced(part):
        return factor(sp.Poly(sp.expand(part), s).rem(unit).as_expr())

    return (reduced(num) / reduced(den)).subs({c: sp.cos(theta), s: sp.sin(theta)})


def expand_angle_sums(expr: sp.Expr, angles) -> sp.Expr:
    """cos and sin of a sum that holds a coordinate (a second arm at phi + beta) written in
    the coordinate's own cos and sin: the position analysis solves for those."""
    angles = set(angles)

    def compound(e) -> bool:
        return (isinstance(e, (sp.sin, sp.cos)) and not e.args[0].is_Symbol
                and bool(e.args[0].free_symbols & angles))

    return expr.replace(compound, lambda e: sp.expand_trig(e)) if expr.has(*angles) else expr


def written_out(definitions, exprs) -> list[sp.Expr]:
    """Expressions in the symbols of a straight-line program (definitions: (symbol,
    expression) in order), with those symbols written out in the program's inputs."""
    values: dict[sp.Symbol, sp.Expr] = {}
    for symbol, definition in definitions:
        values[symbol] = definition.xreplace(values)
    return [sp.sympify(e).xreplace(values) for e in exprs]
