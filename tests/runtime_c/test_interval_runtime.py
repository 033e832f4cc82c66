"""Tests for the runtime's interval arithmetic and certified zero isolation,
runtime/codegen_interval.h/.c (copied verbatim to generated/runtime/).

Self-contained: drivers/interval_driver.c is compiled here with gcc and the project's strict
flags (runtime/cflags.txt) against runtime/codegen_interval.c, and fed commands on stdin;
doubles travel as hex floats both ways (see the driver's header), so nothing is rounded between
C and Python. Nothing of the project is imported but the flags.

References are independent of the code under test: exact rational arithmetic on the doubles
(fractions.Fraction) for +, -, *, / and integer powers, mpmath at 50 digits for sqrt, sin and
cos; the test functions of the isolation tests have zeros known exactly (doubles, or exact
rationals such as p - 1/c and e + c^2) or to 50 digits (asin).
"""
from __future__ import annotations

import math
import os
import pathlib
import subprocess
from dataclasses import dataclass
from fractions import Fraction

import mpmath
import numpy as np
import pytest

SEED = 20_240_611

POLE, EDGE, OUTSIDE = 1, 2, 4                          # CODEGEN_IV_* flags
ROOT_KIND, CLUSTER, SINGULAR = 0, 1, 2                 # codegen_isolated_kind
FULL, BUDGET = -1, -2                                  # CODEGEN_ISOLATE_* statuses
SPLIT = 0.5078125                                      # where the isolator splits a box
INF = math.inf
TINY = 2.0 ** -1074


# ---------------------------------------------------------------------------- the driver

def _compile(compiler, tmp: pathlib.Path, name: str, flags=None, defines=()) -> pathlib.Path:
    return compiler.build(tmp / name, "interval_driver.c", "codegen_interval.c", flags, defines)


@pytest.fixture(scope="module")
def drv(tmp_path_factory, runtime_driver):
    """The driver, compiled with -O2 and the strict flags (a warning is an error)."""
    return runtime_driver.program(_compile(runtime_driver, tmp_path_factory.mktemp("interval"),
                                           "interval_driver"))


def h(x: float) -> str:
    return float(x).hex()


def f(token: str) -> float:
    return float.fromhex(token)


# ---------------------------------------------------------------------------- exact references

def ulp(x: float) -> float:
    return math.ulp(x)                                 # ulp(0) is the smallest subnormal


def X(x):
    """A double as an exact rational; infinities stay floats (they compare with Fractions)."""
    return x if math.isinf(x) else Fraction(x)


def isinf(v) -> bool:
    return isinstance(v, float) and math.isinf(v)


def xadd(x, y):
    """x + y, never -inf + inf (no interval has lo = +inf or hi = -inf)."""
    if isinf(x) or isinf(y):
        return x if isinf(x) else y
    return Fraction(x) + Fraction(y)


def xmul(x, y):
    if x == 0 or y == 0:
        return Fraction(0)                             # the bounds stand for finite values
    if isinf(x) or isinf(y):
        return INF if (x > 0) == (y > 0) else -INF
    return Fraction(x) * Fraction(y)


def xdiv(x, y):
    """The values x / y approaches near the corner (x, y), y != 0 (a list)."""
    if x == 0:
        return [Fraction(0)]
    sign = 1.0 if (x > 0) == (y > 0) else -1.0
    if isinf(x) and isinf(y):
        return [Fraction(0), sign * INF]
    if isinf(y):
        return [Fraction(0)]
    if isinf(x):
        return [sign * INF]
    return [Fraction(x) / Fraction(y)]


def xpow(x, n):
    if isinf(x):
        return INF if (x > 0 or n % 2 == 0) else -INF
    return Fraction(x) ** n


def exact_range(op, a, b=None, n=None):
    """(inf, sup) of the exact values of op over the real points of the intervals."""
    (alo, ahi) = a
    if op == "add":
        return xadd(alo, b[0]), xadd(ahi, b[1])
    if op == "sub":
        return xadd(alo, -b[1]), xadd(ahi, -b[0])
    if op == "mul":
        c = [xmul(x, y) for x in a for y in b]
        return min(c), max(c)
    if op == "div":
        c = [v for x in a for y in b for v in xdiv(x, y)]
        return min(c), max(c)
    if op == "pow":
        lo, hi = xpow(alo, n), xpow(ahi, n)
        if n % 2 == 1 or alo >= 0:
            return lo, hi
        if ahi <= 0:
            return hi, lo
        return Fraction(0), max(lo, hi)
    raise AssertionError(op)


def exact_point(op, x, y=None, n=None):
    if op == "add":
        return Fraction(x) + Fraction(y)
    if op == "sub":
        return Fraction(x) - Fraction(y)
    if op == "mul":
        return Fraction(x) * Fraction(y)
    if op == "div":
        return Fraction(x) / Fraction(y)
    if op == "pow":
        return Fraction(x) ** n
    raise AssertionError(op)


def ulps_away(bound: float, exact) -> float:
    """|bound - exact| in ulps of exact rounded to double (inf if that overflows)."""
    try:
        scale = ulp(float(exact))
    except OverflowError:
        return INF
    if math.isinf(scale):
        return INF
    return float(abs(Fraction(bound) - Fraction(exact)) / Fraction(scale))


# ---------------------------------------------------------------------------- random intervals

def random_double(rng, allow_inf=False) -> float:
    u = rng.random()
    sign = -1.0 if rng.random() < 0.5 else 1.0
    if allow_inf and rng.random() < 0.15:
        return sign * INF
    if u < 0.40:
        return sign * 10.0 ** rng.uniform(-3, 3)
    if u < 0.50:
        return sign * 10.0 ** rng.uniform(150, 308.25)            # huge (overflowing products)
    if u < 0.58:
        return sign * 10.0 ** rng.uniform(-307, -150)             # tiny (underflowing ones)
    if u < 0.66:
        return sign * float(rng.integers(1, 2**52)) * TINY         # subnormal
    if u < 0.76:
        return sign * 0.0
    if u < 0.88:
        return sign * float(rng.integers(1, 9)) / float(rng.choice([1, 2, 4, 3]))
    return sign * 10.0 ** rng.uniform(-20, 20)


def interior(rng, lo, hi, k):
    """k doubles inside the finite interval [lo, hi]."""
    out = []
    for _ in range(k):
        t = rng.random()
        x = lo * (1.0 - t) + hi * t
        out.append(min(max(x, lo), hi))
    return out


def random_interval(rng, allow_inf=False, sign=0):
    """[lo, hi], with lo never +inf and hi never -inf; sign > 0: lo > 0, sign < 0: hi < 0."""
    a = random_double(rng, allow_inf)
    u = rng.random()
    if u < 0.15:
        b = a                                                     # a point
    elif u < 0.35 and math.isfinite(a):
        b = a
        for _ in range(int(rng.integers(1, 6))):                  # a few ulps wide
            b = math.nextafter(b, INF)
    elif u < 0.5 and math.isfinite(a) and a != 0:
        b = a * (1.0 + 2.0 ** -float(rng.integers(1, 40)))          # narrow, relative
    else:
        b = random_double(rng, allow_inf)
    lo, hi = min(a, b), max(a, b)
    if lo == INF or hi == -INF:
        lo, hi = (-INF, hi) if lo == INF else (lo, INF)
        lo, hi = min(lo, hi), max(lo, hi)
        if lo == INF or hi == -INF:
            lo, hi = -INF, INF
    if sign:
        lo, hi = sorted((abs(lo), abs(hi)))
        if lo == INF:
            lo = 1.0
        if lo == 0.0:
            lo = TINY if hi > 0 else 1.0
            hi = max(hi, lo)
        if sign < 0:
            lo, hi = -hi, -lo
    return lo, hi


# ---------------------------------------------------------------------------- 1. arithmetic

RATIONAL_ULPS = 4.0      # +, -, *, /: one rounding to nearest and one outward step


