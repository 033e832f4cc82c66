"""An analysis as text for a terminal (the command line prints it).

The default table fits 100 columns: the angle, what the root is, whether it is proven, the
stiffness and the vibration. ``wide`` adds M_EQ, B_EQ and the eigenvalues. A quantity with no
meaning for a root (anything but the angle of an extraneous root, omega_n where M = 0) is "-".
"""
from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Callable

from . import common
from ..runtime.analysis import (KINDS, STABILITY, Analysis, Equilibrium, MultibodyAnalysis,
                                coordinates_of)

if TYPE_CHECKING:   # branches builds on sweep: imported only for the type
    from ..runtime.branches import Branches

WIDTH = 100


#: Fixed decimals up to here; a larger value in scientific notation (not hundreds of digits).
LARGEST_FIXED = 1e10


def _number(x: float, digits: int = 4) -> str:
    """Fixed decimals like the paper's Table 3, scientific below 1e-2 and from LARGEST_FIXED;
    never a negative zero."""
    x += 0.0  # -0.0 + 0.0 is +0.0
    fixed = x == 0 or 1e-2 <= abs(x) < LARGEST_FIXED
    return f"{x:.{digits}f}" if fixed else f"{x:.{digits}e}"


def _complex(z: complex, digits: int = 4) -> str:
    if z.imag == 0:
        return _number(z.real, digits)
    if z.real == 0:
        return f"{_number(z.imag, digits)} i"
    return f"{_number(z.real, digits)}{'+' if z.imag >= 0 else '-'}{_number(abs(z.imag), digits)} i"


LABELS = {"equilibrium": "equilibrium", "other assembly mode": "other mode",
          "extraneous": "extraneous", "mode undecided": "mode ?"}


#: The table's legend for complex quantities and extraneous roots (docs/python.md has the
#: same convention for JSON, CSV, Python and C).
COMPLEX_NOTE = (" A value \"x i\" is imaginary: where K_EQ < 0, omega_n = sqrt(K/M) "
                "and zeta are (JSON [re, im], Python complex, C arrays [2] of re, im).")
EXTRANEOUS_NOTE = ("An extraneous root is not an equilibrium: it has no stability, damping or "
                   "vibration (\"-\"; null in JSON and CSV, None in Python).")


@dataclass(frozen=True)
class Column:
    header: str
    width: int
    text: Callable[[Equilibrium], str]
    physical: bool = True   # "-" for an extraneous root: not a state of the mechanism
    wide: bool = False      # only in the wide table


def _defined(x: float, text: str) -> str:
    """A value, or "-" where it is undefined (no inertia: NaN)."""
    return "-" if math.isnan(x) else text


COLUMNS = (
    Column("theta_E [deg]", 13, lambda r: f"{r.theta_deg + 0.0:.4f}", physical=False),
    Column("kind", 11, lambda r: LABELS[r.kind], physical=False),
    Column("proof", 9, lambda r: "certified" if r.certified else "-", physical=False),
    Column("M_EQ", 10, lambda r: _number(r.M), wide=True),
    Column("B_EQ", 11, lambda r: _number(r.B), wide=True),
    Column("K_EQ", 11, lambda r: _number(r.K)),
    Column("omega_n", 12, lambda r: _defined(r.omega_n.real, _complex(r.omega_n))),
    Column("zeta", 13, lambda r: _defined(r.zeta.real, _complex(r.zeta))),
    Column("eigenvalues [1/s]", 36, lambda r: _defined(
        r.eigenvalues[0].real, ", ".join(_complex(z) for z in r.eigenvalues)), wide=True),
    Column("stability", 9, lambda r: r.stability or "-"),
    Column("damping", 11, lambda r: r.damping or "-"),
)


def _rows(analysis: Analysis, wide: bool) -> list[str]:
    columns = [c for c in COLUMNS if wide or not c.wide]
    head = " ".join(f"{c.header:>{c.width}}" for c in columns)
    lines = [head, "-" * len(head)]
    for r in analysis.roots:
        meaningless = r.kind == "extraneous"
        lines.append(" ".join(
            f"{'-' if meaningless and c.physical else c.text(r):>{c.width}}" for c in columns))
    return lines


