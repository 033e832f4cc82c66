"""Step 8, algebraic part: every square root of G eliminated into one polynomial in tau.

G is a rational function of cos(theta), sin(theta) and the roots rho_1..rho_n of the
position analysis (rho_i^2 = R_i, where R_i may hold earlier roots). Its numerator N is a
polynomial in them. Writing N = alpha + beta rho_n (powers of rho_n reduced by
rho_n^2 = R_n), minus the product over both signs of rho_n, beta^2 R_n - alpha^2, no longer holds
rho_n; repeating for rho_{n-1}, .., rho_1 leaves a polynomial in cos, sin that vanishes
wherever N vanishes on *some* branch (choice of signs of the roots). The tangent half-angle
substitution makes it a polynomial in tau = tan(theta/2) (half_angle.py).

Nothing is expanded in the parameters. Every polynomial is a map from monomials of the roots
to coefficient vectors in tau, and after each squaring the non-trivial coefficients are
named (a straight-line program of intermediates), so each step multiplies short sums of
named values. The emitted coefficients are that program, and CSE sees its structure.
Coefficients that vanish identically (and factors 1 + tau^2, which have no real root) are
found by exact evaluation at random rational parameters, so the degree is derived.

Clearing G's denominators can leave powers of them in the numerator (a four-bar's
|O2 A|^2 enters every closed-form position), and each squaring doubles them: factors with no
equilibrium among their zeros that inflate the degree and, clustered as multiple complex
roots, make the real roots ill-conditioned. After every stage each denominator factor is
divided out as often as it divides exactly (again decided at random rationals).
"""
from __future__ import annotations

import random
from dataclasses import dataclass

import sympy as sp

from .half_angle import TauPolynomial, to_tau
from .positions import Root

Monomial = tuple[int, ...]


@dataclass(frozen=True)
class Polynomial:
    """sum sigma_i tau^i = (1+tau^2)^weight * (product over branches of the numerator of G),
    up to a constant factor, as a straight-line program."""

    definitions: tuple[tuple[sp.Symbol, sp.Expr], ...]  # intermediates, in order
    coefficients: tuple[sp.Expr, ...]                   # sigma_0..sigma_degree
    weight: int
    #: (factor in cos, sin, power) divided out: the polynomial is the product over branches
    #: divided by the product of factor**power
    divided: tuple[tuple[sp.Expr, int], ...] = ()

    @property
    def degree(self) -> int:
        return len(self.coefficients) - 1

    def explicit(self) -> tuple[sp.Expr, ...]:
        """The coefficients in the parameters (a shared expression graph, for CSE)."""
        values: dict[sp.Symbol, sp.Expr] = {}
        for symbol, definition in self.definitions:
            values[symbol] = definition.xreplace(values)
        return tuple(c.xreplace(values) for c in self.coefficients)


class _Program:
    """Names non-trivial coefficients and evaluates them exactly at random parameters."""

    def __init__(self, parameters: tuple[sp.Symbol, ...], trials: int = 3):
        self.definitions: list[tuple[sp.Symbol, sp.Expr]] = []
        rng = random.Random(20240611)
        self.values: list[dict] = [{p: sp.Rational(rng.randint(1, 10**6), rng.randint(1, 10**6))
                                    for p in parameters} for _ in range(trials)]

    def name(self, expr: sp.Expr) -> sp.Expr:
        if expr.is_Number or expr.is_Symbol or (expr.is_Mul and len(expr.args) == 2
                                                and expr.args[0].is_Number
                                                and expr.args[1].is_Symbol):
            return expr
        symbol = sp.Symbol(f"w_{len(self.definitions)}", real=True)
        self.definitions.append((symbol, expr))
        for values in self.values:
            values[symbol] = expr.xreplace(values)
        return symbol

    def vanishes(self, expr: sp.Expr) -> bool:
        """Zero at every random point: identically zero (Schwartz-Zippel)."""
        return all(expr.xreplace(v) == 0 for v in self.values)

    def divides(self, divisor: tuple[sp.Expr, ...], coeffs: tuple[sp.Expr, ...]) -> bool:
        """Whether sum divisor_i tau^i divides sum coeffs_i tau^i at every random point."""
        tau = sp.Dummy("tau")
        for v in self.values:
            d = sp.Poly([c.xreplace(v) for c in reversed(divisor)], tau, domain="QQ")
            p = sp.Poly([c.xreplace(v) for c in reversed(coeffs)], tau, domain="QQ")
            if d.degree() < len(divisor) - 1 or not sp.rem(p, d).is_zero:
                return False
        return True