@pytest.fixture(scope="module")
def rational_cases(drv):
    """(op, a, b, n, (lo, hi, flags)) for several thousand random cases of add, sub, mul, div
    (divisors with and without 0) and pow (n = 1..7), with infinite bounds in a part of them."""
    rng = np.random.default_rng([SEED, 1])
    cases = []
    for i in range(1500):
        allow_inf = i % 3 == 0
        a, b = random_interval(rng, allow_inf), random_interval(rng, allow_inf)
        cases += [("add", a, b, None), ("sub", a, b, None), ("mul", a, b, None)]
        if i % 5 == 0:
            cases.append(("div", a, b, None))                        # b may hold 0
        else:
            cases.append(("div", a, random_interval(rng, allow_inf, sign=int(rng.choice([-1, 1]))),
                          None))
        cases.append(("pow", a, None, int(rng.integers(1, 8))))
    lines = []
    for op, a, b, n in cases:
        if op == "pow":
            lines.append(f"pow {h(a[0])} {h(a[1])} {n}")
        else:
            lines.append(f"{op} {h(a[0])} {h(a[1])} {h(b[0])} {h(b[1])}")
    out = drv(lines)
    return [(op, a, b, n, (f(o[0]), f(o[1]), int(o[2]))) for (op, a, b, n), o in zip(cases, out)]


def test_rational_operations_enclose_exact_range(rational_cases):
    """add, sub, mul, div, pow: the exact range over the argument intervals (from the
    endpoint / extreme combinations in exact rationals, infinities as limits and 0 * inf = 0)
    and the exact results at sampled interior points lie in [lo, hi]; no NaN bound; the
    divisor holding 0 gives POLE and [-inf, inf], otherwise no flag."""
    rng = np.random.default_rng([SEED, 2])
    checked = 0
    for op, a, b, n, (lo, hi, flags) in rational_cases:
        where = f"{op} {a} {b} n={n} -> [{lo!r}, {hi!r}] flags {flags}"
        assert not (math.isnan(lo) or math.isnan(hi)), where
        assert lo <= hi, where
        if op == "div" and not (b[0] > 0 or b[1] < 0):
            assert flags == POLE and (lo, hi) == (-INF, INF), where
            continue
        assert flags == 0, where
        inf, sup = exact_range(op, a, b, n)
        assert X(lo) <= inf and sup <= X(hi), where
        if all(map(math.isfinite, (*a, *(b or ())))):
            xs = [*a, *interior(rng, *a, 3)]
            ys = [*b, *interior(rng, *b, 3)] if b else [None]
            for x in xs:
                for y in ys:
                    v = exact_point(op, x, y, n)
                    assert X(lo) <= v <= X(hi), (where, x, y)
                    checked += 1
    assert checked > 50_000


def test_div_infinite_over_infinite(drv):
    """Unbounded dividend over an unbounded divisor: the result must still enclose every
    quotient, e.g. -1 / 1 = -1 for [-inf, 0] / [1, inf] (true range (-inf, 0])."""
    cases = [((-INF, 0.0), (1.0, INF)), ((-INF, -1.0), (1.0, INF)),
             ((-INF, -1.0), (-INF, -1.0)), ((-INF, 5.0), (-INF, -2.0)),
             ((-INF, 3.0), (0.5, INF)), ((1.0, INF), (1.0, INF)), ((-1.0, INF), (-INF, -1.0))]
    out = drv([f"div {h(a[0])} {h(a[1])} {h(b[0])} {h(b[1])}" for a, b in cases])
    bad = []
    for (a, b), got in zip(cases, out):
        lo, hi = f(got[0]), f(got[1])
        inf, sup = exact_range("div", a, b)
        if not (X(lo) <= inf and sup <= X(hi)):
            bad.append(f"{a} / {b} -> [{lo!r}, {hi!r}], exact range [{inf}, {sup}]")
    assert not bad, "\n".join(bad)


def test_rational_operations_are_tight(rational_cases):
    """On finite arguments, each bound is within a few ulps of the exact extreme (when that is
    a finite double): 4 for +, -, *, /; 3 n + 2 for x^n (square-and-multiply: each product
    rounded and widened, the relative errors compounding; ~2.3 n measured)."""
    worst = {}
    for op, a, b, n, (lo, hi, flags) in rational_cases:
        if not all(math.isfinite(x) for x in (*a, *(b or ()))) or flags:
            continue
        inf, sup = exact_range(op, a, b, n)
        limit = RATIONAL_ULPS if op != "pow" else 3.0 * n + 2.0
        for bound, exact in ((lo, inf), (hi, sup)):
            d = ulps_away(bound, exact)
            if math.isinf(d):
                continue
            worst[op] = max(worst.get(op, 0.0), d)
            assert d <= limit, f"{op} {a} {b} n={n} -> [{lo!r}, {hi!r}]: {d:.3g} ulps from {exact}"
    assert set(worst) == {"add", "sub", "mul", "div", "pow"}


def test_arithmetic_special_cases(drv):
    """0 * [-inf, inf] = 0; sums with an exact 0 are exact; x / [0, 0], x / [-1, 0],
    x / [0, 2] are poles; negation and |.| are exact; x^2 + y^2 over 2000 random pairs encloses the exact
    range, starts at exactly 0 where both hold 0, and never below 0 (but where a square
    underflows: test_even_power_of_tiny_is_nonnegative)."""
    cases = [
        ("mul 0 0 -inf inf", (0.0, 0.0, 0)),
        ("mul -inf inf 0 0", (0.0, 0.0, 0)),
        ("mul 0 0 0x1p+1023 0x1p+1023", (0.0, 0.0, 0)),
        ("mul 0 inf 0 inf", (0.0, INF, 0)),
        ("add 0 0 0 0", (0.0, 0.0, 0)),
        ("add 0 0 0x1.8p-3 0x1.8p+1", (0.1875, 3.0, 0)),
        ("add 0x1p+0 0x1p+1 0 0", (1.0, 2.0, 0)),
        ("sub 0x1p+0 0x1p+1 0 0", (1.0, 2.0, 0)),
        ("neg -0x1p+0 inf", (-INF, 1.0, 0)),
        ("div 1 2 0 0", (-INF, INF, POLE)),
        ("div 1 2 -1 0", (-INF, INF, POLE)),
        ("div 1 2 0 2", (-INF, INF, POLE)),
        ("div 0 0 0 0", (-INF, INF, POLE)),
        ("div 0 0 1 inf", (0.0, 0.0, 0)),
        ("pow -3 2 2", None),
        ("sumsq -1 2 -3 0.5", None),
        ("sumsq 0 0 -0x1p-1074 0x1p-1074", (0.0, None, 0)),
        ("sumsq -1e-300 1e-300 -1e-200 0", (0.0, None, 0)),
        ("sumsq -inf inf -inf inf", (0.0, INF, 0)),
        ("abs 0x1p+0 0x1p+1", (1.0, 2.0, 0)),
        ("abs -0x1p+1 -0x1p+0", (1.0, 2.0, 0)),
        ("abs -0x1.8p+1 0x1p+0", (0.0, 3.0, 0)),
        ("abs -0x1p+0 0x1.8p+1", (0.0, 3.0, 0)),
        ("abs -inf 0", (0.0, INF, 0)),
    ]
    out = drv([c for c, _ in cases])
    for (cmd, want), got in zip(cases, out):
        lo, hi, flags = f(got[0]), f(got[1]), int(got[2])
        if want is not None:
            assert lo == want[0] and flags == want[2], (cmd, got)
            if want[1] is not None:
                assert hi == want[1], (cmd, got)
    assert f(out[14][0]) == 0.0 and f(out[14][1]) >= 9.0                   # x^2 over [-3, 2]
    assert f(out[15][0]) == 0.0 and f(out[15][1]) >= 13.0                  # over [-1,2]x[-3,.5]
    # x^2 + y^2 never below 0, and exactly 0 where both hold 0, over random intervals
    rng = np.random.default_rng([SEED, 3])
    pairs = [(random_interval(rng, True), random_interval(rng, True)) for _ in range(2000)]
    out = drv([f"sumsq {h(a[0])} {h(a[1])} {h(b[0])} {h(b[1])}" for a, b in pairs])
    for (a, b), got in zip(pairs, out):
        lo, hi = f(got[0]), f(got[1])
        if not (_square_underflows(a) or _square_underflows(b)):  # see test_even_power_of_tiny
            assert lo >= 0.0, (a, b, got)
        if a[0] <= 0 <= a[1] and b[0] <= 0 <= b[1]:
            assert lo == 0.0, (a, b, got)
        sq = [exact_range("pow", a, n=2), exact_range("pow", b, n=2)]
        assert X(lo) <= xadd(sq[0][0], sq[1][0]) and xadd(sq[0][1], sq[1][1]) <= X(hi)


