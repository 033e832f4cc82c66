"""Layer 4a'': expressions as interval programs for the runtime's outward-rounded arithmetic
(templates/runtime/codegen_interval.h), for the certified isolation of G's zeros.

Each expression becomes nested calls (codegen_iv_add(a, codegen_iv_mul(b, c))) after one
common-subexpression pass, so every value has exactly one enclosure. Constants that the real
type cannot hold (1/3, pi) are enclosed between the numbers of that type just below and
above them, computed exactly here for double and for float (``CODEGEN_BOUND`` picks one when
the library is compiled); square roots and divisions report, through ``flags``, where a radicand may
reach below zero or a divisor hold zero.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from .printer import _temporary_prefix

#: digits for enclosing irrational constants; far beyond double's 17
_CONSTANT_DIGITS = 40


@dataclass(frozen=True)
class IntervalBody:
    """One mode's program: parameters as point intervals, temporaries, then G and G'."""

    unpack: tuple[str, ...]                   # parameter names used
    temporaries: tuple[tuple[str, str], ...]  # (name, C expression of type codegen_iv)
    outputs: tuple[str, ...]                  # C expressions of G and G'
    operations: int
    unused: tuple[str, ...] = ()              # inputs, and the flags pointer, it never reads


def _exact(value: sp.Expr) -> tuple[Fraction, int]:
    """The number as a fraction, and how many steps outward its own error needs (an
    irrational one is a 40-digit value, ~1e-40 off: one step)."""
    if value.is_Rational:
        return Fraction(int(value.p), int(value.q)), 0
    return Fraction(str(sp.N(value, _CONSTANT_DIGITS))), 1


def _enclose(exact: Fraction, margin: int, kind: type) -> tuple[float, float]:
    """The tightest numbers of ``kind`` (float or numpy.float32) around exact, then margin
    steps further out; lo == hi when exact is one of them."""
    nearest = kind(float(exact))  # rounds twice for float32: corrected below
    lo = hi = nearest
    while Fraction(float(lo)) > exact:
        lo = np.nextafter(lo, kind(-math.inf))
    while Fraction(float(hi)) < exact:
        hi = np.nextafter(hi, kind(math.inf))
    for _ in range(margin):
        lo, hi = np.nextafter(lo, kind(-math.inf)), np.nextafter(hi, kind(math.inf))
    return float(lo), float(hi)


def enclose_constant(value: sp.Expr, kind: type = float) -> tuple[float, float]:
    """The tightest doubles (or, with kind=numpy.float32, floats) (lo, hi) around an exact
    number (lo == hi when it is one of them)."""
    return _enclose(*_exact(value), kind)


def _point(x: float) -> str:
    """A number exact in both types, as a literal of the library's type."""
    return str(int(x)) if x.is_integer() and abs(x) < 2**24 else f"CODEGEN_R({x!r})"


def _literal(x: float) -> str:
    """A bound as C text for CODEGEN_BOUND (which appends F to the float one)."""
    if math.isinf(x):
        return "CODEGEN_HUGE" if x > 0 else "-CODEGEN_HUGE"
    return x.hex()


class _IntervalPrinter:
    def __init__(self, flags: str):
        self._flags = flags
        self.flagged = False  # whether an operation that raises flags was printed

    @property
    def flags(self) -> str:
        self.flagged = True
        return self._flags

    def constant(self, value: sp.Expr) -> str:
        lo, hi = enclose_constant(value)
        flo, fhi = enclose_constant(value, np.float32)
        if lo == hi == flo == fhi:  # exact in both types
            return f"codegen_iv_point({_point(lo)})"
        return (f"codegen_iv_make(CODEGEN_BOUND({_literal(lo)}, {_literal(flo)}), "
                f"CODEGEN_BOUND({_literal(hi)}, {_literal(fhi)}))")

    def print(self, expr: sp.Expr) -> str:
        if expr.is_Symbol:
            return expr.name
        if expr.is_number:
            return self.constant(expr)
        if expr.is_Add:
            terms = sorted(expr.args, key=sp.default_sort_key)
            text = self.print(terms[0])
            for term in terms[1:]:
                if term.could_extract_minus_sign():
                    text = f"codegen_iv_sub({text}, {self.print(-term)})"
                else:
                    text = f"codegen_iv_add({text}, {self.print(term)})"
            return text
        if expr.is_Mul:
            coefficient, factors = expr.as_coeff_mul()
            if coefficient < 0:
                return f"codegen_iv_neg({self.print(-expr)})"
            parts = ([coefficient] if coefficient != 1 else []) + sorted(
                factors, key=sp.default_sort_key)
            denominators = [p.base ** -p.exp for p in parts if p.is_Pow and p.exp.is_negative]
            numerators = [p for p in parts if not (p.is_Pow and p.exp.is_negative)]
            text = self._product(numerators)
            if denominators:
                text = f"codegen_iv_div({text}, {self._product(denominators)}, {self.flags})"
            return text
        if expr.is_Pow:
            return self._power(expr.base, expr.exp)
        if isinstance(expr, (sp.sin, sp.cos)):
            return f"codegen_iv_{type(expr).__name__}({self.print(expr.args[0])})"
        raise ValueError(f"no interval rule for {type(expr).__name__} in {expr}: the certified "
                         "isolation supports +, -, *, /, integer and half-integer powers, "
                         "sin and cos")

    def _product(self, parts) -> str:
        if not parts:
            return "codegen_iv_point(1.0)"
        text = self.print(parts[0])
        for part in parts[1:]:
            text = f"codegen_iv_mul({text}, {self.print(part)})"
        return text

    def _power(self, base: sp.Expr, exp: sp.Expr) -> str:
        if exp.is_negative:
            return f"codegen_iv_div(codegen_iv_point(1.0), {self._power(base, -exp)}, {self.flags})"
        if exp.is_Integer:
            return f"codegen_iv_pow({self.print(base)}, {int(exp)})"
        if exp.is_Rational and exp.q == 2:
            root = f"codegen_iv_sqrt({self.print(base)}, {self.flags})"
            return root if exp.p == 1 else f"codegen_iv_pow({root}, {int(exp.p)})"
        raise ValueError(f"no interval rule for the power {exp} in {base ** exp}")


def interval_body(exprs: list[sp.Expr], parameters: tuple[str, ...], inputs: set[str],
                  flags: str) -> IntervalBody:
    """exprs (in the parameters and ``inputs``) as one interval program."""
    used = set().union(*(e.free_symbols for e in exprs))
    prefix = _temporary_prefix(used)
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols(prefix),
                                   order="canonical")
    printer = _IntervalPrinter(flags)
    names = {s.name for s in used}
    unknown = names - set(parameters) - inputs
    if unknown:
        raise ValueError(f"symbols {sorted(unknown)} are neither parameters nor inputs")
    operations = sum(sp.count_ops(e) for _, e in replacements) + sum(
        sp.count_ops(e) for e in reduced)
    temporaries = tuple((str(s), printer.print(e)) for s, e in replacements)
    outputs = tuple(printer.print(e) for e in reduced)
    return IntervalBody(
        unpack=tuple(p for p in parameters if p in names),
        temporaries=temporaries, outputs=outputs, operations=int(operations),
        unused=tuple(sorted(inputs - names)) + (() if printer.flagged else (flags,)))
