"""What a mechanism must satisfy before anything is derived from it.

``check(mechanism, path)`` raises ModelError with one line naming the first problem (and,
for a model file, the line of the file where the offending name or square root is written),
instead of a derivation, a C compiler or cffi failing minutes later on it.
"""
from __future__ import annotations

import keyword
import re
from collections import Counter
from pathlib import Path

import sympy as sp
from sympy.core.function import AppliedUndef

from .mechanism import TIME, Mechanism
from .names import c_identifier, refusal

#: How to declare a square root of the coordinates (README: "Your own mechanism").
DECLARE = ("write a length between two points as distance(p, q) in a spring or damper, a "
           "(length, angle) coordinate pair in polar_pairs, and an assembly mode through the "
           "constraints and assembly_modes")


class ModelError(ValueError):
    """A model that cannot be derived; the message is one line and names the file."""


#: The C99 standard headers: a library's header NAME.h beside its sources would hide one.
STANDARD_HEADERS = frozenset(
    "assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal "
    "stdarg stdbool stddef stdint stdio stdlib string tgmath time wchar wctype".split())


def check(mechanism: Mechanism, path: Path | None = None) -> None:
    """Raise ModelError for the first problem of the mechanism (read from ``path``)."""
    for problem in (_names, _undeclared, _roots):
        found = problem(mechanism)
        if found:
            message, written = found
            raise ModelError(_located(path, written, message))


def _located(path: Path | None, written: tuple[str, ...], message: str) -> str:
    """'PATH:LINE: message', the line the first one (outside comments) where the first of
    the regular expressions ``written`` that matches anywhere matches; 'PATH: message' where
    none does; the message alone for a shipped model."""
    if path is None:
        return message
    try:
        lines = [line.split("#")[0] for line in Path(path).read_text().splitlines()]
    except (OSError, UnicodeDecodeError):
        lines = []
    for pattern in written:
        number = next((i for i, line in enumerate(lines, 1) if re.search(pattern, line)), None)
        if number:
            return f"{path}:{number}: {message}"
    return f"{path}: {message}"


def _quoted(name: str) -> tuple[str, ...]:
    """Where a name is given as a string (parameter("k", ...), Coordinate("theta", ...))."""
    return (rf"""["']{re.escape(name)}["']""",)


def _names(m: Mechanism):
    if not c_identifier(m.name) or keyword.iskeyword(m.name):
        return (f"the mechanism's name {m.name!r} is not a C identifier (it prefixes every C "
                "name of the library: letters, digits and _, not starting with a digit)",
                _quoted(m.name))
    if m.name == "runtime" or m.name.lower().startswith("codegen"):
        return (f"the mechanism's name {m.name!r} is the shared runtime's (its folder, or its "
                "prefix codegen): rename it", _quoted(m.name))
    if m.name in STANDARD_HEADERS:
        return (f"the mechanism's name {m.name!r} would make {m.name}.h, which hides the C "
                f"standard header <{m.name}.h>: rename it", _quoted(m.name))
    names = [p.symbol.name for p in m.parameters] + [c.name for c in m.coordinates]
    twice = [n for n, k in Counter(names).items() if k > 1]
    if twice:
        return (f"{twice[0]!r} names two parameters or coordinates", _quoted(twice[0]))
    for name in names:
        why = refusal(name, m.name)
        if why:
            return f"the name {name!r} {why}: rename it", _quoted(name)
    codes = [r.code for r in m.requirements]
    for code in codes:  # each names a status, PREFIX_ERR_CODE, of the C enum
        if not c_identifier(f"E_{code}") or codes.count(code) > 1:
            return (f"the requirement code {code!r} is not a C identifier's end or names two "
                    "requirements", _quoted(code))
    coordinates = {c.name for c in m.coordinates}
    if any(len(x) != m.dof for x in (m.centres, m.periodics)) or len(set(m.independents)) < m.dof:
        return ("give one range_centre and one periodic for each independent coordinate, and "
                "name each independent coordinate once", (r"\brange_centre\b", r"\bperiodic\b"))
    for name in (*m.independents, *(n for pair in m.polar_pairs for n in pair)):
        if name not in coordinates:
            return f"{name!r} is not one of the coordinates {sorted(coordinates)}", _quoted(name)
    return None