def _square_underflows(a):
    """The smaller |end| of a, squared, underflows (a not holding 0)."""
    m = min(abs(a[0]), abs(a[1]))
    return not (a[0] <= 0 <= a[1]) and m * m < 2.0 ** -1022


def test_even_power_of_tiny_is_nonnegative(drv):
    """x^2, x^4 and x^2 + y^2 of intervals of tiny (underflowing) magnitude start at 0 or
    above: an even power is never negative."""
    cases = ["pow 0x1p-600 1 2", "pow -1 -0x1p-600 2", "pow 1e-200 1e-200 4",
             "sumsq 1e-200 1 0x1p-1074 0x1p-1074", "sumsq -1e-300 -1e-300 1e-170 1e-170"]
    out = drv(cases)
    bad = [f"{c} -> {o}" for c, o in zip(cases, out) if f(o[0]) < 0.0]
    assert not bad, "\n".join(bad)


def _mp_sqrt_range(lo, hi):
    return mpmath.sqrt(max(mpmath.mpf(lo), 0)), mpmath.sqrt(mpmath.mpf(hi))


def test_sqrt_encloses_and_flags(drv):
    """sqrt: hi < 0 gives OUTSIDE; lo <= 0 <= hi gives EDGE and starts at exactly 0; lo > 0
    gives no flag. Where defined, sqrt at the ends and at 50 interior points (mpmath, 50
    digits) lies inside, and the bounds are within 4 ulps of the exact ones."""
    rng = np.random.default_rng([SEED, 4])
    cases = [random_interval(rng, allow_inf=i % 4 == 0) for i in range(1500)]
    cases += [(0.0, 0.0), (-0.0, 0.0), (-1.0, -0.0), (-INF, -1.0), (-INF, INF), (0.0, INF),
              (4.0, 4.0), (TINY, TINY), (2.0 ** -1022, 4.0), (1.0, 1.7976931348623157e308)]
    out = drv([f"sqrt {h(lo)} {h(hi)}" for lo, hi in cases])
    with mpmath.workdps(50):
        for k, ((lo, hi), got) in enumerate(zip(cases, out)):
            rlo, rhi, flags = f(got[0]), f(got[1]), int(got[2])
            where = f"sqrt [{lo!r}, {hi!r}] -> [{rlo!r}, {rhi!r}] flags {flags}"
            assert rlo <= rhi and not math.isnan(rlo + rhi), where
            if hi < 0:
                assert flags == OUTSIDE, where
                continue
            if lo <= 0:
                assert flags == EDGE and rlo == 0.0, where
            else:
                assert flags == 0, where
            s_lo, s_hi = _mp_sqrt_range(lo, hi) if math.isfinite(hi) else (None, None)
            if math.isinf(hi):
                assert rhi == INF, where
                s_lo = mpmath.sqrt(max(mpmath.mpf(lo), 0))
            assert rlo <= s_lo, where
            if s_hi is not None:
                assert s_hi <= rhi, where
                if lo > 0:
                    assert s_lo - rlo <= 4 * ulp(float(s_lo)), where
                assert (s_hi == 0 and rhi <= 2 * TINY) or \
                    (rhi - s_hi) <= 4 * ulp(float(s_hi)), where
                if k % 5 == 0:
                    for x in interior(rng, max(lo, 0.0), hi, 50):
                        assert rlo <= mpmath.sqrt(x) <= rhi, (where, x)


def _phase_points(lo, hi, phase):
    """Whether (phase + 2 k) pi lies in [lo, hi] for some integer k (to 50 digits beyond the
    magnitude)."""
    with mpmath.workdps(50 + int(max(math.log10(max(abs(lo), abs(hi), 1.0)), 0))):
        two_pi = 2 * mpmath.pi
        phase = phase * mpmath.pi
        k_lo = mpmath.ceil((mpmath.mpf(lo) - phase) / two_pi)
        return phase + k_lo * two_pi <= hi


def _trig_cases(rng):
    cases = []
    for i in range(1200):
        u = rng.random()
        if u < 0.5:
            c = rng.uniform(-10, 10)
        elif u < 0.75:
            c = 10.0 ** rng.uniform(1, 6) * rng.choice([-1, 1])
        elif u < 0.85:                           # (below 5.7e16: see test_sin_cos_huge_points)
            c = 10.0 ** rng.uniform(6, 16.5) * rng.choice([-1, 1])
        else:                                    # near a crest / trough / zero of sin or cos
            c = float(int(rng.integers(-40, 41))) * math.pi / 2 + rng.normal(0, 1e-6)
        w = 10.0 ** rng.uniform(-16, 1.1) if rng.random() < 0.9 else 0.0
        lo = float(c)
        hi = float(c + w * abs(c)) if rng.random() < 0.3 else float(c + w)
        cases.append((min(lo, hi), max(lo, hi)))
    for _ in range(150):                  # around far crests / troughs (2 pi k off by ~|x| 1e-16)
        m = 10.0 ** rng.uniform(5, 16.5)
        with mpmath.workdps(60):
            k = mpmath.nint(mpmath.mpf(m) / mpmath.pi)
            c = float(k * mpmath.pi / 2 * int(rng.choice([1, 2])) + int(rng.integers(-1, 2))
                      * mpmath.pi / 2)
        w = max(m * 10.0 ** rng.uniform(-16, -13), 4 * ulp(c))
        lo, hi = c - w * rng.uniform(0, 1), c + w * rng.uniform(0, 1)
        cases.append((min(lo, hi), max(lo, hi)))
    cases += [(0.0, 0.0), (-INF, INF), (0.0, INF), (1e300, 1e300), (-1e308, -1e308), (1e22, 1e22),
              (math.pi / 2, math.pi / 2), (-math.pi, math.pi), (0.0, 6.0), (0.0, 5.999),
              (1.0, 7.0), (2.0 ** 60, 2.0 ** 60 + 4096.0)]
    return cases


