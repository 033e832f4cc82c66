"""Expressions to C statements, through SymPy's C99 printer after one
common-subexpression pass over all outputs of a function.

The C computes in ``codegen_real`` (codegen_real.h): double, or float when the library is
compiled with -DCODEGEN_FLOAT. So the printer writes literals that take the library's type:
an integer as it is (exact in float below 2^24), a rational as ``(codegen_real)p/q`` (one
rounding in the library's type), any other number through ``CODEGEN_R``. libm is called as
``codegen_sin``, ..., which codegen_real.h maps to sinf or sin.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import sympy as sp
from sympy.printing.c import C99CodePrinter

from .double_double import Program, assemble
from .plan import CFunction

#: The real type's name in the C sources (codegen_real.h), and in the cffi declarations,
#: whose extension modules always build the double library.
C_REAL, CFFI_REAL = "codegen_real", "double"
#: Integers up to this size are exact in float as well as in double.
EXACT_INTEGER = 2**24
#: Integer (and half-integer) powers up to this are written as products: libm's pow costs
#: tens of multiplications (the four-bar's kernels raise lengths to the 5th and 6th).
MAX_PRODUCT_POWER = 8
#: libm as SymPy's C printer names it, and as codegen_real.h maps it for the real type.
_LIBM_CALL = re.compile(r"(?<![\w.])(atan2|atan|ceil|copysign|cos|fabs|fma|fmax|fmin|pow|sin|"
                        r"sqrt|tan)\(")


class RealPrinter(C99CodePrinter):
    """C99 printer for ``codegen_real`` with small integer and half-integer powers as
    products and sqrt."""

    def doprint(self, expr, assign_to=None):
        return _LIBM_CALL.sub(r"codegen_\1(", super().doprint(expr, assign_to))

    def _print_Integer(self, expr):
        if abs(int(expr)) < EXACT_INTEGER:
            return str(int(expr))
        return f"CODEGEN_R({int(expr)}.0)"

    def _print_Rational(self, expr):
        p, q = int(expr.p), int(expr.q)
        if abs(p) < EXACT_INTEGER and q < EXACT_INTEGER:
            return f"((codegen_real){p}/{q})"
        return f"(CODEGEN_R({p}.0)/CODEGEN_R({q}.0))"

    def _print_Float(self, expr):
        return f"CODEGEN_R({super()._print_Float(expr)})"

    def _print_NumberSymbol(self, expr):  # pi, E: M_PI would be a double
        return f"CODEGEN_R({sp.N(expr, 36)})"

    def _print_Max(self, expr):
        return self._real_call("fmax", expr)

    def _print_Min(self, expr):
        return self._real_call("fmin", expr)

    def _real_call(self, name, expr):
        """name(a, name(b, ...)) with numbers as literals of the library's type: <tgmath.h>
        would call the double function for an integer argument."""
        args = [f"CODEGEN_R({float(a)!r})" if a.is_number else self._print(a)
                for a in expr.args]
        text = args[-1]
        for arg in reversed(args[:-1]):
            text = f"{name}({arg}, {text})"
        return text

    def _print_And(self, expr):
        return " && ".join(f"({self._print(a)})" for a in expr.args)

    def _print_Or(self, expr):
        return " || ".join(f"({self._print(a)})" for a in expr.args)

    def _print_Pow(self, expr):
        base, exp = expr.base, expr.exp
        if exp.is_Rational and exp.q in (1, 2) and 0 < abs(exp) <= MAX_PRODUCT_POWER and exp != sp.S.Half:
            whole, half = divmod(abs(exp.p), 2) if exp.q == 2 else (abs(exp.p), 0)
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"])
            factors = [b] * whole + ([self._print(sp.sqrt(base))] if half else [])
            product = "*".join(factors)
            if exp > 0:
                return product if len(factors) == 1 else f"({product})"
            return f"1/({product})"
        if exp.is_Integer:  # pow(x, 9) would call the double pow through <tgmath.h>
            b = self._print(base)
            return f"pow({b}, CODEGEN_R({int(exp)}.0))"
        return super()._print_Pow(expr)


@dataclass(frozen=True)
class CTarget:
    ctype: str = C_REAL

    @property
    def printer(self) -> RealPrinter:
        return RealPrinter()


@dataclass(frozen=True)
class PrintedBody:
    """Unpacked inputs, const temporaries, and output assignments into ``out`` (in plain
    arithmetic the inputs are loaded among the temporaries, where first read: unpack empty)."""

    unpack: tuple[tuple[str, str], ...]       # (local name, source expression)
    temporaries: tuple[tuple[str, str], ...]  # (name, C expression)
    assignments: tuple[str, ...]              # C expression of out[i]
    operations: int
    program: Program | None = None            # double-double: run by the runtime's machine
    unpack_errors: tuple[str, ...] = ()       # double-double: a bound on each input's error


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


def shared_with_program(program, exprs, prefix: str) -> tuple[list, list]:
    """One CSE over a straight-line program's steps and the expressions: (the steps, their
    subexpressions shared, then the common subexpressions; the expressions reduced). The
    statements are not in dependency order (in_dependency_order puts them so). Sharing
    across the steps pays in plain and double-double arithmetic alike: the elimination's
    definitions repeat many products, and a double-double operation costs tens of plain
    ones."""
    replacements, reduced = sp.cse([d for _, d in program] + list(exprs),
                                   symbols=sp.numbered_symbols(prefix), order="canonical")
    steps = [(symbol, d) for (symbol, _), d in zip(program, reduced)]
    return _used(steps + replacements, reduced[len(program):]), reduced[len(program):]


def _used(statements, exprs) -> list:
    """The statements the expressions read, directly or through others (CSE can leave a
    subexpression unread where the terms that shared it cancel)."""
    wanted = set().union(*(sp.sympify(e).free_symbols for e in exprs)) if exprs else set()
    by_symbol = dict(statements)
    pending = list(wanted)
    while pending:
        symbol = pending.pop()
        if symbol in by_symbol:
            for s in by_symbol.pop(symbol).free_symbols - wanted:
                wanted.add(s)
                pending.append(s)
    return [(s, e) for s, e in statements if s in wanted]


def _argument_clashes(function: CFunction, fields) -> dict[str, str]:
    """Parameter symbol -> local name, for the parameters named like one of the function's
    arguments: param_NAME (with underscores added while that is taken too)."""
    arguments = {a.name for a in function.inputs + function.outputs}
    taken = arguments | {local for local, _ in fields}
    renamed = {}
    for local, _ in fields:
        if local in arguments:
            name = f"param_{local}"
            while name in taken:
                name += "_"
            taken.add(name)
            renamed[local] = name
    return renamed


def print_body(function: CFunction, fields: tuple[tuple[str, str], ...],
               target: CTarget) -> PrintedBody:
    """The body of a function; ``fields`` pairs each parameter's symbol with the field of
    PREFIX_params it is read from (Plan.fields)."""
    exprs = [sp.sympify(e) for o in function.outputs for e in o.exprs]
    program = needed_definitions(function.definitions, exprs)
    clashes = _argument_clashes(function, fields)
    if clashes:
        symbols = set().union(*(e.free_symbols for e in exprs),
                              *(d.free_symbols for _, d in program))
        renamed = {s: sp.Symbol(clashes[s.name], **s.assumptions0) for s in symbols
                   if s.name in clashes}
        exprs = [e.xreplace(renamed) for e in exprs]
        program = [(s, d.xreplace(renamed)) for s, d in program]
    used = set().union(*(sp.sympify(e).free_symbols for e in exprs),
                       *(d.free_symbols for _, d in program))
    prefix = _temporary_prefix(used)
    computed: list[tuple[str, str]] = []
    if function.arithmetic == "double-double":
        exprs, program, computed = _parameter_functions(exprs, program, fields, clashes, used)
    # (_calls_first puts the statements in dependency order)
    replacements, reduced = shared_with_program(program, exprs, prefix)
    printer = target.printer
    used_names = {s.name for s in used}
    unpack = [(clashes.get(local, local), f"params->{field}") for local, field in fields
              if clashes.get(local, local) in used_names]
    used -= {symbol for symbol, _ in program}
    for arg in function.inputs:
        for i, sym in enumerate(arg.symbols):
            if sym in used:
                unpack.append((sym.name, f"{arg.name}[{i}]" if arg.size else arg.name))
    operations = (sum(sp.count_ops(e) for _, e in replacements)
                  + sum(sp.count_ops(e) for e in reduced))
    if function.arithmetic == "double-double":
        return _double_double_body(unpack + computed, _calls_first(replacements), reduced,
                                   int(operations), len(unpack))
    return PrintedBody(
        unpack=(),
        temporaries=_loaded_on_first_use([(n, src) for n, src in unpack if n != src],
                                         _calls_first(replacements), printer),
        assignments=tuple(printer.doprint(e) for e in reduced),
        operations=int(operations),
    )


def _calls_first(replacements: list) -> list:
    """The statements in an order that makes each libm call (sin, cos, ...: a function
    application; sqrt is an instruction) as early as its operands allow, then the rest as
    they were: fewer values live across a call, each of which would be saved to memory."""
    return in_dependency_order(replacements, [symbol for symbol, expr in replacements
                                              if expr.atoms(sp.Function)])


def in_dependency_order(replacements: list, first=()) -> list:
    """(symbol, expression) statements ordered so that each follows the ones it reads: the
    statements ``first`` names as early as their operands allow, then the rest as they
    were."""
    position = {symbol: i for i, (symbol, _) in enumerate(replacements)}
    placed: set = set()
    order = []

    def place(root) -> None:
        stack = [(root, False)]
        while stack:
            symbol, ready = stack.pop()
            if symbol in placed:
                continue
            if ready:
                placed.add(symbol)
                order.append(replacements[position[symbol]])
                continue
            stack.append((symbol, True))
            operands = [f for f in replacements[position[symbol]][1].free_symbols
                        if f in position and f not in placed]
            stack.extend((f, False) for f in sorted(operands, key=position.get, reverse=True))

    for symbol in first:
        place(symbol)
    for symbol, _ in replacements:
        place(symbol)
    return order


def _loaded_on_first_use(unpack, replacements, printer) -> tuple[tuple[str, str], ...]:
    """The temporaries, each input loaded just before the first one that reads it (or at the
    end, for the outputs alone): a value loaded before a libm call must be kept across it,
    in memory, since every floating-point register is the callee's to overwrite."""
    first_use = {}
    for index, (_, expr) in enumerate(replacements):
        for symbol in expr.free_symbols:
            first_use.setdefault(symbol.name, index)
    waiting: dict[int, list[tuple[str, str]]] = {}
    for name, source in unpack:
        waiting.setdefault(first_use.get(name, len(replacements)), []).append((name, source))
    statements = []
    for index, (symbol, expr) in enumerate(replacements):
        statements += waiting.get(index, [])
        statements.append((str(symbol), printer.doprint(expr)))
    return tuple(statements + waiting.get(len(replacements), []))


