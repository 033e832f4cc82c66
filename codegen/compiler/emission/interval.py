"""Expressions as interval programs for the runtime's outward-rounded arithmetic
(runtime/codegen_interval.h), for the certified isolation of G's zeros.

Each expression becomes three-address instructions over reused slots (a program that
codegen_iv_run executes) after one common-subexpression pass, so every value has exactly one
enclosure; a program splits where theta first enters (split_program), and its part at theta
can be written as inline C (inline_tail). Constants that the real type cannot hold (1/3, pi)
are enclosed between the numbers of that type just below and above them, computed exactly
here for double and for float (``CODEGEN_BOUND`` picks one when the library is compiled);
square roots and divisions report, through the runtime's flags, where a radicand may reach
below zero or a divisor hold zero.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from .printer import (_temporary_prefix, in_dependency_order, needed_definitions,
                      shared_with_program)

#: digits for enclosing irrational constants; far beyond double's 17
_CONSTANT_DIGITS = 40


#: The runtime's operations (codegen_iv_operation, codegen_interval.h), in its order.
OPERATIONS = ("const", "add", "sub", "mul", "div", "neg", "pow", "sqrt", "sin", "cos", "abs")


@dataclass(frozen=True)
class IntervalInstruction:
    operation: str    # one of OPERATIONS
    destination: int
    left: int         # a slot; for const, an index into the constants
    right: int = 0    # a slot; for pow, the exponent


@dataclass(frozen=True)
class IntervalProgram:
    """The same computation as three-address instructions over slots v[0..n_slots): the
    inputs first (the parameters as unpacked, then theta), each slot reused once its value
    is consumed. Constants are (lo, hi) pairs of C text."""

    inputs: tuple[str, ...]    # the names of v[0..], filled by the caller
    instructions: tuple[IntervalInstruction, ...]
    constants: tuple[tuple[str, str], ...]
    outputs: tuple[int, ...]   # the slot of each output
    n_slots: int
    first_input: int = 0       # the slot of inputs[0] (the others follow)


@dataclass(frozen=True)
class IntervalBody:
    """Expressions as one interval program, and their operation count (for the docs)."""

    operations: int
    program: IntervalProgram


@dataclass(frozen=True)
class SplitProgram:
    """A program in two parts over one array of slots, the same operations on the same
    operands (the same bounds bit for bit): the head, the instructions no varying input
    reaches, run once per parameter set, writes each value the tail reads into its own fixed
    slot; the tail, the rest, runs at each theta. Both keep their inputs and scratch at or
    above ``base``, above every program's fixed slots."""

    head: IntervalProgram
    tail: IntervalProgram
    n_fixed: int   # fixed slots it writes: [first fixed, + n_fixed)


#: Operations that can raise flags stay in the tail, so that each call's flags are its own.
_FLAGGED = frozenset({"div", "sqrt"})


def _operands(op: IntervalInstruction) -> tuple[int, ...]:
    if op.operation == "const":
        return ()
    if op.operation in ("add", "sub", "mul", "div"):
        return op.left, op.right
    return (op.left,)


