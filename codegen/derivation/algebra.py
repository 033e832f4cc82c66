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


def tidy(expr: sp.Expr, step: Callable[[sp.Expr], sp.Expr] = sp.factor) -> sp.Expr:
    """Apply ``step`` with every square root held as an opaque symbol."""
    roots = {sp.sqrt(b): sp.Dummy(f"root{i}", positive=True)
             for i, b in enumerate(square_roots(expr))}
    held = expr.subs(roots)
    return sp.factor_terms(step(held)).subs({v: k for k, v in roots.items()})