def paragraph(text: str) -> str:
    """Prose wrapped to the table's width."""
    return textwrap.fill(text, WIDTH, break_on_hyphens=False)


def _modal(z: complex) -> str:
    """A mode's omega_n or zeta to 6 digits, "x i" where it is imaginary (an unstable mode),
    "-" where it is undefined, as one coordinate's table prints them."""
    if math.isnan(z.real) or math.isnan(z.imag):
        return "-"
    if z.imag == 0:
        return f"{z.real + 0.0:.6g}"
    if z.real == 0:
        return f"{z.imag + 0.0:.6g} i"
    return f"{z.real + 0.0:.6g}{'+' if z.imag >= 0 else '-'}{abs(z.imag):.6g} i"


def _several_table(analysis: MultibodyAnalysis) -> str:
    """Every equilibrium of a mechanism with n coordinates, numbered from 1: its coordinates
    (angles in degrees), stability, and each mode's natural frequency and damping ratio;
    then the boxes that could not be decided."""
    coordinates = coordinates_of(analysis.library)
    names = [f"{c.name} [{'deg' if c.angle else c.unit}]" for c in coordinates]

    def shown(values: Any) -> list[float]:
        return [math.degrees(v) if c.angle else float(v) for v, c in zip(values, coordinates)]

    n = len(coordinates)
    modes = [f"{h} {j + 1}" for j in range(n) for h in ("omega_n", "zeta")]
    header = ["#", *names, "stability", *modes]
    rows = [[str(i + 1), *(f"{round(v, 6) + 0.0:.6f}" for v in shown(e.theta)), e.stability,
             *(_modal(z) for j in range(n) for z in (e.omega_n[j], e.zeta[j]))]
            for i, e in enumerate(analysis.equilibria)]
    widths = [max(len(r[k]) for r in [header, *rows]) for k in range(len(header))]
    lines = ["  ".join(cell.rjust(w) for cell, w in zip(row, widths)).rstrip()
             for row in [header, *rows]]
    imaginary = any(z.imag for e in analysis.equilibria for z in e.omega_n)
    lines += ["", f"{len(analysis.equilibria)} equilibri"
              f"{'um' if len(analysis.equilibria) == 1 else 'a'}, each proven to be the only "
              "one in its box; omega_n [rad/s] undamped, zeta each mode's damping ratio"
              + (" (\"x i\": imaginary, an unstable mode)" if imaginary else "")]
    for u in analysis.uncertain:
        box = ", ".join(f"{name} in [{a:.6f}, {b:.6f}]" for name, a, b in
                        zip(names, shown(u.lo), shown(u.hi)))
        lines.append(f"uncertain ({u.kind}, not an equilibrium): {box}")
    return "\n".join(lines)