def split_program(program: IntervalProgram, varying: set[str], first_fixed: int,
                  base: int) -> SplitProgram:
    """program split at the inputs named in ``varying`` (theta): its head's values the tail
    reads go to the fixed slots first_fixed, first_fixed + 1, ...; every other slot s of
    program becomes base + s. Constants are written where they are read (in either part,
    or both); square roots and divisions are left to the tail (_FLAGGED)."""
    code = program.instructions
    varying_input = {i for i, name in enumerate(program.inputs) if name in varying}
    producer: dict[int, tuple[str, int]] = {i: ("input", i) for i in range(len(program.inputs))}
    sources: list[list[tuple[str, int]]] = []  # each instruction's operands' producers
    in_tail: list[bool] = []
    for op in code:
        sources.append([producer[slot] for slot in _operands(op)])
        in_tail.append(op.operation != "const" and (op.operation in _FLAGGED or any(
            (kind == "input" and k in varying_input) or (kind == "op" and in_tail[k])
            for kind, k in sources[-1])))
        producer[op.destination] = ("op", len(in_tail) - 1)
    outputs = [producer[slot] for slot in program.outputs]
    read_by_tail = {k for j, srcs in enumerate(sources) if in_tail[j]
                    for kind, k in srcs if kind == "op"}
    read_by_tail |= {k for kind, k in outputs if kind == "op"}
    read_by_head = {k for j, srcs in enumerate(sources) if not in_tail[j]
                    for kind, k in srcs if kind == "op"}
    constant = [op.operation == "const" for op in code]
    fixed = {}
    for k in sorted(read_by_tail):
        if not in_tail[k] and not constant[k]:
            fixed[k] = first_fixed + len(fixed)

    def slot(source: tuple[str, int]) -> int:
        kind, k = source
        if kind == "op" and k in fixed:
            return fixed[k]
        return base + (k if kind == "input" else code[k].destination)

    def part(keep, results) -> IntervalProgram:
        kept = [k for k in range(len(code)) if keep(k)]
        constants: dict[int, int] = {}
        instructions = []
        for k in kept:
            op = code[k]
            if constant[k]:
                left = constants.setdefault(op.left, len(constants))
                right = 0
            else:
                operands = [slot(source) for source in sources[k]]
                left = operands[0]
                right = operands[1] if len(operands) > 1 else op.right  # pow: its exponent
            instructions.append(IntervalInstruction(op.operation, slot(("op", k)), left, right))
        return IntervalProgram(program.inputs, tuple(instructions),
                               tuple(program.constants[c] for c in constants),
                               tuple(slot(source) for source in results),
                               base + program.n_slots, first_input=base)

    head = part(lambda k: not in_tail[k] and (not constant[k] or k in read_by_head), [])
    tail = part(lambda k: in_tail[k] or (constant[k] and k in read_by_tail), outputs)
    return SplitProgram(head=head, tail=tail, n_fixed=len(fixed))


@dataclass(frozen=True)
class InlineTail:
    """A tail as C statements, one local per instruction (the inline form of
    CODEGEN_INLINE_INTERVALS): the same operations as the program, in its order."""

    unpack: tuple[tuple[str, int], ...]        # (input, its slot) the tail reads
    statements: tuple[tuple[str, str], ...]    # (local, C expression of type codegen_iv)
    outputs: tuple[str, ...]
    unused: tuple[str, ...]                    # of params, the flags and the slots v


def inline_tail(tail: IntervalProgram, varying: set[str], flags: str) -> InlineTail:
    """The tail as statements: an input read by its name (a parameter unpacked as a point,
    theta as the function's own argument), a fixed slot s as v[s], a constant as a
    literal."""
    prefix = _temporary_prefix({sp.Symbol(name) for name in tail.inputs})
    text = {tail.first_input + i: name for i, name in enumerate(tail.inputs)}
    statements, flagged, fixed = [], False, False

    def operand(slot: int) -> str:
        nonlocal fixed
        if slot < tail.first_input:
            fixed = True
            return f"v[{slot}]"
        return text[slot]

    for k, op in enumerate(tail.instructions):
        if op.operation == "const":
            lo, hi = tail.constants[op.left]
            text[op.destination] = (f"codegen_iv_point({lo})" if lo == hi
                                    else f"codegen_iv_make({lo}, {hi})")
            continue
        args = [operand(slot) for slot in _operands(op)]
        if op.operation == "pow":
            args.append(str(op.right))
        if op.operation in _FLAGGED:
            args.append(flags)
            flagged = True
        name = f"{prefix}{k}"
        statements.append((name, f"codegen_iv_{op.operation}({', '.join(args)})"))
        text[op.destination] = name
    outputs = tuple(operand(slot) for slot in tail.outputs)
    read = inputs_read(tail)
    unpack = tuple((name, slot) for name, slot in read if name not in varying)
    unused = tuple(sorted(varying - {name for name, _ in read})) + (
        () if unpack else ("params",)) + (() if flagged else (flags,)) + (
        () if fixed else ("v",))
    return InlineTail(unpack, tuple(statements), outputs, unused)


def inputs_read(program: IntervalProgram) -> tuple[tuple[str, int], ...]:
    """The inputs an instruction or an output reads, with their slots, in input order."""
    live = {program.first_input + i for i in range(len(program.inputs))}
    read = set()
    for op in program.instructions:
        read |= live.intersection(_operands(op))
        live.discard(op.destination)
    read |= live.intersection(program.outputs)
    return tuple((program.inputs[slot - program.first_input], slot) for slot in sorted(read))


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


