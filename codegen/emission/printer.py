"""Layer 4a: expressions to C statements, through SymPy's C99 printer after one
common-subexpression pass over all outputs of a function.

The real type is a setting: ``CTarget("float")`` prints sinf/sqrtf and F-suffixed
literals from the very same expressions, so a float build computes in float.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.codegen.ast import float32, float64, real
from sympy.printing.c import C99CodePrinter

from .double_double import Program, assemble
from .plan import CFunction

_REAL_TYPES = {"double": float64, "float": float32}


class RealPrinter(C99CodePrinter):
    """C99 printer with small integer and half-integer powers as products and sqrt."""

    def __init__(self, ctype: str = "double"):
        super().__init__({"type_aliases": {real: _REAL_TYPES[ctype]}})
        self.ctype = ctype

    def _print_And(self, expr):
        return " && ".join(f"({self._print(a)})" for a in expr.args)

    def _print_Or(self, expr):
        return " || ".join(f"({self._print(a)})" for a in expr.args)

    def _print_Pow(self, expr):
        base, exp = expr.base, expr.exp
        if exp.is_Rational and exp.q in (1, 2) and 0 < abs(exp) <= 4 and exp != sp.S.Half:
            whole, half = divmod(abs(exp.p), 2) if exp.q == 2 else (abs(exp.p), 0)
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"])
            factors = [b] * whole + ([self._print(sp.sqrt(base))] if half else [])
            product = "*".join(factors)
            if exp > 0:
                return product if len(factors) == 1 else f"({product})"
            return f"{self._print(sp.S.One)}/({product})"
        return super()._print_Pow(expr)


@dataclass(frozen=True)
class CTarget:
    ctype: str = "double"

    @property
    def printer(self) -> RealPrinter:
        return RealPrinter(self.ctype)


@dataclass(frozen=True)
class PrintedBody:
    """Unpacked inputs, const temporaries, and output assignments into ``out``."""

    unpack: tuple[tuple[str, str], ...]       # (local name, source expression)
    temporaries: tuple[tuple[str, str], ...]  # (name, C expression)
    assignments: tuple[str, ...]              # C expression of out[i]
    operations: int
    program: Program | None = None            # double-double: run by the runtime's machine


def _temporary_prefix(used: set[sp.Symbol]) -> str:
    names = {s.name for s in used}
    prefix = "tmp"
    while any(n.startswith(prefix) for n in names):
        prefix = "_" + prefix
    return prefix


def needed_definitions(definitions, exprs) -> list:
    """The definitions the expressions use, directly or through other definitions, in order."""
    wanted = set().union(*(sp.sympify(e).free_symbols for e in exprs)) if exprs else set()
    kept = []
    for symbol, definition in reversed(definitions):
        if symbol in wanted:
            kept.append((symbol, definition))
            wanted |= definition.free_symbols
    return kept[::-1]


def print_body(function: CFunction, parameters: tuple[str, ...], target: CTarget) -> PrintedBody:
    # A parameter named like one of the function's arguments is unpacked as param_NAME.
    arguments = {a.name for a in function.inputs + function.outputs}
    renamed = {sp.Symbol(n, real=True): sp.Symbol(f"param_{n}", real=True)
               for n in parameters if n in arguments}
    exprs = [sp.sympify(e).xreplace(renamed) for o in function.outputs for e in o.exprs]
    program = [(s, d.xreplace(renamed))
               for s, d in needed_definitions(function.definitions, exprs)]
    used = set().union(*(sp.sympify(e).free_symbols for e in exprs),
                       *(d.free_symbols for _, d in program))
    prefix = _temporary_prefix(used)
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols(prefix),
                                   order="canonical")
    replacements = program + replacements
    printer = target.printer
    unpack = [(renamed.get(sp.Symbol(n, real=True), sp.Symbol(n)).name, f"params->{n}")
              for n in parameters
              if renamed.get(sp.Symbol(n, real=True), sp.Symbol(n, real=True)) in used]
    used -= {symbol for symbol, _ in program}
    for arg in function.inputs:
        for i, sym in enumerate(arg.symbols):
            if sym in used:
                unpack.append((sym.name, f"{arg.name}[{i}]" if arg.size else arg.name))
    operations = (sum(sp.count_ops(e) for _, e in replacements)
                  + sum(sp.count_ops(e) for e in reduced))
    if function.arithmetic == "double-double":
        return _double_double_body(unpack, replacements, reduced, int(operations))
    return PrintedBody(
        unpack=tuple((n, src) for n, src in unpack if n != src),
        temporaries=tuple((str(s), printer.doprint(e)) for s, e in replacements),
        assignments=tuple(printer.doprint(e) for e in reduced),
        operations=int(operations),
    )


def _double_double_body(unpack, replacements, reduced, operations) -> PrintedBody:
    """The inputs in v[0..], then the program's instructions; out[i] from its slot."""
    program = assemble([n for n, _ in unpack], [(str(s), e) for s, e in replacements],
                       reduced)
    return PrintedBody(
        unpack=tuple((f"v[{i}]", f"codegen_dd_from({src})")
                     for i, (_, src) in enumerate(unpack)),
        temporaries=(), operations=operations, program=program,
        assignments=tuple(f"codegen_dd_to_double(v[{slot}])" for slot in program.outputs))