def table(analysis: Analysis | MultibodyAnalysis, wide: bool = False,
          sigma: bool = False) -> str:
    """A table like the paper's Table 3, plus what the paper leaves implicit; ``wide`` adds
    every column, ``sigma`` the polynomial's coefficients. With several coordinates, a row
    per equilibrium numbered from 1, each mode's omega_n and zeta (``wide`` adds nothing)."""
    if isinstance(analysis, MultibodyAnalysis):
        return _several_table(analysis) + (
            "\nNo sigma: the isolation route works on G itself." if sigma else "")
    lines = _rows(analysis, wide)
    count = {k: sum(r.kind == k for r in analysis.roots) for k in KINDS}
    parts = [f"{count['equilibrium']} equilibri{'um' if count['equilibrium'] == 1 else 'a'}"]
    parts += [f"{count['other assembly mode']} of another assembly mode"] * bool(
        count["other assembly mode"])
    parts += [f"{count['extraneous']} extraneous (a negative length)"] * bool(count["extraneous"])
    parts += [f"{count['mode undecided']} in no declared assembly mode"] * bool(
        count["mode undecided"])
    parts += [f"{len(analysis.singular)} singular"] * bool(analysis.singular)
    parts += [f"{len(analysis.unassembled)} where it cannot be assembled"] * bool(
        analysis.unassembled)
    parts += [f"{len(analysis.uncertain)} undecided in double precision"] * bool(
        analysis.uncertain)
    proven = sum(r.certified for r in analysis.roots)
    if analysis.method == "polynomial":
        n = len(analysis.roots) + len(analysis.singular) + len(analysis.unassembled)
        summary = (f"{n} real roots of the polynomial: {', '.join(parts)}; "
                   f"{proven} certified by interval enclosures.")
    else:
        summary = (f"Certified isolation of the zeros of G: {', '.join(parts)}. Each "
                   "equilibrium is proven in an interval where G changes sign and G' keeps "
                   "its sign; none are missed outside the intervals listed.")
    notes = [summary]
    for title, angles in (("a square root is zero, so G is undefined", analysis.singular),
                          ("the mechanism cannot be assembled", analysis.unassembled)):
        if angles:
            listed = ", ".join(f"{math.degrees(t) + 0.0:.4f}" for t in angles)
            notes.append(f"Roots where {title}: {listed} deg.")
    for u in analysis.uncertain:
        what = ("G and G' are within rounding of zero (a fold, a pair closer than double "
                "separates, or none)" if u.kind == "cluster" else
                "G is undefined or not smooth (a pole or a limit position): no equilibrium "
                "is claimed")
        change = "; G changes sign across it: at least one equilibrium" if u.sign_change else ""
        notes.append(f"Undecided [{u.lo_deg + 0.0:.10f}, {u.hi_deg + 0.0:.10f}] deg "
                     f"(mode {'undecided' if u.mode is None else u.mode}): {what}{change}.")
    notes.append("Angles in degrees, omega_n in rad/s, zeta dimensionless; M, B and K in SI "
                 "units of the coordinate." + (COMPLEX_NOTE if any(
                     r.omega_n.imag for r in analysis.roots) else ""))
    if count["extraneous"]:
        notes.append(EXTRANEOUS_NOTE)
    lines += [""] + [paragraph(n) for n in notes]
    if sigma and analysis.sigma:
        lines.append(f"sigma_0..sigma_{len(analysis.sigma) - 1}:")
        lines += [f"  sigma_{i:<2} = {s + 0.0: .10e}" for i, s in enumerate(analysis.sigma)]
    elif sigma:
        lines.append("No sigma: the isolation route works on G itself.")
    return "\n".join(lines)


def _plural(count: int, noun: str) -> str:
    """'1 fold', '2 folds', '3 branches'."""
    return f"{count} {noun}" if count == 1 else \
        f"{count} {noun}{'es' if noun.endswith(('ch', 'sh', 's')) else 's'}"


def _stabilities(codes: Sequence[int]) -> str:
    """The stabilities a branch passes through, in order: 'unstable -> stable'."""
    seen = [STABILITY[c] for i, c in enumerate(codes) if i == 0 or c != codes[i - 1]]
    return " -> ".join(seen)


def _positions(result: Branches) -> tuple[str, Callable[[Any], str], str]:
    """The coordinates' heading, a position's text (angles in degrees) and what K is: for
    one coordinate theta_E and K_EQ; for n, each coordinate by name and det K."""
    library = result.library
    if library.dof == 1:
        return "theta_E", lambda t: f"{math.degrees(t) + 0.0:.4f}", "K_EQ"
    coordinates = library.SPEC["coordinates"]
    units = ["deg" if c["unit"] == "rad" else c["unit"] for c in coordinates]
    names = [c["name"] for c in coordinates]
    heading = (f"{', '.join(names)} [{units[0]}]" if len(set(units)) == 1 else
               ", ".join(f"{n} [{u}]" for n, u in zip(names, units)))

    def text(theta: Any) -> str:   # rounded first: never a negative zero
        return ", ".join(f"{round(math.degrees(v) if u == 'deg' else float(v), 4) + 0.0:.4f}"
                         for v, u in zip(theta, units))
    return heading, text, "det K"