class _Tape:
    """Operations as instructions over slots: the program form. A value made inside an
    expression (scratch) is freed when an operation consumes it; a named value (an input or
    a temporary) when the statement holding its last use is done."""

    def __init__(self, inputs: list[str]):
        self.slots = {name: i for i, name in enumerate(inputs)}
        self.size = len(inputs)
        self.free: list[int] = []
        self.named = set(range(len(inputs)))
        self.kept: set[int] = set()  # the outputs' slots
        self.code: list[IntervalInstruction] = []
        self.constants: dict[tuple[str, str], int] = {}

    def _take(self, operation: str, left: int, right: int = 0) -> int:
        slot = self.free.pop() if self.free else self.size
        self.size = max(self.size, slot + 1)
        self.code.append(IntervalInstruction(operation, slot, left, right))
        return slot

    def _consume(self, *slots: int) -> None:
        for slot in slots:
            if slot not in self.named and slot not in self.free:
                self.free.append(slot)

    def release(self, slot: int) -> None:
        """A named value no statement reads any more (unless it is an output)."""
        if slot not in self.kept:
            self.named.discard(slot)
            self._consume(slot)

    def symbol(self, name: str) -> int:
        return self.slots[name]

    def constant(self, value: sp.Expr) -> int:
        pair = _bound_texts(value)
        return self._take("const", self.constants.setdefault(pair, len(self.constants)))

    def one(self) -> int:
        return self.constant(sp.S.One)

    def apply(self, operation: str, *operands: int) -> int:
        self._consume(*operands)
        return self._take(operation, *operands)

    def power(self, operand: int, n: int) -> int:
        self._consume(operand)
        return self._take("pow", operand, n)


def _program(inputs: list[str], statements, outputs) -> IntervalProgram:
    """statements: (name, expr) in order, then the outputs, as a program over slots."""
    tape = _Tape(inputs)
    writer = _Writer(tape)
    exprs = [e for _, e in statements] + list(outputs)
    last = {}  # the statement of each name's last read
    for k, e in enumerate(exprs):
        for s in e.free_symbols:
            last[s.name] = k
    ending: dict[int, list[str]] = {}  # statement -> the names read there for the last time,
    for name in sorted(last):          # sorted: slots must not follow the order of a set
        ending.setdefault(last[name], []).append(name)
    for name in list(tape.slots):  # inputs no statement reads
        if name not in last:
            tape.release(tape.slots[name])

    def done(k: int) -> None:
        for name in ending.get(k, ()):
            tape.release(tape.slots[name])

    for k, (name, expr) in enumerate(statements):
        slot = writer.write(expr)
        if slot in tape.named:  # a copy of an earlier value: its own slot, value + 0
            slot = tape.apply("add", slot, tape.constant(sp.S.Zero))
        tape.named.add(slot)
        tape.slots[name] = slot
        done(k)
    result = []
    for k, expr in enumerate(outputs, start=len(statements)):
        slot = writer.write(expr)
        tape.named.add(slot)
        tape.kept.add(slot)  # read by the caller after the last instruction
        result.append(slot)
        done(k)
    return IntervalProgram(tuple(inputs), tuple(tape.code), tuple(tape.constants),
                           tuple(result), tape.size)


def _bound_texts(value: sp.Expr) -> tuple[str, str]:
    """A constant's lower and upper bounds as C text; the same text twice (a literal exact
    in both types) when it is exact in double and in float."""
    lo, hi = enclose_constant(value)
    flo, fhi = enclose_constant(value, np.float32)
    if lo == hi == flo == fhi:
        return (_point(lo),) * 2
    return (f"CODEGEN_BOUND({_literal(lo)}, {_literal(flo)})",
            f"CODEGEN_BOUND({_literal(hi)}, {_literal(fhi)})")