@pytest.mark.parametrize("name", ["sin", "cos"])
def test_sin_cos_enclose_true_range(drv, name):
    """sin, cos of intervals (small to 1e22, widths 0 to 12, near crests and troughs, infinite):
    the values at the ends, at ~50 interior points, and +-1 at any crest / trough inside
    (mpmath, 50 digits) lie in the result, which lies in [-1, 1]; for |x| <= 1e6 and width < 6
    the bounds are within 6 ulps (2 for libm, 2 outward steps, rounding) of the true range."""
    rng = np.random.default_rng([SEED, 5, name == "sin"])
    cases = _trig_cases(rng)
    out = drv([f"{name} {h(lo)} {h(hi)}" for lo, hi in cases])
    fn = mpmath.sin if name == "sin" else mpmath.cos
    crest, trough = (0.5, -0.5) if name == "sin" else (0.0, 1.0)          # in units of pi
    interior_checked = 0
    for k, ((lo, hi), got) in enumerate(zip(cases, out)):
        rlo, rhi = f(got[0]), f(got[1])
        where = f"{name} [{lo!r}, {hi!r}] -> [{rlo!r}, {rhi!r}]"
        assert int(got[2]) == 0 and -1.0 <= rlo <= rhi <= 1.0, where
        if not (math.isfinite(lo) and math.isfinite(hi)) or hi - lo >= 2 * math.pi:
            assert (rlo, rhi) == (-1.0, 1.0), where
            continue
        dps = 50 + int(max(math.log10(max(abs(lo), abs(hi), 1.0)), 0))
        with mpmath.workdps(dps):
            ends = [fn(mpmath.mpf(lo)), fn(mpmath.mpf(hi))]
            top = 1 if _phase_points(lo, hi, crest) else max(ends)
            bottom = -1 if _phase_points(lo, hi, trough) else min(ends)
            assert rlo <= bottom and top <= rhi, where
            if k % 4 == 0 and hi > lo:
                for x in interior(rng, lo, hi, 50):
                    assert rlo <= fn(mpmath.mpf(x)) <= rhi, (where, x)
                    interior_checked += 1
            if max(abs(lo), abs(hi)) <= 1e6 and hi - lo < 6:
                for bound, exact in ((rlo, bottom), (rhi, top)):
                    d = abs(mpmath.mpf(bound) - exact) / ulp(float(exact))
                    assert d <= 6, f"{where}: {float(d):.3g} ulps from {exact}"
    assert interior_checked > 5000


def test_sin_cos_huge_points(drv):
    """sin and cos of single large doubles and narrow intervals there return (within 2 s for
    all of them) an enclosure of the true value (mpmath): at most [-1, 1]."""
    big = float.fromhex("0x1.f4bbff13cedf1p+519")
    cases = [("sin", 6e16, 6e16), ("cos", 6e16, 6e16), ("sin", 8e16, 8e16), ("cos", -1e17, -1e17),
             ("sin", 1e17, 1e17 + 64), ("cos", 2.0 ** 56, 2.0 ** 56), ("sin", big, big),
             ("cos", -big, -big)]
    try:
        out = drv([f"{name} {h(lo)} {h(hi)}" for name, lo, hi in cases], timeout=2.0)
    except subprocess.TimeoutExpired:
        pytest.fail("codegen_iv_sin / codegen_iv_cos did not return")
    for (name, lo, hi), got in zip(cases, out):
        rlo, rhi = f(got[0]), f(got[1])
        fn = mpmath.sin if name == "sin" else mpmath.cos
        with mpmath.workdps(80):
            assert -1.0 <= rlo <= fn(mpmath.mpf(lo)) <= rhi <= 1.0


# ---------------------------------------------------------------------------- 2. isolation

@dataclass
class Isolated:
    lo: float
    hi: float
    theta: float
    kind: int
    sign_change: int

    def holds(self, z) -> bool:
        return self.lo <= z <= self.hi                   # exact: Fraction / mpf vs double


@dataclass
class Result:
    status: int
    found: list
    calls: int
    bad: int


def poly(*roots, c=0.0) -> str:
    """(t - r1)^m1 ... + c; roots given as r or (r, m)."""
    pairs = [(r, 1) if not isinstance(r, tuple) else r for r in roots]
    return f"poly {h(c)} {len(pairs)} " + " ".join(f"{h(r)} {m}" for r, m in pairs)


def pole(c, p) -> str:
    return f"pole {h(c)} {h(p)}"


def sqrt_fn(e, c) -> str:
    return f"sqrt {h(e)} {h(c)}"


def sin_fn(s) -> str:
    return f"sin {h(s)}"


def flagged(bits, a, b, fn) -> str:
    """fn, with bits & (POLE | EDGE) raised where theta meets [a, b], bits & OUTSIDE where theta
    lies within [a, b]."""
    return f"flagged {bits} {h(a)} {h(b)} {fn}"


def isolate_lines(problems):
    """problems: (lo, hi, function, capacity[, fail_status, fail_after[, mode]])."""
    lines = []
    for p in problems:
        lo, hi, fn, cap = p[:4]
        fail_status, fail_after = p[4:6] if len(p) > 4 else (0, 0)
        mode = p[6] if len(p) > 6 else 3
        lines.append(f"isolate {mode} {h(lo)} {h(hi)} {cap} {fail_status} {fail_after} {fn}")
    return lines


def isolate_many(drv, problems):
    out = []
    for tokens in drv(isolate_lines(problems)):
        status, count, calls, bad = map(int, tokens[:4])
        found = []
        for i in range(4, len(tokens), 5):
            lo, hi, theta = map(f, tokens[i:i + 3])
            found.append(Isolated(lo, hi, theta, int(tokens[i + 3]), int(tokens[i + 4])))
        assert len(found) == count or status != 0, tokens
        out.append(Result(status, found, calls, bad))
    return out


def check_contract(problem, res: Result, expect_status=0):
    """What holds for every result: status, the callback called with the caller's mode and
    sub-intervals of [lo, hi] only, at most capacity entries, each a sub-interval of [lo, hi]
    with lo <= theta <= hi, a known kind, a ROOT with a sign change, all ascending and
    disjoint (neighbours may share an end)."""
    lo, hi, _, cap = problem[:4]
    where = f"{problem}: {res}"
    assert res.status == expect_status, where
    assert res.bad == 0, where
    assert len(res.found) <= cap, where
    for r in res.found:
        assert lo <= r.lo <= r.theta <= r.hi <= hi, where
        assert r.kind in (ROOT_KIND, CLUSTER, SINGULAR) and r.sign_change in (0, 1), where
        if r.kind == ROOT_KIND:
            assert r.sign_change == 1, where
    for a, b in zip(res.found, res.found[1:]):
        assert a.hi <= b.lo, f"not ascending / overlapping: {a} {b}\n{where}"


def holding(res: Result, z):
    return [r for r in res.found if r.holds(z)]


def assert_simple_zeros(problem, res, zeros, theta_tol, only=True):
    """Each known simple zero in exactly one interval, a ROOT holding no other zero, theta
    within theta_tol(z) of it; only=True: nothing else reported."""
    check_contract(problem, res)
    where = f"{problem}: {res}"
    for z in zeros:
        got = holding(res, z)
        assert len(got) == 1, f"zero {z} in {len(got)} intervals\n{where}"
        r = got[0]
        assert r.kind == ROOT_KIND, f"zero {z} in {r}\n{where}"
        assert sum(r.holds(w) for w in zeros) == 1, where
        assert distance(r.theta, z) <= theta_tol(z), \
            f"theta {r.theta!r} vs zero {z}\n{where}"
    if only:
        assert len(res.found) == len(zeros), where


def distance(x: float, z) -> float:
    """|x - z| for a double x and an exact zero z (Fraction, or mpf to 50 digits)."""
    if isinstance(z, Fraction):
        return float(abs(Fraction(x) - z))
    with mpmath.workdps(50):
        return float(abs(mpmath.mpf(x) - z))


def ulps_tol(k):
    return lambda z: k * ulp(float(z))


def _well_separated(rng, n, lo, hi, gap):
    while True:
        zs = sorted(float(x) for x in rng.uniform(lo, hi, n))
        if all(b - a >= gap for a, b in zip(zs, zs[1:])):
            return zs


def test_isolate_simple_polynomial_zeros(drv):
    """(t - r1)...(t - rk), k = 1..8, at several scales (roots near 1, near 1e3..1e4, near 0
    within 1e-2, negative): each root in exactly one ROOT interval holding no other root, theta
    within 4 ulps of it (the roots are doubles: the sign is decided everywhere else), and
    nothing else reported."""
    rng = np.random.default_rng([SEED, 10])
    problems, zero_sets = [], []
    scales = [(-4.0, 4.0, 1e-2), (1e3, 1e4, 1.0), (-1e-2, 1e-2, 1e-4), (-300.0, -200.0, 1e-1)]
    for i in range(240):
        zlo, zhi, gap = scales[i % len(scales)]
        zs = _well_separated(rng, int(rng.integers(1, 9)), zlo, zhi, gap)
        margin = (zhi - zlo) * rng.uniform(0.01, 0.5)
        lo, hi = zlo - margin, zhi + margin * rng.uniform(0.1, 2)
        problems.append((lo, hi, poly(*zs), 16))
        zero_sets.append([Fraction(z) for z in zs])
    for p, res, zs in zip(problems, isolate_many(drv, problems), zero_sets):
        assert_simple_zeros(p, res, zs, ulps_tol(4))


