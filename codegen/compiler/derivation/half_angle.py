"""The tangent half-angle substitution (44), done on coefficient vectors.

A polynomial in sin(theta), cos(theta) of total degree w becomes, after
sin = 2 tau/(1+tau^2) and cos = (1-tau^2)/(1+tau^2) and multiplication by (1+tau^2)^w,
a polynomial of degree <= 2w in tau. Rather than expanding monomials of the parameters,
the expression tree is walked: sums add coefficient vectors (lifting the lighter term by
powers of 1+tau^2), products convolve them. Each coefficient stays a short combination
of the coefficients of small polynomials, so common-subexpression elimination later
finds the convolution structure and the emitted code is a few dozen operations.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class TauPolynomial:
    """coeffs[i] multiplies tau**i; the trig expression equals this over (1+tau^2)^weight."""

    coeffs: tuple[sp.Expr, ...]
    weight: int

    def lifted(self, weight: int) -> "TauPolynomial":
        """The same value written over (1+tau^2)^weight, weight >= self.weight."""
        result = self
        for _ in range(weight - self.weight):
            result = result * _ONE_PLUS_TAU2
        return TauPolynomial(result.coeffs, weight)

    def __add__(self, other: "TauPolynomial") -> "TauPolynomial":
        w = max(self.weight, other.weight)
        a, b = self.lifted(w).coeffs, other.lifted(w).coeffs
        n = max(len(a), len(b))
        a, b = a + (sp.S.Zero,) * (n - len(a)), b + (sp.S.Zero,) * (n - len(b))
        return TauPolynomial(tuple(x + y for x, y in zip(a, b)), w)

    def __mul__(self, other: "TauPolynomial") -> "TauPolynomial":
        a, b = self.coeffs, other.coeffs
        conv = [sp.S.Zero] * (len(a) + len(b) - 1)
        for i, x in enumerate(a):
            for j, y in enumerate(b):
                if x != 0 and y != 0:
                    conv[i + j] += x * y
        return TauPolynomial(tuple(conv), self.weight + other.weight)

    def scaled(self, factor) -> "TauPolynomial":
        return TauPolynomial(tuple(factor * c for c in self.coeffs), self.weight)

    def power(self, n: int) -> "TauPolynomial":
        result = TauPolynomial((sp.S.One,), 0)
        for _ in range(n):
            result = result * self
        return result


_ONE_PLUS_TAU2 = TauPolynomial((sp.S.One, sp.S.Zero, sp.S.One), 0)


def to_tau(expr: sp.Expr, theta: sp.Symbol) -> TauPolynomial:
    """Convert a polynomial in sin(theta), cos(theta) (parameter coefficients) to tau form."""
    if not expr.has(theta):
        return TauPolynomial((expr,), 0)
    if expr == sp.sin(theta):
        return TauPolynomial((sp.S.Zero, sp.Integer(2)), 1)
    if expr == sp.cos(theta):
        return TauPolynomial((sp.S.One, sp.S.Zero, sp.Integer(-1)), 1)
    if expr.is_Add:
        terms = [to_tau(t, theta) for t in expr.args]
        total = terms[0]
        for t in terms[1:]:
            total = total + t
        return total
    if expr.is_Mul:
        total = TauPolynomial((sp.S.One,), 0)
        for f in expr.args:
            total = total * to_tau(f, theta)
        return total
    if expr.is_Pow and expr.exp.is_Integer and expr.exp >= 0:
        return to_tau(expr.base, theta).power(int(expr.exp))
    raise ValueError(f"not a polynomial in sin/cos of {theta}: {expr}")