class _Writer:
    """Walks an expression in the interval rules, writing each operation through ``out``
    (a _Tape)."""

    def __init__(self, out):
        self.out = out

    def write(self, expr: sp.Expr):
        out = self.out
        if expr.is_Symbol:
            return out.symbol(expr.name)
        if expr.is_number:
            return out.constant(expr)
        if expr.is_Add:
            terms = sorted(expr.args, key=sp.default_sort_key)
            total = self.write(terms[0])
            for term in terms[1:]:
                if term.could_extract_minus_sign():
                    total = out.apply("sub", total, self.write(-term))
                else:
                    total = out.apply("add", total, self.write(term))
            return total
        if expr.is_Mul:
            coefficient, factors = expr.as_coeff_mul()
            if coefficient < 0:
                return out.apply("neg", self.write(-expr))
            parts = ([coefficient] if coefficient != 1 else []) + sorted(
                factors, key=sp.default_sort_key)
            denominators = [p.base ** -p.exp for p in parts if p.is_Pow and p.exp.is_negative]
            numerators = [p for p in parts if not (p.is_Pow and p.exp.is_negative)]
            total = self._product(numerators)
            if denominators:
                total = out.apply("div", total, self._product(denominators))
            return total
        if expr.is_Pow:
            return self._power(expr.base, expr.exp)
        if isinstance(expr, (sp.sin, sp.cos)):
            return out.apply(type(expr).__name__, self.write(expr.args[0]))
        if isinstance(expr, sp.Abs):  # sqrt(n s^2) written out: sqrt(n) |s|
            return out.apply("abs", self.write(expr.args[0]))
        raise ValueError(f"no interval rule for {type(expr).__name__} in {expr}: the certified "
                         "isolation supports +, -, *, /, integer powers and powers p/2^k, "
                         "sin, cos and |.|")

    def _product(self, parts):
        if not parts:
            return self.out.one()
        total = self.write(parts[0])
        for part in parts[1:]:
            total = self.out.apply("mul", total, self.write(part))
        return total

    def _power(self, base: sp.Expr, exp: sp.Expr):
        out = self.out
        if exp.is_negative:
            one = out.one()
            return out.apply("div", one, self._power(base, -exp))
        if exp.is_Integer:
            return out.power(self.write(base), int(exp))
        if exp.is_Rational and exp.q & (exp.q - 1) == 0:   # q = 2^k: k nested square roots
            root = self.write(base)
            for _ in range(exp.q.bit_length() - 1):
                root = out.apply("sqrt", root)
            return root if exp.p == 1 else out.power(root, int(exp.p))
        raise ValueError(f"no interval rule for the power {exp} in {base ** exp}")


def singular_parts(expr: sp.Expr, definitions=()) -> list[sp.Expr]:
    """Every division and root that evaluating expr (and the ``definitions`` it reads)
    performs: the powers with a negative or a fractional exponent, whose interval operations
    alone raise the flags (a pole, a square root's edge, no state). An interval program of
    these tells whether expr is smooth on an interval for a fraction of expr's cost."""
    exprs = [sp.sympify(expr), *(sp.sympify(e) for _, e in needed_definitions(definitions, [expr]))]
    parts = {p for e in exprs for p in e.atoms(sp.Pow)
             if p.exp.is_negative or not p.exp.is_integer}
    return sorted(parts, key=sp.default_sort_key)


def interval_body(exprs: list[sp.Expr], parameters: tuple[str, ...], inputs: set[str],
                  definitions=()) -> IntervalBody:
    """exprs (in the parameters and ``inputs``, and the symbols of ``definitions``, a
    straight-line program: (symbol, expression) in order) as one interval program."""
    program = needed_definitions(definitions, exprs)
    used = set().union(*(e.free_symbols for e in exprs), *(d.free_symbols for _, d in program))
    replacements, reduced = shared_with_program(program, exprs, _temporary_prefix(used))
    if program:
        replacements = in_dependency_order(replacements)
    names = {s.name for s in used} - {symbol.name for symbol, _ in program}
    unknown = names - set(parameters) - inputs
    if unknown:
        raise ValueError(f"symbols {sorted(unknown)} are neither parameters nor inputs")
    operations = sum(sp.count_ops(e) for _, e in replacements) + sum(
        sp.count_ops(e) for e in reduced)
    unpack = [p for p in parameters if p in names]
    return IntervalBody(operations=int(operations),
                        program=_program([*unpack, *sorted(inputs)],
                                         [(str(s), e) for s, e in replacements], reduced))