def test_isolate_sin_pole_and_sqrt_zeros(drv):
    """sin(t) - s (zeros asin(s) + 2 pi k, pi - asin(s) + 2 pi k, to 50 digits; theta within
    the rounding of the enclosure: 8 ulps of s over |cos|); c + 1/(t - p) (zero p - 1/c, a
    SINGULAR interval holding the pole, no ROOT holding it); sqrt(t - e) - c (zero e + c^2,
    nothing reported below e where the radicand is negative). For these theta is within the
    rounding of the enclosure near the zero, carried to t through G': 4 ulps of the zero plus
    8 ulps of 1/c and c / c^2 (pole), of c^2 and 2 c ulp(c) (sqrt)."""
    rng = np.random.default_rng([SEED, 11])
    problems, expected = [], []
    for _ in range(60):                                            # sin(t) - s
        s = float(rng.uniform(-0.98, 0.98))
        lo = float(rng.uniform(-12, 0))
        hi = float(lo + rng.uniform(1, 14))
        with mpmath.workdps(50):
            a = mpmath.asin(s)
            zs = [z for k in range(-4, 5) for z in (a + 2 * mpmath.pi * k,
                                                    mpmath.pi - a + 2 * mpmath.pi * k)
                  if lo <= z <= hi]
        tol = (lambda s_: (lambda z: 4 * ulp(float(z)) + 8 * ulp(abs(s_) + 1e-300)
                           / abs(math.cos(float(z)))))(s)
        problems.append((lo, hi, sin_fn(s), 16))
        expected.append(("sin", sorted(zs), tol))
    for _ in range(60):                                            # c + 1/(t - p)
        p = float(rng.uniform(-2, 2))
        c = float(rng.choice([-1, 1]) * 2.0 ** rng.uniform(-1, 3))
        lo, hi = p - float(rng.uniform(0.5, 4)), p + float(rng.uniform(0.5, 4))
        problems.append((lo, hi, pole(c, p), 16))
        expected.append(("pole", Fraction(p) - 1 / Fraction(c), p,
                         (lambda c_: lambda z: 4 * ulp(float(z)) + 8 * ulp(1 / c_)
                          + 8 * ulp(c_) / c_ ** 2)(c)))
    for _ in range(60):                                            # sqrt(t - e) - c
        e = float(rng.uniform(-2, 2))
        c = float(rng.uniform(0.01, 1.5))
        lo, hi = e - float(rng.uniform(0, 3)), e + c * c + float(rng.uniform(0.01, 3))
        problems.append((lo, hi, sqrt_fn(e, c), 16))
        expected.append(("sqrt", Fraction(e) + Fraction(c) ** 2, e,
                         (lambda c_: lambda z: 4 * ulp(float(z)) + 8 * ulp(c_ * c_)
                          + 16 * c_ * ulp(c_))(c)))
    for p, res, exp in zip(problems, isolate_many(drv, problems), expected):
        where = f"{p}: {res}"
        if exp[0] == "sin":
            assert_simple_zeros(p, res, exp[1], exp[2])
            continue
        check_contract(p, res)
        kind, z, special, tol = exp
        assert_simple_zeros(p, Result(0, [r for r in res.found if r.kind == ROOT_KIND], 0, 0),
                            [z] if p[0] <= z <= p[1] else [], tol)
        if kind == "pole":
            at_pole = holding(res, Fraction(special))
            assert at_pole and all(r.kind == SINGULAR for r in at_pole), where
            assert len(res.found) == len(at_pole) + (p[0] <= z <= p[1]), where
        else:
            assert all(r.hi >= special for r in res.found), where
            assert len(res.found) == 1, where


def _pair_outcome(res, z1, z2, where):
    """How a pair of zeros z1 < z2 was reported: "roots" (two ROOTs, one zero each),
    "cluster" (one CLUSTER holding both, no sign change) or "mixed" (one zero in a ROOT, the
    other in a CLUSTER of its own: still every claim true). Checks that each is in exactly one
    interval and no ROOT holds both."""
    h1, h2 = holding(res, z1), holding(res, z2)
    assert h1 and h2, f"a zero is outside every interval\n{where}"
    assert len(h1) == 1 and len(h2) == 1, f"a zero reported twice\n{where}"
    if h1[0] == h2[0]:
        assert h1[0].kind == CLUSTER and h1[0].sign_change == 0, where
        return "cluster"
    kinds = sorted((h1[0].kind, h2[0].kind))
    if kinds == [ROOT_KIND, ROOT_KIND]:
        return "roots"
    assert kinds == [ROOT_KIND, CLUSTER], where
    return "mixed"


def test_isolate_close_pairs(drv):
    """Pairs r, r + d with d = 1e-3 .. 1e-15 (relative to max(1, |r|)) and one ulp, with a third,
    far zero: each zero in exactly one interval; a ROOT holds exactly one zero; the two either
    in two ROOTs or together in one CLUSTER (or, close to the resolution, one in a ROOT and the
    other in a CLUSTER of its own); from d = 1e-9 up, two ROOTs; nothing else reported."""
    rng = np.random.default_rng([SEED, 12])
    problems, pairs = [], []
    for d in (1e-3, 1e-6, 1e-9, 1e-12, 1e-14, 1e-15, None):
        for _ in range(12):
            r = float(rng.uniform(-2, 2)) * float(rng.choice([1.0, 100.0]))
            r2 = math.nextafter(r, INF) if d is None else r + d * max(1.0, abs(r))
            far = r + 3.0 * float(rng.choice([-1, 1]))
            lo = min(r, far) - float(rng.uniform(0.1, 2))
            hi = max(r2, far) + float(rng.uniform(0.1, 2))
            problems.append((lo, hi, poly(r, r2, far), 16))
            pairs.append((d, Fraction(r), Fraction(r2), Fraction(far)))
    outcomes = {}
    for p, res, (d, z1, z2, far) in zip(problems, isolate_many(drv, problems), pairs):
        check_contract(p, res)
        where = f"{p}: {res}"
        zs = (z1, z2, far)
        assert len(holding(res, far)) == 1 and holding(res, far)[0].kind == ROOT_KIND, where
        for r in res.found:
            held = sum(r.holds(z) for z in zs)
            assert held >= 1 and (r.kind != ROOT_KIND or held == 1), where
        outcome = _pair_outcome(res, z1, z2, where)
        if d is not None and d >= 1e-9:
            assert outcome == "roots", where
        outcomes[d, outcome] = outcomes.get((d, outcome), 0) + 1
    assert {o for _, o in outcomes} >= {"roots", "cluster"}, outcomes


def test_isolate_multiple_zeros(drv):
    """(t - r)^2 (t - s): a CLUSTER holding r without sign change, s a ROOT; (t - r)^3 (t - s):
    r in a CLUSTER or a ROOT (with a sign change either way it is decided), s a ROOT."""
    rng = np.random.default_rng([SEED, 13])
    problems, data = [], []
    for i in range(80):
        m = 2 if i % 2 == 0 else 3
        r = float(rng.uniform(-3, 3))
        s = r + float(rng.choice([-1, 1]) * rng.uniform(0.5, 2))
        lo, hi = min(r, s) - float(rng.uniform(0.1, 2)), max(r, s) + float(rng.uniform(0.1, 2))
        problems.append((lo, hi, poly((r, m), s), 8))
        data.append((m, Fraction(r), Fraction(s)))
    for p, res, (m, r, s) in zip(problems, isolate_many(drv, problems), data):
        check_contract(p, res)
        where = f"{p}: {res}"
        hs, hr = holding(res, s), holding(res, r)
        assert len(hs) == 1 and hs[0].kind == ROOT_KIND and not hs[0].holds(r), where
        assert len(hr) == 1, where
        if m == 2:
            assert hr[0].kind == CLUSTER and hr[0].sign_change == 0, where
        else:
            assert hr[0].kind in (CLUSTER, ROOT_KIND), where
        assert len(res.found) == 2, where