#: What libm's sin and cos may be off by (docs/method.md: two ulps), as an error bound.
LIBM_ERROR = "(CODEGEN_R(2.0) * CODEGEN_EPSILON * codegen_fabs({value}) + CODEGEN_REAL_TRUE_MIN)"


def _parameter_functions(exprs, program, fields, clashes, used):
    """sin and cos of a parameter (a bracket's angle) as inputs of a double-double program,
    computed by libm in working precision (their error bound is libm's, see LIBM_ERROR):
    (exprs, program, [(input name, C source)])."""
    field_of = {clashes.get(local, local): field for local, field in fields}
    atoms = sorted({a for e in [*exprs, *(d for _, d in program)]
                    for a in e.atoms(sp.sin, sp.cos)
                    if a.args[0].is_Symbol and a.args[0].name in field_of},
                   key=sp.default_sort_key)
    taken = {x.name for x in used}
    inputs = {}
    for atom in atoms:
        name = f"{type(atom).__name__}_{atom.args[0].name}"
        while name in taken:
            name += "_"
        taken.add(name)
        inputs[atom] = sp.Symbol(name, real=True)
    computed = [(inputs[a].name, f"codegen_{type(a).__name__}(params->{field_of[a.args[0].name]})")
                for a in atoms]
    return ([e.xreplace(inputs) for e in exprs], [(s, d.xreplace(inputs)) for s, d in program],
            computed)


def _double_double_body(unpack, replacements, reduced, operations, exact) -> PrintedBody:
    """The inputs in v[0..] (the first ``exact`` of them exact, the others libm's values),
    then the program's instructions; out[i] from its slot."""
    program = assemble([n for n, _ in unpack], [(str(s), e) for s, e in replacements],
                       reduced)
    return PrintedBody(
        unpack=tuple((f"v[{i}]", f"codegen_dd_from({src})")
                     for i, (_, src) in enumerate(unpack)),
        temporaries=(), operations=operations, program=program,
        assignments=tuple(f"codegen_dd_to_double(v[{slot}])" for slot in program.outputs),
        unpack_errors=tuple("0" if i < exact else LIBM_ERROR.format(value=f"v[{i}].hi")
                            for i in range(len(unpack))))
