"""Straight-line polynomial programs as instructions for the runtime's
double-double machine (runtime/codegen_dd.c).

Squaring the square roots out of G cancels up to ~13 digits in sigma's low coefficients,
so sigma is evaluated in double-double. Written as C calls, the thousands of operations of
a high-degree program take compilers minutes and gigabytes; as a table of three-address
instructions (operation, destination, operands) they compile instantly, and the machine
runs them with its arithmetic inlined. Values live in one array v: the inputs first, then
each named value of the program, then scratch slots for the inside of expressions, reused
as soon as an expression has consumed them.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

OPERATIONS = ("CONST", "ADD", "SUB", "MUL", "DIV", "NEG")
#: Integers below this are exact in float (and double).
EXACT_BITS = 2**24


@dataclass(frozen=True)
class Instruction:
    operation: str   # one of OPERATIONS
    destination: int
    left: int        # a slot; for CONST, an index into the constants
    right: int = 0
    label: str = ""  # the named value this instruction completes, if any


@dataclass(frozen=True)
class Program:
    inputs: tuple[str, ...]            # names of v[0..], filled by the caller
    instructions: tuple[Instruction, ...]
    constants: tuple[float, ...]
    outputs: tuple[int, ...]           # the slot of each output
    n_values: int


class _Assembler:
    def __init__(self, inputs):
        self.slots = {name: i for i, name in enumerate(inputs)}
        self.size = len(inputs)
        self.free: list[int] = []
        self.named = set(range(len(inputs)))  # slots whose values outlive an expression
        self.code: list[Instruction] = []
        self.constants: dict[float, int] = {}

    def scratch(self) -> int:
        if self.free:
            return self.free.pop()
        self.size += 1
        return self.size - 1

    def release(self, slot: int, named: set[int]) -> None:
        if slot not in named and slot not in self.free:
            self.free.append(slot)

    def emit(self, operation, left, right=0) -> int:
        target = self.scratch()
        self.code.append(Instruction(operation, target, left, right))
        return target

    def constant(self, value: sp.Rational) -> int:
        """A constant from numbers exact in float as well as double (24 bits), so that one
        table serves both builds."""
        p, q = int(value.p), int(value.q)
        if q & (q - 1):  # not dyadic: a quotient
            return self.binary("DIV", sp.Integer(p), sp.Integer(q))
        odd = abs(p) >> ((abs(p) & -abs(p)).bit_length() - 1) if p else 0
        if odd >= EXACT_BITS:  # high * 2^24 + low, each exact
            high, low = divmod(abs(p), EXACT_BITS)
            sign = 1 if p > 0 else -1
            return self.binary("ADD", sp.Rational(sign * high * EXACT_BITS, q),
                               sp.Rational(sign * low, q))
        index = self.constants.setdefault(float(value), len(self.constants))
        return self.emit("CONST", index)

    def binary(self, operation, left, right) -> int:
        return self._combine(operation, self.value(left), right)

    def value(self, expr: sp.Expr) -> int:
        """The slot holding expr (a named slot, or a new scratch slot)."""
        if expr.is_Symbol:
            return self.slots[expr.name]
        if expr.is_Rational:
            return self.constant(expr)
        if expr.is_Add:
            terms = sorted(expr.args, key=sp.default_sort_key)
            total = self.value(terms[0])
            for term in terms[1:]:
                negative = term.could_extract_minus_sign()
                total = self._combine("SUB" if negative else "ADD", total,
                                      -term if negative else term)
            return total
        if expr.is_Mul:
            coefficient, factors = expr.as_coeff_mul()
            if coefficient < 0:
                inner = self.value(-expr)
                self.release(inner, self.named)
                return self.emit("NEG", inner)
            parts = ([] if coefficient == 1 else [coefficient]) + sorted(
                factors, key=sp.default_sort_key)
            product = self.value(parts[0])
            for factor in parts[1:]:
                product = self._combine("MUL", product, factor)
            return product
        if expr.is_Pow and expr.exp.is_Integer and expr.exp > 0:
            product = self.value(expr.base)
            for _ in range(int(expr.exp) - 1):
                product = self._combine("MUL", product, expr.base)
            return product
        if expr.is_Pow and expr.exp.is_Integer and expr.exp < 0:
            return self.binary("DIV", sp.S.One, expr.base ** -expr.exp)
        raise ValueError(f"no double-double rule for {type(expr).__name__}: {expr}")

    def _combine(self, operation, slot, expr) -> int:
        other = self.value(expr)
        self.release(slot, self.named)
        self.release(other, self.named)
        return self.emit(operation, slot, other)


def assemble(inputs, statements, outputs) -> Program:
    """inputs: names; statements: (name, expr) in order; outputs: expressions."""
    asm = _Assembler(inputs)
    # A named value's slot is free again after the last statement that reads it (the
    # outputs' operands are kept to the end): shared subexpressions are many, short-lived.
    last_read: dict[str, int] = {}
    for i, (_, expr) in enumerate(statements):
        for symbol in sp.sympify(expr).free_symbols:
            last_read[symbol.name] = i
    for expr in outputs:
        for symbol in sp.sympify(expr).free_symbols:
            last_read[symbol.name] = len(statements)
    for i, (name, expr) in enumerate(statements):
        slot = asm.value(expr)
        if slot in asm.named:  # a plain copy of an earlier value: its own slot, slot + 0
            slot = asm.binary("ADD", expr, sp.S.Zero)
        asm.named.add(slot)
        asm.slots[name] = slot
        last = asm.code[-1]
        asm.code[-1] = Instruction(last.operation, last.destination, last.left, last.right, name)
        for symbol in sorted(sp.sympify(expr).free_symbols | {sp.Symbol(name)}, key=str):
            if last_read.get(symbol.name, i) == i and symbol.name in asm.slots:
                freed = asm.slots[symbol.name]
                asm.named.discard(freed)
                asm.release(freed, asm.named)
    result = []
    for expr in outputs:
        slot = asm.value(expr)
        asm.named.add(slot)  # kept until the caller reads it
        result.append(slot)
    return Program(tuple(inputs), tuple(asm.code), tuple(asm.constants), tuple(result),
                   asm.size)