def test_isolate_near_double_without_real_zero(drv):
    """(t - r)^2 + e: e = 1e-3 gives nothing; e = 1e-30 nothing or CLUSTERs, never a ROOT;
    (t - r)^2 - 1e-30 (zeros r +- 1e-15, to 50 digits): each in exactly one interval, as for the
    close pairs of test_isolate_close_pairs."""
    rng = np.random.default_rng([SEED, 14])
    problems, kinds = [], []
    for _ in range(30):
        r = float(rng.uniform(-3, 3))
        lo, hi = r - float(rng.uniform(0.1, 3)), r + float(rng.uniform(0.1, 3))
        for e in (1e-3, 1e-30, -1e-30):
            problems.append((lo, hi, poly((r, 2), c=e), 8))
            kinds.append((e, r))
    for p, res, (e, r) in zip(problems, isolate_many(drv, problems), kinds):
        check_contract(p, res)
        where = f"{p}: {res}"
        if e == 1e-3:
            assert res.found == [], where
        elif e > 0:
            assert all(x.kind == CLUSTER for x in res.found), where
        else:
            with mpmath.workdps(50):
                zs = [mpmath.mpf(r) - mpmath.sqrt(mpmath.mpf(-e)),
                      mpmath.mpf(r) + mpmath.sqrt(mpmath.mpf(-e))]
            _pair_outcome(res, *zs, where)
            assert all(any(x.holds(z) for z in zs) for x in res.found), where


def test_isolate_poles(drv):
    """1/(t - p): one SINGULAR interval holding p, nothing else (no ROOT across the sign
    change at the pole); c + 1/(t - p) with the zero outside [lo, hi]: the same."""
    rng = np.random.default_rng([SEED, 15])
    problems, poles = [], []
    for i in range(40):
        p = float(rng.uniform(-2, 2))
        c = 0.0 if i % 2 == 0 else float(rng.choice([-1, 1]) * 2.0 ** rng.uniform(-3, -1))
        lo, hi = p - float(rng.uniform(0.1, 1)), p + float(rng.uniform(0.1, 1))
        problems.append((lo, hi, pole(c, p), 8))
        poles.append(p)
    for prob, res, p in zip(problems, isolate_many(drv, problems), poles):
        check_contract(prob, res)
        assert len(res.found) == 1 and res.found[0].kind == SINGULAR and res.found[0].holds(p), \
            f"{prob}: {res}"


def test_isolate_sqrt_edge_zero(drv):
    """sqrt(t - e) (zero exactly at the edge of the domain): e lies in one interval, not a ROOT
    (G has no sign below e), and nothing lies wholly below e."""
    rng = np.random.default_rng([SEED, 16])
    problems, edges = [], []
    for _ in range(30):
        e = float(rng.uniform(-2, 2))
        problems.append((e - float(rng.uniform(0.1, 2)), e + float(rng.uniform(0.1, 2)),
                         sqrt_fn(e, 0.0), 8))
        edges.append(e)
    for p, res, e in zip(problems, isolate_many(drv, problems), edges):
        check_contract(p, res)
        where = f"{p}: {res}"
        got = holding(res, e)
        assert len(got) == 1 and got[0].kind != ROOT_KIND, where
        assert all(r.hi >= e for r in res.found), where


def test_isolate_respects_flags(drv):
    """The enclosure's flags, raised artificially over a region around a simple zero (the
    values of G unchanged): EDGE or POLE where G holds 0 make the zero SINGULAR, never a ROOT
    (G's sign is not decided where G is not smooth); OUTSIDE over a region drops its zeros (no
    state there) but nothing else; a flag where G is away from 0 changes nothing."""
    fn = poly(0.3, 0.7)
    cases = [(flagged(EDGE, 0.29, 0.31, fn), [(0.3, SINGULAR), (0.7, ROOT_KIND)]),
             (flagged(POLE, 0.3, 0.3, fn), [(0.3, SINGULAR), (0.7, ROOT_KIND)]),
             (flagged(POLE | EDGE, 0.2, 0.8, fn), [(0.3, SINGULAR), (0.7, SINGULAR)]),
             (flagged(POLE, 0.5, 0.5, fn), [(0.3, ROOT_KIND), (0.7, ROOT_KIND)]),
             (flagged(EDGE, 0.4, 0.6, fn), [(0.3, ROOT_KIND), (0.7, ROOT_KIND)]),
             (flagged(OUTSIDE, 0.2, 0.4, fn), [(0.7, ROOT_KIND)]),
             (flagged(OUTSIDE, 0.25, 0.75, fn), []),
             (flagged(OUTSIDE, -1.0, 2.0, fn), [])]
    problems = [(0.0, 1.0, c, 8) for c, _ in cases]
    for p, res, (_, want) in zip(problems, isolate_many(drv, problems), cases):
        check_contract(p, res)
        where = f"{p}: {res}"
        assert len(res.found) == len(want), where
        for z, kind in want:
            got = holding(res, Fraction(z))
            assert len(got) == 1 and got[0].kind == kind, where


def _split_points(lo, hi, depth):
    """The isolator's split points of [lo, hi] down to depth levels (in its own arithmetic)."""
    out, boxes = [], [(lo, hi)]
    for _ in range(depth):
        nxt = []
        for a, b in boxes:
            m = a + SPLIT * (b - a)
            out.append(m)
            nxt += [(a, m), (m, b)]
        boxes = nxt
    return out


def test_isolate_zero_on_split_points_and_ends(drv):
    """A zero exactly on one of the first splits of [lo, hi] is in exactly one interval, a ROOT
    with theta on it; simple and double zeros exactly at lo, at hi, or both, are in exactly one
    interval each."""
    rng = np.random.default_rng([SEED, 17])
    problems, data = [], []
    for lo, hi in [(0.0, 1.0), (-1.0, 1.0), (-math.pi, math.pi), (2.0, 3.0)] + \
            [tuple(sorted(map(float, rng.uniform(-5, 5, 2)))) for _ in range(8)]:
        for m in _split_points(lo, hi, 4):
            other = lo + 0.123 * (hi - lo)
            problems.append((lo, hi, poly(m, other), 8))
            data.append(("split", [Fraction(m), Fraction(other)]))
        problems.append((lo, hi, poly(lo, 0.5 * lo + 0.5 * hi), 8))
        data.append(("end", [Fraction(lo), Fraction(0.5 * lo + 0.5 * hi)]))
        problems.append((lo, hi, poly(hi, (lo, 2)), 8))
        data.append(("end", [Fraction(hi), Fraction(lo)]))
        problems.append((lo, hi, poly((hi, 2)), 8))
        data.append(("end", [Fraction(hi)]))
    for p, res, (kind, zs) in zip(problems, isolate_many(drv, problems), data):
        check_contract(p, res)
        where = f"{p}: {res}"
        for z in zs:
            assert len(holding(res, z)) == 1, f"zero {z} in {holding(res, z)}\n{where}"
        if kind == "split":
            got = holding(res, zs[0])[0]
            assert got.kind == ROOT_KIND and got.theta == zs[0], where
        assert len(res.found) == len(zs), where


def test_isolate_identically_zero(drv):
    """G = 0 on [lo, hi]: one CLUSTER covering exactly [lo, hi]."""
    problems = [(lo, hi, "zero", 4) for lo, hi in
                [(0.0, 1.0), (-math.pi, math.pi), (-1e-300, 1e-300), (1e6, 1e6 + 1), (2.0, 2.0)]]
    for p, res in zip(problems, isolate_many(drv, problems)):
        check_contract(p, res)
        assert [(r.lo, r.hi, r.kind) for r in res.found] == [(p[0], p[1], CLUSTER)], res