class RootPolynomial:
    """sum over monomials m of coeffs[m](tau) * rho^m, each coefficient a TauPolynomial."""

    def __init__(self, terms: dict[Monomial, TauPolynomial], n: int):
        self.terms = {m: t for m, t in terms.items() if any(c != 0 for c in t.coeffs)}
        self.n = n

    @classmethod
    def constant(cls, value: TauPolynomial, n: int) -> "RootPolynomial":
        return cls({(0,) * n: value}, n)

    def __add__(self, other: "RootPolynomial") -> "RootPolynomial":
        terms = dict(self.terms)
        for m, t in other.terms.items():
            terms[m] = terms[m] + t if m in terms else t
        return RootPolynomial(terms, self.n)

    def __neg__(self) -> "RootPolynomial":
        return RootPolynomial({m: t.scaled(-1) for m, t in self.terms.items()}, self.n)

    def __mul__(self, other: "RootPolynomial") -> "RootPolynomial":
        terms: dict[Monomial, TauPolynomial] = {}
        for m1, t1 in self.terms.items():
            for m2, t2 in other.terms.items():
                m = tuple(a + b for a, b in zip(m1, m2))
                product = t1 * t2
                terms[m] = terms[m] + product if m in terms else product
        return RootPolynomial(terms, self.n)

    def split(self, i: int) -> tuple["RootPolynomial", "RootPolynomial"]:
        """(alpha, beta) with self = alpha + beta rho_i (rho_i of degree <= 1 in self)."""
        parts = ({}, {})
        for m, t in self.terms.items():
            parts[m[i]][m[:i] + (0,) + m[i + 1:]] = t
        return RootPolynomial(parts[0], self.n), RootPolynomial(parts[1], self.n)

    def reduced(self, radicands: list["RootPolynomial"]) -> "RootPolynomial":
        """Powers rho_i^k, k >= 2, replaced by R_i rho_i^(k-2) until every degree is <= 1."""
        result = self
        while True:
            high = next(((m, i) for m in result.terms for i, e in enumerate(m) if e >= 2), None)
            if high is None:
                return result
            m, i = high
            t = result.terms[m]
            rest = dict(result.terms)
            del rest[m]
            lower = m[:i] + (m[i] - 2,) + m[i + 1:]
            lowered = RootPolynomial({lower: t}, self.n) * radicands[i]
            result = RootPolynomial(rest, self.n) + lowered

    def divided(self, divisor: TauPolynomial, program: _Program) -> "RootPolynomial | None":
        """self / divisor when every coefficient divides exactly, else None."""
        terms = {m: t.lifted(max(t.weight, divisor.weight)) for m, t in self.terms.items()}
        if not all(program.divides(divisor.coeffs, t.coeffs) for t in terms.values()):
            return None
        inverse = program.name(1 / divisor.coeffs[-1])
        return RootPolynomial({m: TauPolynomial(_quotient(t.coeffs, divisor.coeffs, inverse,
                                                          program), t.weight - divisor.weight)
                               for m, t in terms.items()}, self.n)

    def named(self, program: _Program) -> "RootPolynomial":
        return RootPolynomial({m: TauPolynomial(tuple(program.name(c) for c in t.coeffs),
                                                t.weight)
                               for m, t in self.terms.items()}, self.n)


class NotPolynomial(ValueError):
    """G is not a polynomial in the roots and sin/cos of theta: no polynomial route."""


def to_root_polynomial(expr: sp.Expr, theta: sp.Symbol, roots: tuple[Root, ...]) -> RootPolynomial:
    """A polynomial in cos(theta), sin(theta) and the root symbols, structured."""
    n = len(roots)
    index = {r.symbol: i for i, r in enumerate(roots)}
    symbols = set(index)

    def walk(e) -> RootPolynomial:
        if not e.free_symbols & symbols:
            return RootPolynomial.constant(to_tau(e, theta), n)
        if e in index:
            return RootPolynomial({tuple(int(j == index[e]) for j in range(n)):
                                   TauPolynomial((sp.S.One,), 0)}, n)
        if e.is_Add:
            total = walk(e.args[0])
            for a in e.args[1:]:
                total = total + walk(a)
            return total
        if e.is_Mul:
            total = walk(e.args[0])
            for a in e.args[1:]:
                total = total * walk(a)
            return total
        if e.is_Pow and e.exp.is_Integer and e.exp >= 0:
            base, result = walk(e.base), RootPolynomial.constant(TauPolynomial((sp.S.One,), 0), n)
            for _ in range(int(e.exp)):
                result = result * base
            return result
        raise NotPolynomial(f"not a polynomial in the roots and sin/cos of {theta}: {e}")

    return walk(expr)


