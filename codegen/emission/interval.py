"""Layer 4a'': expressions as interval programs for the runtime's outward-rounded arithmetic
(templates/runtime/codegen_interval.h), for the certified isolation of G's zeros.

Each expression becomes nested calls (codegen_iv_add(a, codegen_iv_mul(b, c))) after one
common-subexpression pass, so every value has exactly one enclosure. Constants that double
cannot hold (1/3, pi) are enclosed between the doubles just below and above them, computed
exactly here; square roots and divisions report, through ``flags``, where a radicand may
reach below zero or a divisor hold zero.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

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


def _double(text: float) -> str:
    return repr(text) if math.isfinite(text) else ("HUGE_VAL" if text > 0 else "-HUGE_VAL")


def enclose_constant(value: sp.Expr) -> tuple[float, float]:
    """The tightest doubles (lo, hi) around an exact number (lo == hi when it is a double)."""
    if value.is_Rational:
        exact, margin = Fraction(int(value.p), int(value.q)), 0
    else:  # a 40-digit value, then one more double outward for its own error (~1e-40)
        exact, margin = Fraction(str(sp.N(value, _CONSTANT_DIGITS))), 1
    nearest = float(exact)
    if Fraction(nearest) == exact and not margin:
        return nearest, nearest
    lo = nearest if Fraction(nearest) < exact else math.nextafter(nearest, -math.inf)
    hi = nearest if Fraction(nearest) > exact else math.nextafter(nearest, math.inf)
    for _ in range(margin):
        lo, hi = math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf)
    return lo, hi


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
        if lo == hi:
            return f"codegen_iv_point({_double(lo)})"
        return f"codegen_iv_make({lo.hex()}, {hi.hex()})"

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