def test_isolate_capacity_and_status_pass_through(drv):
    """More zeros than capacity: CODEGEN_ISOLATE_FULL with at most capacity entries (each a
    valid one), also at capacity 0 (NULL out); exactly capacity zeros fit. A nonzero status of
    the enclosure, at its first call or later, is returned unchanged."""
    zs = [-2.5, -1.75, -1.0, -0.25, 0.5, 1.25, 2.0, 2.75]
    fn = poly(*zs)
    problems = [(-3.0, 3.0, fn, cap) for cap in (0, 1, 3, 7)] + [(-3.0, 3.0, fn, 8),
                                                                 (-0.9, -0.8, fn, 0)]
    results = isolate_many(drv, problems)
    for p, res in zip(problems[:4], results[:4]):
        check_contract(p, res, expect_status=FULL)
        assert len(res.found) <= p[3]
        for r in res.found:
            held = [z for z in zs if r.holds(z)]
            assert len(held) == 1 and r.kind == ROOT_KIND, res
    check_contract(problems[4], results[4])
    assert len(results[4].found) == 8
    check_contract(problems[5], results[5])
    assert results[5].found == []
    total = results[4].calls
    failing = [(-3.0, 3.0, fn, 16, status, after)
               for status in (1, 7, 12345, -99) for after in (0, 1, 2, 5, total // 3, total - 1)]
    for p, res in zip(failing, isolate_many(drv, failing)):
        assert res.status == p[4], (p, res)
        assert res.calls == p[5] + 1, (p, res)             # stops at the first failure
        assert res.bad == 0 and len(res.found) <= 16


def test_isolate_budget(tmp_path_factory, runtime_driver):
    """With CODEGEN_ISOLATE_MAX_BOXES = 50: a problem that needs more returns
    CODEGEN_ISOLATE_BUDGET after exactly 50 enclosures; a small one still succeeds."""
    exe = _compile(runtime_driver, tmp_path_factory.mktemp("budget"), "interval_budget",
                   defines=["-DCODEGEN_ISOLATE_MAX_BOXES=50L"])
    d = runtime_driver.program(exe)
    problems = [(-3.0, 3.0, poly(*[-2.5, -1.75, -1.0, -0.25, 0.5, 1.25, 2.0, 2.75]), 16),
                (0.0, 1.0, poly(0.3), 4)]
    big, small = isolate_many(d, problems)
    assert big.status == BUDGET and big.calls == 50, big
    check_contract(problems[1], small)
    assert len(small.found) == 1 and small.found[0].kind == ROOT_KIND


def test_isolate_transcendental_double_zero(drv):
    """sin(t) - 1 on [1.5, 1.6], sin(t) + 1 on [-1.6, -1.5]: a double zero at +-pi/2, which
    double precision cannot separate: one CLUSTER holding it (status 0, not BUDGET); and
    sin(t) - (1 - 1e-15) on [0.5, 2.5] (zeros pi/2 -+ 4.5e-8): each zero in one interval."""
    near = 1.0 - 1e-15
    problems = [(1.5, 1.6, sin_fn(1.0), 8), (-1.6, -1.5, sin_fn(-1.0), 8),
                (0.5, 2.5, sin_fn(near), 8)]
    with mpmath.workdps(50):
        zeros = [[mpmath.pi / 2], [-mpmath.pi / 2],
                 [mpmath.asin(near), mpmath.pi - mpmath.asin(near)]]
    for p, res, zs in zip(problems, isolate_many(drv, problems), zeros):
        check_contract(p, res)
        for z in zs:
            assert len(holding(res, z)) == 1, f"{p}: {res}"
        if len(zs) == 1:
            assert len(res.found) == 1 and res.found[0].kind == CLUSTER, f"{p}: {res}"


def test_isolate_wide_intervals(drv):
    """Zeros 1 and 2 of (t - 1)(t - 2) on [0, 1e30], [-1e300, 1e300], [-1e308, 1e308]: each in a
    ROOT of its own, the enclosure only called inside [lo, hi]."""
    problems = [(0.0, 1e30, poly(1.0, 2.0), 8), (-1e300, 1e300, poly(1.0, 2.0), 8),
                (-1e308, 1e308, poly(1.0, 2.0), 8)]
    for p, res in zip(problems, isolate_many(drv, problems)):
        assert_simple_zeros(p, res, [Fraction(1), Fraction(2)], ulps_tol(4))


# ---------------------------------------------------------------------------- 3. certify

def certify_many(drv, problems):
    """problems: (lo, hi, function[, fail_status, fail_after]) -> (status, certified, calls,
    bad)."""
    lines = []
    for p in problems:
        lo, hi, fn = p[:3]
        fail_status, fail_after = p[3:5] if len(p) > 3 else (0, 0)
        lines.append(f"certify 5 {h(lo)} {h(hi)} {fail_status} {fail_after} {fn}")
    return [tuple(map(int, t)) for t in drv(lines)]


def test_certify(drv):
    """A box around one simple zero is certified (also with a flag raised outside it); boxes
    holding two or three zeros, a double zero, no zero, a pole (with a sign change across it),
    a domain edge, a flag raised inside or at an end, or lying outside the domain are not. The
    enclosure's status is passed through."""
    yes = [(0.2, 0.4, poly(0.3)), (0.29, 0.31, poly(0.3, 2.0)), (-4.0, -0.5, poly(-1.0, 1.0)),
           (0.2, 0.4, flagged(POLE | EDGE | OUTSIDE, 0.41, 0.5, poly(0.3))),
           (0.5, 1.5, sin_fn(0.9)), (0.3, 1.0, sqrt_fn(0.25, 0.5)), (-0.5, 0.0, pole(2.0, 0.3)),
           (0.3 - 1e-12, 0.3 + 1e-12, poly(0.3))]
    no = [(0.0, 1.0, poly(0.3, 0.6)), (0.0, 1.0, poly((0.3, 2))), (0.0, 1.0, poly(0.3, c=1.0)),
          (0.5, 1.0, poly(0.3)), (0.0, 1.0, pole(0.0, 0.5)), (0.0, 1.0, pole(2.0, 0.3)),
          (0.0, 1.0, sqrt_fn(0.25, 0.5)), (-1.0, 0.0, sqrt_fn(0.25, 0.5)),
          (0.0, 1.0, poly(0.3, 0.3 + 1e-12)), (0.0, 1.0, "zero"), (1.5, 1.6, sin_fn(1.0)),
          (0.0, 1.0, poly(0.2, 0.5, 0.8)),                       # three: a sign change, G' not
          (0.2, 0.4, flagged(EDGE, 0.39, 0.395, poly(0.3))),      # G not smooth inside
          (0.2, 0.4, flagged(POLE, 0.4, 0.5, poly(0.3))),         # ... at an end
          (0.2, 0.4, flagged(OUTSIDE, 0.1, 0.5, poly(0.3))),      # no state on the box
          (0.2, 0.4, flagged(OUTSIDE, 0.35, 0.5, poly(0.3)))]     # ... at an end
    fails = [(0.2, 0.4, poly(0.3), 9, 0), (0.2, 0.4, poly(0.3), -4, 1),
             (0.2, 0.4, poly(0.3), 3, 2)]
    out = certify_many(drv, yes + no + fails)
    for p, (status, certified, calls, bad) in zip(yes + no + fails, out):
        assert bad == 0, (p, out)
    for p, o in zip(yes, out[:len(yes)]):
        assert o[:2] == (0, 1), (p, o)
    for p, o in zip(no, out[len(yes):len(yes) + len(no)]):
        assert o[:2] == (0, 0), (p, o)
    for p, o in zip(fails, out[len(yes) + len(no):]):
        assert o[0] == p[3] and o[1] == 0 and o[2] == p[4] + 1, (p, o)


def newton_many(drv, problems, slope=None):
    """problems: (m, function[, fail_status, fail_after]) -> (status, certified, calls, bad,
    lo, hi); enclosures may be asked anywhere in m +- 8. slope: the slope the caller passes
    (None: 0, unknown)."""
    lines = []
    for p in problems:
        m, fn = p[:2]
        fail_status, fail_after = p[2:4] if len(p) > 2 else (0, 0)
        op = "newton" if slope is None else f"newton_slope {h(slope)}"
        lines.append(f"{op} 5 {h(m - 8.0)} {h(m + 8.0)} {fail_status} {fail_after} {fn}")
    return [tuple(int(x) for x in t[:4]) + tuple(f(x) for x in t[4:]) for t in drv(lines)]


def test_certify_newton(drv):
    """The interval Newton test proves a simple zero from a point within rounding of it (or
    near it), in an interval a few ulps wide that holds the zero, with two enclosures a try;
    it proves nothing at a double zero, a close pair, a pole or a domain edge at the point,
    beside a double zero without a real one, or where the enclosure fails (whose status it
    passes on)."""
    near = [(0.3, poly(0.3)), (0.3 + 2e-16, poly(0.3, 2.0)), (-1.0, poly(-1.0, 1.0)),
            (math.asin(0.9), sin_fn(0.9)), (0.5, sqrt_fn(0.25, 0.5)), (1e-9, poly(0.0)),
            (0.3 + 1e-9, poly(0.3))]
    for (m, fn), (status, certified, calls, bad, lo, hi) in zip(near, newton_many(drv, near)):
        assert (status, certified, bad) == (0, 1, 0), (m, fn)
        assert calls <= 5 and lo < hi and hi - lo < 1e-6, (m, fn, lo, hi)
    zeros = [0.3, 0.3, -1.0, math.asin(0.9), 0.5, 0.0, 0.3]
    for (lo, hi), z in zip([r[4:] for r in newton_many(drv, near)], zeros):
        assert lo <= z <= hi
    no = [(0.3, poly((0.3, 2))), (0.3, poly(0.3 - 1e-13, 0.3 + 1e-13)), (1.5, sin_fn(1.0)),
          (0.3, pole(0.0, 0.3)), (0.25, sqrt_fn(0.25, 0.0)), (0.3, "zero"),
          (0.3, flagged(EDGE, 0.3, 0.3, poly(0.3))), (0.3, flagged(OUTSIDE, 0.0, 1.0, poly(0.3)))]
    for p, o in zip(no, newton_many(drv, no)):
        assert o[:2] == (0, 0) and o[3] == 0 and math.isnan(o[4]), (p, o)
    fails = [(0.3, poly(0.3), 9, 0), (0.3, poly(0.3), -4, 1)]
    for p, o in zip(fails, newton_many(drv, fails)):
        assert o[0] == p[2] and o[1] == 0 and o[2] == p[3] + 1, (p, o)


def test_certify_newton_with_a_known_slope(drv):
    """Given the slope, the first enclosure is of G alone, and the proof is the same: any
    nonzero slope only sizes the interval, so a wrong one (here a hundred times too large
    or too small, or of the wrong sign) may fail to prove a zero but never proves a false
    one; at a double zero, a pole or a domain edge nothing is proven whatever the slope."""
    near = [(0.3, poly(0.3)), (-1.0, poly(-1.0, 1.0)), (math.asin(0.9), sin_fn(0.9)),
            (0.5, sqrt_fn(0.25, 0.5))]
    slopes = [1.0, -2.0, math.sqrt(1 - 0.81), 1.0]      # G'(m), up to sign
    for p, s in zip(near, slopes):
        (status, certified, calls, bad, lo, hi), = newton_many(drv, [p], slope=s)
        assert (status, certified, bad) == (0, 1, 0) and calls <= 3, (p, s)
        assert lo <= p[0] <= hi and hi - lo < 1e-6
        for wrong in (100 * s, s / 100, -s):
            (status, certified, _, bad, lo, hi), = newton_many(drv, [p], slope=wrong)
            assert status == 0 and bad == 0
            assert not certified or lo <= p[0] <= hi, (p, wrong)
    no = [(0.3, poly((0.3, 2))), (0.3, pole(0.0, 0.3)), (0.25, sqrt_fn(0.25, 0.0)),
          (0.3, flagged(EDGE, 0.3, 0.3, poly(0.3)))]
    for p in no:     # (a slope far too small sizes X past the m +- 8 the problem allows)
        for s in (1.0, 1e-30, 1e30):
            o, = newton_many(drv, [p], slope=s)
            assert o[:2] == (0, 0) and math.isnan(o[4]), (p, s, o)


# ---------------------------------------------------------------------------- 4. sanitizers

def _sanitizer_script():
    rng = np.random.default_rng([SEED, 30])
    lines = []
    for i in range(600):
        a, b = random_interval(rng, i % 2 == 0), random_interval(rng, i % 2 == 0)
        for op in ("add", "sub", "mul", "div", "sumsq"):
            lines.append(f"{op} {h(a[0])} {h(a[1])} {h(b[0])} {h(b[1])}")
        lines.append(f"pow {h(a[0])} {h(a[1])} {int(rng.integers(1, 8))}")
        for op in ("sqrt", "sin", "cos", "neg", "abs"):
            lines.append(f"{op} {h(a[0])} {h(a[1])}")
    zs = [-2.5, -1.75, -1.0, -0.25, 0.5, 1.25, 2.0, 2.75]
    problems = [(-3.0, 3.0, poly(*zs), cap) for cap in (0, 1, 2, 8, 9)]
    problems += [(-3.0, 3.0, poly(*zs), 8, 5, after) for after in (0, 3, 40)]
    problems += [(0.0, 1.0, poly((0.3, 2), 0.3 + 1e-12, 0.7), 1),
                 (0.0, 1.0, poly((0.5078125, 3), c=1e-30), 2),
                 (-2.0, 2.0, pole(0.0, 0.25), 1), (-2.0, 2.0, sqrt_fn(0.25, 0.0), 1),
                 (-10.0, 10.0, sin_fn(0.3), 3), (0.0, 1.0, "zero", 1), (0.0, 1.0, "zero", 0),
                 (-1e-300, 1e-300, poly(0.0), 1), (1.5, 1.6, sin_fn(1.0), 2),
                 (0.0, 1.0, flagged(POLE | EDGE, 0.2, 0.8, poly(0.3, 0.7)), 2),
                 (0.0, 1e30, poly(1.0, 2.0), 2), (-1e308, 1e308, poly(1.0, 2.0), 2)]
    lines += isolate_lines(problems)
    lines += [f"certify 0 {h(lo)} {h(hi)} 0 0 {fn}" for lo, hi, fn in
              [(0.2, 0.4, poly(0.3)), (0.0, 1.0, pole(0.0, 0.5)), (-1.0, 0.0, sqrt_fn(0.25, 0.5))]]
    lines += [f"newton 0 {h(m - 1)} {h(m + 1)} 0 0 {fn}" for m, fn in
              [(0.3, poly(0.3)), (0.3, poly((0.3, 2))), (0.3, pole(0.0, 0.3))]]
    return lines


def test_sanitized_driver(tmp_path, drv, sanitizer, runtime_driver):
    """The driver under AddressSanitizer + UBSan (results in heap blocks of exactly capacity
    entries, NULL at 0) over arithmetic on hostile intervals, and isolation at and beyond
    capacity, with failing enclosures, out of budget, over huge intervals: clean, and the same
    output bit for bit as the -O2 build."""
    exe = _compile(runtime_driver, tmp_path, "interval_driver_san",
                   [*sanitizer.flags, *runtime_driver.warnings])
    # leak checking is off only because LeakSanitizer cannot run under some tracers
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0", UBSAN_OPTIONS="print_stacktrace=1")
    lines = _sanitizer_script()
    sanitized = runtime_driver.program(exe, env).raw(lines)
    assert sanitized == drv.raw(lines)
