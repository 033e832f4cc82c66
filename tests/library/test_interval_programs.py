"""The two forms of every generated enclosure give the same bounds bit for bit.

A library runs its interval enclosures of G and G' as programs (codegen_iv_run over a few
slots: small stack and code, for firmware; the default on 32-bit targets, or
-DCODEGEN_INTERVAL_PROGRAMS) or expands them as inline calls, one local per operation
(-DCODEGEN_INLINE_INTERVALS; faster, the default on 64-bit targets and the Python
extension's form). A driver prints PREFIX_enclosure of every mode over random
intervals, from narrow to several turns wide, at parameter sets around the example; it is
compiled in both forms and in both real types, and the outputs must agree exactly. The
layer below is tested on its own too: the emission's slot allocation never reads a slot
before it is written nor overwrites a value still to be read.
"""
from __future__ import annotations

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
from libraries import generated_libraries
import sympy as sp

from codegen.api import load
from codegen.compiler.emission.interval import inline_tail, interval_body, split_program
from codegen.resources import cflags

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated"
MECHANISMS = generated_libraries(GENERATED, several=False)  # theirs: tests/runtime/test_multibody.py

DRIVER = r"""
#include <stdio.h>
#include "%(prefix)s.h"
#include "%(prefix)s_kernels.h"

/* Parameters (the header's order), then "lo hi" lines: every mode's enclosure as hex, then
 * the kernel's G alone (dg NULL) and its flags alone (g NULL too). */
int main(void)
{
    %(prefix)s_params params;
    double values[%(n)d], theta[2];
    int i;
    for (i = 0; i < %(n)d; ++i) {
        if (scanf("%%lf", &values[i]) != 1) {
            return 2;
        }
    }
%(assign)s
    while (scanf("%%lf %%lf", &theta[0], &theta[1]) == 2) {
        unsigned mode;
        for (mode = 0; mode < %(PREFIX)s_N_MODES; ++mode) {
            codegen_real t[2], g[2], dg[2];
            unsigned flags = 0;
            int status;
            t[0] = (codegen_real)theta[0];
            t[1] = (codegen_real)theta[1];
            codegen_iv value;
            unsigned value_flags = 0, smooth_flags = 0;
            status = (int)%(prefix)s_enclosure(&params, mode, t, g, dg, &flags);
            (void)%(prefix)s_enclosure_kernel(&params, mode, codegen_iv_make(t[0], t[1]), &value,
                                              NULL, &value_flags);
            (void)%(prefix)s_enclosure_kernel(&params, mode, codegen_iv_make(t[0], t[1]), NULL,
                                              NULL, &smooth_flags);
            printf("%%d %%a %%a %%a %%a %%u %%a %%a %%u %%u\n", status, (double)g[0], (double)g[1],
                   (double)dg[0], (double)dg[1], flags, (double)value.lo, (double)value.hi,
                   value_flags, smooth_flags);
        }
    }
    return 0;
}
"""


def _driver(tmp: Path, name: str, flags: list[str]) -> Path:
    lib = load(name)
    source = tmp / f"{name}_enclosure.c"
    assign = "\n".join(f"    params.{p} = (codegen_real)values[{i}];"
                       for i, p in enumerate(lib.PARAMETER_NAMES))
    source.write_text(DRIVER % {"prefix": lib.PREFIX, "PREFIX": lib.PREFIX.upper(),
                                "n": len(lib.PARAMETER_NAMES), "assign": assign})
    exe = tmp / f"{name}{''.join(flags).replace('-D', '_')}"
    sources = sorted((GENERATED / name).glob("*.c")) + sorted((GENERATED / "runtime").glob("*.c"))
    subprocess.run(["gcc", *cflags("base", "optimize"), *flags, f"-I{GENERATED / name}",
                    f"-I{GENERATED / 'runtime'}", str(source), *map(str, sources), "-lm",
                    "-o", str(exe)], check=True)
    return exe