def _expressions(m: Mechanism):
    """(where, expression) for every expression of the model."""
    yield from ((f"constraint {i + 1}", e) for i, e in enumerate(m.constraints))
    for b in m.bodies:
        yield from ((f"body {b.name!r}", e) for e in (b.mass, *b.centre, b.inertia, b.angle))
    for i, s in enumerate(m.springs):
        yield from ((f"spring {i + 1}", e) for e in (s.stiffness, s.free_length, s.length))
    for i, d in enumerate(m.dampers):
        yield from ((f"damper {i + 1}", e) for e in (d.coefficient, d.length))
    for i, f in enumerate(m.forces):
        yield from ((f"force {i + 1}", e) for e in (*f.point, *f.force))
    for i, t in enumerate(m.torques):
        yield from ((f"torque {i + 1}", e) for e in (t.torque, t.angle))
    yield "gravity", m.gravity
    for name, point in m.points.items():
        yield from ((f"point {name!r}", e) for e in point)
    yield from ((f"requirement {r.code}", r.condition) for r in m.requirements)
    yield from ((f"assembly mode {i + 1}", e) for i, e in enumerate(m.assembly_modes))
    yield from (("range_centre", c) for c in m.centres)


def _undeclared(m: Mechanism):
    """A symbol that is no parameter's, or a function of time that is no coordinate."""
    coordinates = {c.function for c in m.coordinates}
    parameters = {p.symbol for p in m.parameters}
    by_name = {p.symbol.name: p.symbol for p in m.parameters}
    for where, expr in _expressions(m):
        expr = sp.sympify(expr)
        for f in sorted(expr.atoms(AppliedUndef) - coordinates, key=str):
            return (f"{where}: {f} is not one of the coordinates "
                    f"({', '.join(c.name for c in m.coordinates)})", _quoted(type(f).__name__))
        free = expr.xreplace({c: sp.Dummy() for c in coordinates}).free_symbols
        for s in sorted(free - parameters - {s for s in free if isinstance(s, sp.Dummy)},
                        key=str):
            if s == TIME:
                return (f"{where}: the time t appears outside the coordinates (the model is "
                        "autonomous)", (r"\bTIME\b",))
            hint = (" (a parameter's symbol is the real one parameter() makes: use "
                    "p.symbol)" if s.name in by_name else "")
            return (f"{where}: the symbol {s.name!r} is not a declared parameter{hint}",
                    _quoted(s.name) + (rf"\b{re.escape(s.name)}\b",))
    return None


def _is_square(term: sp.Expr) -> bool:
    """An even power, or a product of even powers and positive numbers (x**2 * y**2)."""
    factors = term.args if term.is_Mul else (term,)
    return any(f.is_Pow for f in factors) and all(
        (f.is_Pow and f.exp.is_even) or (f.is_number and f.is_positive) for f in factors)


def _is_distance(radicand: sp.Expr) -> bool:
    """A sum of two squares, as distance(p, q) makes, or one square written out (two points
    on one axis)."""
    terms = sp.Add.make_args(radicand)
    return (len(terms) <= 2 and all(_is_square(t) for t in terms)) or _is_square(
        sp.factor(radicand))


def _roots(m: Mechanism):
    """A square root of an expression of the coordinates that the model does not declare."""
    coordinates = tuple(c.function for c in m.coordinates)
    lengths = {id(e) for s in m.springs for e in (s.length,)} | {id(d.length) for d in m.dampers}
    for where, expr in _expressions(m):
        for power in sorted(sp.sympify(expr).atoms(sp.Pow), key=sp.default_sort_key):
            if not (power.exp.is_Rational and power.exp.q == 2 and power.base.has(*coordinates)):
                continue
            if id(expr) in lengths and _is_distance(power.base):
                continue
            text = str(sp.sqrt(power.base))
            text = text if len(text) <= 60 else text[:57] + "..."
            return (f"{where}: the square root {text} of an expression of the coordinates is "
                    f"not declared: {DECLARE}", (r"\bsqrt\(", "sqrt"))
    return None