def branch_summary(result: Branches) -> str:
    """The branches of a ``codegen.runtime.branches.Branches`` for a terminal: what was varied,
    a line per branch (where it runs and its stability), a line per event. With n
    coordinates a position is each coordinate's value, and det K stands for K_EQ."""
    name, unit = result.parameter, result.unit
    # an angle parameter shown in degrees, as --from, --to and --set read it
    shown = math.degrees if unit == "rad" else (lambda value: value)
    unit = "deg" if unit == "rad" else unit
    others = common.params_line({k: v for k, v in vars(result.base).items() if k != name},
                                result.library.UNITS)
    kinds = [e.kind for e in result.events]
    counted = [_plural(result.count, "branch"), *(
        _plural(kinds.count(k), k) for k in ("fold", "pitchfork") if k in kinds)]
    lines = [paragraph(
        f"Equilibria of {result.library.TITLE} as {name} runs from {shown(result.values[0]):g} "
        f"to {shown(result.values[-1]):g} {unit} over {len(result.values):,} values (the other "
        f"parameters: {others}; {result.method} route): {', '.join(counted)}."), ""]
    heading, position, K = _positions(result)
    one = result.library.dof == 1
    ends = [[position(t) for t in result.branch(number)["theta"][[0, -1]]]
            for number in range(result.count)]
    if one:
        start, stop = f"{heading} from [deg]", "to [deg]"
        widths = (19, 10)
    else:
        start, stop = f"{heading} from", "to"
        widths = tuple(1 + max([len(h), *(len(e[k]) for e in ends)]) for k, h in
                       enumerate((start, stop)))
    head = (f"{'branch':>6} {name + ' from':>14} {name + ' to':>14} {start:>{widths[0]}} "
            f"{stop:>{widths[1]}}  stability")
    lines += [head, "-" * len(head)]
    for number in range(result.count):
        rows = result.branch(number)
        lines.append(f"{number:>6} {shown(rows['value'][0]):>14.8g} "
                     f"{shown(rows['value'][-1]):>14.8g} "
                     f"{ends[number][0]:>{widths[0]}} {ends[number][1]:>{widths[1]}}  "
                     f"{_stabilities(rows['stability'])}")
    if result.events:
        where = [position(e.theta) for e in result.events]
        column = f"{heading} [deg]" if one else heading
        width = max([13 if one else 1 + len(column), *(len(w) for w in where)])
        head = (f"{'event':<16} {name + ' [' + unit + ']':>18} {column:>{width}} "
                f"{K:>12}  branches")
        lines += ["", head, "-" * len(head)]
        for e, at in zip(result.events, where):
            side = (f" ({' -> '.join(e.stability)})" if e.kind == "stability change" else
                    f" (exist {e.side})")
            lines.append(f"{e.kind:<16} {shown(e.value):>18.10g} {at:>{width}} "
                         f"{_number(e.K):>12}  {', '.join(map(str, e.branches))}{side}")
    notes = [f"A fold is where two equilibria meet and vanish, a pitchfork where two meet on a "
             f"third ({K} -> 0 at both); every event is located by bisection to "
             f"{shown(result.tolerance):.1g} {unit}." if result.events else
             "No branch ends or changes stability in this range."]
    if len(result.failed):
        names = {v: k for k, v in result.library.STATUS.items()}
        why = sorted({names.get(int(s), str(s)) for s in result.statuses if s != 0})
        notes.append(f"{len(result.failed):,} values failed ({', '.join(why)}); the branches "
                     "are joined across them.")
    notes.append("Angles in degrees; K_EQ in SI units of the coordinate." if one else
                 "Angles in degrees; det K, the stiffness matrix's determinant, in SI units "
                 "of the coordinates.")
    return "\n".join(lines + [""] + [paragraph(n) for n in notes])