def _inputs(name: str, seed: int) -> str:
    lib = load(name)
    rng = np.random.default_rng(seed)
    example = lib.example_params()
    values = [getattr(example, p) * rng.uniform(0.9, 1.1) for p in lib.PARAMETER_NAMES]
    lines = [" ".join(repr(float(v)) for v in values)]
    for _ in range(400):
        centre = rng.uniform(-math.pi, math.pi)
        half = 10.0 ** rng.uniform(-14, 1)
        lines.append(f"{centre - half!r} {centre + half!r}")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("real", ["double", "float"])
@pytest.mark.parametrize("name", MECHANISMS)
def test_interval_programs_and_inline_enclosures_agree_bit_for_bit(name, real, tmp_path):
    flags = ["-DCODEGEN_FLOAT"] if real == "float" else []
    programs = _driver(tmp_path, name, [*flags, "-DCODEGEN_INTERVAL_PROGRAMS"])
    inline = _driver(tmp_path, name, [*flags, "-DCODEGEN_INLINE_INTERVALS"])
    for seed in (1, 2):
        text = _inputs(name, seed)
        a = subprocess.run([str(programs)], input=text, capture_output=True, text=True,
                           check=True).stdout
        b = subprocess.run([str(inline)], input=text, capture_output=True, text=True,
                           check=True).stdout
        assert a.count("\n") == 400 * int(load(name).SPEC["sizes"]["N_MODES"])
        assert a == b


@pytest.mark.parametrize("name", MECHANISMS)
def test_the_flags_alone_say_where_g_is_smooth(name, tmp_path):
    """The flags-only enclosure (g NULL: G's divisions and square roots alone, which the
    analysis' sign tests ask where a span is expected to hold a zero) raises the flags G's own
    enclosure raises: the same operations on the same expressions. Where it raises none, G's
    enclosure is finite (no pole, every root defined). (The intervals reach several turns: the
    four-bar's and the slider-crank's raise flags on a few hundred of them.)"""
    exe = _driver(tmp_path, name, [])
    for seed in (1, 2):
        for line in subprocess.run([str(exe)], input=_inputs(name, seed), capture_output=True,
                                   text=True, check=True).stdout.splitlines():
            fields = line.split()
            lo, hi = float.fromhex(fields[6]), float.fromhex(fields[7])
            value_flags, smooth_flags = int(fields[8]), int(fields[9])
            assert smooth_flags == value_flags, line
            if smooth_flags == 0:
                assert math.isfinite(lo) and math.isfinite(hi), line


def _number(text: str) -> float:
    """A constant of a program's table as the double it names."""
    if text.startswith("CODEGEN_BOUND("):
        return float.fromhex(text[len("CODEGEN_BOUND("):].split(",")[0])
    if text.startswith("CODEGEN_R("):
        return float(text[len("CODEGEN_R("):-1])
    return float(text)