def eliminate(numerator: sp.Expr, theta: sp.Symbol, roots: tuple[Root, ...],
              parameters: tuple[sp.Symbol, ...], factors: tuple[sp.Expr, ...] = ()) -> Polynomial:
    """The polynomial in tau whose real roots include every zero of ``numerator`` on every
    branch of the roots, with ``factors`` (polynomials in cos, sin: G's denominators, where
    G has no zero) divided out wherever they divide."""
    program = _Program(parameters)
    divisors = [(f, to_tau(f, theta)) for f in factors]
    divisors = [(f, d) for f, d in divisors if len(d.coeffs) > 1]  # no finite root: nothing
    powers = {f: 0 for f, _ in divisors}

    def without_factors(poly: RootPolynomial) -> RootPolynomial:
        for f, divisor in divisors:
            while (quotient := poly.divided(divisor, program)) is not None:
                poly, powers[f] = quotient, powers[f] + 1
        return poly

    radicands = [to_root_polynomial(r.radicand, theta, roots).named(program) for r in roots]
    poly = without_factors(to_root_polynomial(numerator, theta, roots).reduced(radicands)
                           .named(program))
    for i in reversed(range(len(roots))):
        alpha, beta = poly.split(i)
        # beta^2 R - alpha^2, the sign the paper's (45) has: -(alpha + beta rho)(alpha - beta rho)
        powers = {f: 2 * k for f, k in powers.items()}  # a factor taken out is now squared
        poly = without_factors((beta * beta * radicands[i] + -(alpha * alpha))
                               .reduced(radicands).named(program))
    (tau,) = poly.terms.values() or (TauPolynomial((sp.S.Zero,), 0),)
    coeffs = list(tau.coeffs) + [sp.S.Zero] * (2 * tau.weight + 1 - len(tau.coeffs))
    weight = tau.weight
    # A factor 1 + tau^2 (value zero at tau = i) has no real root: divide it out.
    while weight > 0 and _divisible_by_one_plus_tau2(coeffs, program):
        coeffs, weight = _divide_one_plus_tau2(coeffs, program), weight - 1
    coeffs = [sp.S.Zero if program.vanishes(c) else c for c in coeffs]
    return Polynomial(tuple(program.definitions), tuple(coeffs), weight,
                      tuple((f, k) for f, k in powers.items() if k))


def _quotient(coeffs, divisor, inverse, program) -> tuple[sp.Expr, ...]:
    """Exact division from the top (coefficient vectors, lowest power first): q_k =
    (p_{k+m} - sum_j d_{m-j} q_{k+j}) / d_m, each named."""
    m, n = len(divisor) - 1, len(coeffs) - 1
    q = [sp.S.Zero] * (n - m + 1)
    for k in range(n - m, -1, -1):
        rest = sum((divisor[m - j] * q[k + j] for j in range(1, m + 1) if k + j <= n - m),
                   sp.S.Zero)
        q[k] = program.name((coeffs[k + m] - rest) * inverse)
    return tuple(q)


def _divisible_by_one_plus_tau2(coeffs, program) -> bool:
    real = sum((c * (-1) ** (k // 2) for k, c in enumerate(coeffs) if k % 2 == 0), sp.S.Zero)
    imag = sum((c * (-1) ** (k // 2) for k, c in enumerate(coeffs) if k % 2 == 1), sp.S.Zero)
    return program.vanishes(real) and program.vanishes(imag)


def _divide_one_plus_tau2(coeffs, program) -> list[sp.Expr]:
    """Synthetic division by tau^2 + 1, from the top: q_k = p_{k+2} - q_{k+2}."""
    degree = len(coeffs) - 1
    q = [sp.S.Zero] * (degree - 1)
    for k in range(degree - 2, -1, -1):
        q[k] = program.name(coeffs[k + 2] - (q[k + 2] if k + 2 <= degree - 2 else 0))
    return q