def _run(program, values: dict[str, float], v: dict[int, float] | None = None) -> list[float]:
    """The program executed in plain double arithmetic, slot by slot, as codegen_iv_run
    would (a constant by its lower bound), over the slots v (kept from an earlier program);
    reading a slot never written raises."""
    v = {} if v is None else v
    v.update({program.first_input + i: values[name] for i, name in enumerate(program.inputs)})
    unary = {"neg": lambda a: -a, "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos}
    binary = {"add": lambda a, b: a + b, "sub": lambda a, b: a - b,
              "mul": lambda a, b: a * b, "div": lambda a, b: a / b}
    for op in program.instructions:
        if op.operation == "const":
            r = _number(program.constants[op.left][0])
        elif op.operation == "pow":
            r = v[op.left] ** op.right
        elif op.operation in unary:
            r = unary[op.operation](v[op.left])
        else:
            r = binary[op.operation](v[op.left], v[op.right])
        v[op.destination] = r
    return [v[slot] for slot in program.outputs]


@pytest.mark.parametrize("seed", range(5))
def test_programs_compute_their_expressions(seed):
    """Slots reused wrongly (a value overwritten before its last read, an output clobbered)
    would change the numbers: the program run in floats matches the expressions."""
    rng = np.random.default_rng(seed)
    x, y, theta = sp.symbols("x y theta")
    s, c = sp.sin(theta), sp.cos(theta)
    r = sp.sqrt(x**2 + y**2 - 2 * x * y * c)
    g = s * x + r / (2 + c) - x * s**3 + sp.Rational(1, 3) * (y - r) * s / r
    exprs = [g, sp.diff(g, theta)]
    body = interval_body(exprs, ("x", "y"), {"theta"})
    program = body.program
    assert program.n_slots < len(program.instructions)  # consumed values are reused
    point = {"x": rng.uniform(1, 2), "y": rng.uniform(0.1, 0.9), "theta": rng.uniform(-3, 3)}
    got = _run(program, point)
    want = [float(e.subs({x: point["x"], y: point["y"], theta: point["theta"]}).evalf(30))
            for e in exprs]
    assert got == pytest.approx(want, rel=1e-12)


def test_an_output_read_again_by_a_later_output_keeps_its_slot():
    x, theta = sp.symbols("x theta")
    shared = sp.sin(theta) * x
    body = interval_body([shared, shared + sp.cos(theta) * shared], ("x",), {"theta"})
    got = _run(body.program, {"x": 1.5, "theta": 0.7})
    assert got == pytest.approx([1.5 * math.sin(0.7), 1.5 * math.sin(0.7) * (1 + math.cos(0.7))])


def _split_example(seed: int):
    rng = np.random.default_rng(seed)
    x, y, theta = sp.symbols("x y theta")
    s, c = sp.sin(theta), sp.cos(theta)
    r = sp.sqrt(x**2 + y**2 - 2 * x * y * c)
    g = (x**3 * y + 2) * s + r / (x * y + c) - (x - y) ** 2 * s**3 + (y / x) * c + sp.sqrt(y)
    exprs = [g, sp.diff(g, theta)]
    point = {"x": rng.uniform(1, 2), "y": rng.uniform(0.1, 0.9), "theta": rng.uniform(-3, 3)}
    return interval_body(exprs, ("x", "y"), {"theta"}).program, point


@pytest.mark.parametrize("seed", range(5))
def test_a_split_program_computes_what_the_whole_one_does(seed):
    """The head once, then the tail, over the same slots, give the whole program's numbers
    (the same operations on the same operands); the head reads no theta and holds no
    division or square root (their flags belong to each call); the tail is shorter."""
    program, point = _split_example(seed)
    split = split_program(program, {"theta"}, 3, 10)
    v: dict[int, float] = {}
    _run(split.head, point, v)
    assert all(slot < 3 + split.n_fixed or slot >= 10 for slot in v)  # its own fixed slots
    fixed = {slot: value for slot, value in v.items() if slot < 10}
    assert _run(split.tail, point, dict(fixed)) == _run(program, point)
    assert {op.operation for op in split.head.instructions}.isdisjoint({"div", "sqrt"})
    assert split.n_fixed > 0
    assert len(split.tail.instructions) < len(program.instructions)
    moved = dict(point, theta=point["theta"] + 0.5)  # another theta, the same head
    assert _run(split.tail, moved, dict(fixed)) == _run(program, moved)


def test_the_inline_tail_is_the_program_tail_statement_by_statement():
    program, _ = _split_example(0)
    split = split_program(program, {"theta"}, 0, 20)
    inline = inline_tail(split.tail, {"theta"}, "flags")
    assert len(inline.statements) == sum(op.operation != "const"
                                         for op in split.tail.instructions)
    assert any("v[" in expr for _, expr in inline.statements)  # reads the head's values
    assert [name for name, _ in inline.unpack] == ["x", "y"]
    assert inline.unused == ()
