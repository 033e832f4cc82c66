"""Tests for the shared runtime's root finder, runtime/codegen_roots.c:
codegen_poly_real_roots(sigma, degree, theta, n_roots), generic in the degree (1 .. 32).

Self-contained: the runtime is compiled here into its own cffi extension (nothing of the project
is imported but runtime/cflags.txt's flags), so these tests do not depend on the state of the
generator or of generated/.
References: polynomials built in mpmath from prescribed roots and rounded once, mpmath.polyroots
at 50 digits on the exact double coefficients, Doughty's degree-12 hard vectors among them.
"""
from __future__ import annotations

import importlib.util
import math
import os
import pathlib
import subprocess

import mpmath
import numpy as np
import pytest

from .conftest import DRIVERS, RUNTIME, cflags

cffi = pytest.importorskip("cffi")

RUNTIME_SRC = RUNTIME / "codegen_roots.c"
DRIVER_SRC = DRIVERS / "roots_driver.c"

MAX_DEGREE = 64
#: Degrees swept for accuracy against known roots (random-root polynomials grow ill-conditioned
#: with the degree; 1e-9 rad was measured up to 32).
SWEPT_DEGREE = 32
OK, ERR_NULL, ERR_NONFINITE, ERR_ZERO, ERR_DEGREE = range(5)
SEED = 20_240_611

RUNTIME_CDEF = """
#define CODEGEN_MAX_DEGREE ...
typedef enum codegen_roots_status {
    CODEGEN_ROOTS_OK = 0, CODEGEN_ROOTS_ERR_NULL_POINTER = 1, CODEGEN_ROOTS_ERR_NONFINITE = 2,
    CODEGEN_ROOTS_ERR_ZERO_POLYNOMIAL = 3, CODEGEN_ROOTS_ERR_DEGREE = 4
} codegen_roots_status;
codegen_roots_status codegen_poly_real_roots(const double *sigma, int degree, double *theta,
                                             int *n_roots);
"""

def _build(tmpdir: pathlib.Path, name, cdef, source, sources, include_dirs):
    ffi = cffi.FFI()
    ffi.cdef(cdef)
    ffi.set_source(name, source, sources=[str(s) for s in sources],
                   include_dirs=[str(d) for d in include_dirs],
                   extra_compile_args=cflags("base", "optimize"), libraries=["m"])
    path = ffi.compile(tmpdir=str(tmpdir))
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.ffi, module.lib


@pytest.fixture(scope="module")
def rt(tmp_path_factory):
    """(ffi, lib) of runtime/codegen_roots.c, compiled alone."""
    d = tmp_path_factory.mktemp("rt_roots")
    return _build(d, "_rt_roots_test", RUNTIME_CDEF, '#include "codegen_runtime.h"',
                  [RUNTIME_SRC], [RUNTIME])


# ---------------------------------------------------------------------------- calling

def call(rt, sigma, degree=None):
    """(status, roots) from codegen_poly_real_roots; sigma is passed in a cffi array of exactly
    degree + 1 doubles, theta in one of exactly degree doubles."""
    ffi, lib = rt
    degree = len(sigma) - 1 if degree is None else degree
    s = ffi.new("double[]", [float(x) for x in sigma])
    th = ffi.new("double[]", max(degree, 1))
    n = ffi.new("int *", -1)
    status = lib.codegen_poly_real_roots(s, degree, th, n)
    if status != OK:
        assert n[0] == -1, "n_roots written on error"
        return status, None
    return status, list(th[0:n[0]])


def roots_of(rt, sigma):
    """The roots, after checking the output contract."""
    degree = len(sigma) - 1
    status, got = call(rt, sigma)
    assert status == OK
    assert len(got) <= degree
    assert all(not math.isnan(t) and -math.pi < t <= math.pi for t in got), got
    assert all(a < b for a, b in zip(got, got[1:])), got
    return got


def cdist(a, b):
    d = abs(a - b) % (2 * math.pi)
    return min(d, 2 * math.pi - d)


def assert_roots(got, expected, tol):
    """Same number of roots, matched in order around the circle (the match may be rotated across
    +-pi), each within tol radians."""
    expected = sorted(expected)
    assert len(got) == len(expected), f"got {got}\nexpected {expected}"
    if not got:
        return
    best = min(max(cdist(g, expected[(i + k) % len(got)]) for i, g in enumerate(got))
               for k in range(len(got)))
    assert best <= tol, f"max error {best:.3g}\ngot {got}\nexpected {expected}"


# ---------------------------------------------------------------------------- building polynomials

def from_angles(degree, thetas, complex_angles=(), scale=1.0):
    """sigma[0..degree] of scale * prod (cos(t/2) tau - sin(t/2)) * prod over the complex angles
    c of |cos(c/2) tau - sin(c/2)|^2, computed at 60 digits and rounded once. Real roots: exactly
    tau = tan(t/2) for each double t; t = 0 gives sigma_0 = 0 exactly; t = pi is the factor
    (0 tau - 1), i.e. a degree drop (sigma_degree = 0 exactly). The complex angles (nonzero
    imaginary part) give quadratic factors without real roots."""
    assert len(thetas) + 2 * len(complex_angles) == degree
    with mpmath.workdps(60):
        c = [mpmath.mpf(scale)]                                   # low to high
        for t in thetas:
            if t == math.pi:
                a, b = mpmath.mpf(0), mpmath.mpf(-1)
            else:
                a, b = mpmath.cos(mpmath.mpf(t) / 2), -mpmath.sin(mpmath.mpf(t) / 2)
            c = [x * b + y * a for x, y in zip(c + [0], [0] + c)]
        for z in complex_angles:
            w = mpmath.mpc(z) / 2
            ca, sa = mpmath.cos(w), mpmath.sin(w)
            q = [abs(sa) ** 2, -2 * mpmath.re(ca * mpmath.conj(sa)), abs(ca) ** 2]
            c = [sum(c[i - j] * q[j] for j in range(3) if 0 <= i - j < len(c))
                 for i in range(len(c) + 2)]
        return [float(x) for x in c]


def spaced_angles(rng, n, anchors, min_gap):
    """n angles in (-pi, pi], neighbours at least min_gap apart around the circle, including the
    anchors (a subset of {0, pi}) exactly."""
    if n == 0:
        return []
    starts = sorted(anchors) if anchors else [rng.uniform(-math.pi, math.pi)]
    free = n - len(starts)
    arcs = []                                         # (start, length) between anchors
    for i, s in enumerate(starts):
        end = starts[(i + 1) % len(starts)] + (2 * math.pi if i + 1 == len(starts) else 0.0)
        arcs.append((s, end - s))
    counts = [free // len(arcs) + (1 if i < free % len(arcs) else 0) for i in range(len(arcs))]
    out = list(starts)
    for (s, length), k in zip(arcs, counts):
        if k == 0:
            continue
        slack = length - (k + 1) * min_gap
        assert slack > 0
        gaps = min_gap + slack * rng.dirichlet(np.ones(k + 1))
        out += [s + g for g in np.cumsum(gaps)[:-1]]
    wrapped = []
    for t in out:
        t = math.remainder(t, 2 * math.pi)            # in [-pi, pi]
        wrapped.append(math.pi if t <= -math.pi else t)
    return wrapped


def known_case(rng, degree, nreal, anchors):
    thetas = spaced_angles(rng, nreal, anchors, min_gap=min(0.5, math.pi / max(nreal, 1)))
    npairs = (degree - nreal) // 2
    cplx = [complex(rng.uniform(-math.pi, math.pi), rng.choice([-1, 1]) * rng.uniform(0.2, 1.5))
            for _ in range(npairs)]
    scale = rng.choice([-1, 1]) * 10.0 ** rng.uniform(-6, 6)
    return from_angles(degree, thetas, cplx, scale), thetas


# ---------------------------------------------------------------------------- known roots, 1..32

@pytest.mark.parametrize("degree", range(1, SWEPT_DEGREE + 1))
def test_known_roots_every_degree(rt, degree):
    """Prescribed real roots (random well-separated angles, also theta = 0 via sigma_0 = 0 and
    theta = pi via sigma_degree = 0) times random quadratics without real roots: exactly the
    prescribed roots, each within 1e-9 rad, 0 and pi exactly."""
    rng = np.random.default_rng([SEED, degree])
    configs = []
    for nreal in sorted({degree, degree - 2, degree % 2, degree // 2 + (degree // 2 - degree) % 2}):
        if nreal < 0:
            continue
        for anchors in ([], [0.0], [math.pi], [0.0, math.pi]):
            if len(anchors) <= nreal:
                configs.append((nreal, anchors))
    for nreal, anchors in configs:
        assert (degree - nreal) % 2 == 0
        sigma, thetas = known_case(rng, degree, nreal, anchors)
        assert len(sigma) == degree + 1
        assert (sigma[0] == 0.0) == (0.0 in thetas)
        assert (sigma[-1] == 0.0) == (math.pi in thetas)
        got = roots_of(rt, sigma)
        assert_roots(got, thetas, tol=1e-9)
        for t in anchors:
            assert got.count(t) == 1, (t, got)


def test_multiple_roots_at_zero_and_pi_reported_once(rt):
    """tau^k factors and degree drops by k: theta = 0 and theta = pi once each, every degree."""
    rng = np.random.default_rng(SEED)
    for degree in range(2, SWEPT_DEGREE + 1):
        k0 = int(rng.integers(1, degree // 2 + 1))
        kpi = int(rng.integers(1, degree - k0 + 1))
        rest = degree - k0 - kpi
        nreal = rest % 2
        thetas = spaced_angles(rng, nreal, [], 0.5)
        thetas = [t if cdist(t, 0) > 0.3 and cdist(t, math.pi) > 0.3 else 1.0 for t in thetas]
        cplx = [complex(rng.uniform(-3, 3), rng.uniform(0.3, 1.2)) for _ in range(rest // 2)]
        inner = from_angles(rest, thetas, cplx, 1.0)
        sigma = [0.0] * k0 + inner + [0.0] * kpi
        assert len(sigma) == degree + 1
        got = roots_of(rt, sigma)
        assert got.count(0.0) == 1 and got.count(math.pi) == 1
        assert_roots(got, thetas + [0.0, math.pi], tol=1e-9)


def _mp_reference(sigma, dps=50):
    """Real roots (as sorted theta) of the polynomial with exactly these double coefficients, by
    mpmath.polyroots at dps digits; None if some root is neither clearly real nor clearly
    complex, or two real roots are closer than 1e-6 rad."""
    lo = next(i for i, x in enumerate(sigma) if x != 0)
    hi = max(i for i, x in enumerate(sigma) if x != 0)
    out = ([0.0] if lo > 0 else []) + ([math.pi] if hi < len(sigma) - 1 else [])
    if hi > lo:
        # numpy's roots only seed the Durand-Kerner iteration (5x faster at degree 32); its
        # result is mpmath's, converged to the last correction below 10^-dps.
        high_first = list(reversed(sigma[lo:hi + 1]))
        init = [complex(z) for z in np.roots(high_first)]
        with mpmath.workdps(dps):
            c = [mpmath.mpf(x) for x in high_first]
            zs, err = mpmath.polyroots(c, maxsteps=400, extraprec=40, error=True,
                                       roots_init=init)
            assert err < mpmath.mpf(10) ** (-dps + 5)
            for z in map(mpmath.mpc, zs):
                if abs(z.imag) < mpmath.mpf(10) ** (-dps // 2):
                    out.append(float(2 * mpmath.atan(z.real)))
                elif abs(z.imag) < 1e-8 * (1 + abs(z)):
                    return None                           # nearly real: ambiguous
    out.sort()
    if len(out) > 1 and any(cdist(a, b) < 1e-6 for a, b in zip(out, out[1:] + out[:1])):
        return None
    return out


@pytest.mark.parametrize("degree", range(1, SWEPT_DEGREE + 1))
def test_dense_random_against_mpmath(rt, degree):
    """Random dense coefficients, Gaussian and with magnitudes spread over 1e+-4 (so that the
    real roots also lie near tau = 0 and tau = infinity): the same real roots as
    mpmath.polyroots at 50 digits on the exact double coefficients, within 1e-10 rad."""
    rng = np.random.default_rng([SEED, 1, degree])
    for spread in (0.0, 4.0):
        for _ in range(20):                   # redraw in the (rare) ambiguous cases
            sigma = rng.standard_normal(degree + 1) * 10.0 ** rng.uniform(-spread, spread,
                                                                           degree + 1)
            sigma = [float(x) for x in sigma]
            ref = _mp_reference(sigma)
            if ref is not None:
                break
        else:
            pytest.fail("no unambiguous random polynomial drawn")
        assert_roots(roots_of(rt, sigma), ref, tol=1e-10)


# ---------------------------------------------------------------------------- bit identity, degree 12
# The runtime once replaced a degree-12 finder written for Doughty alone; the vectors that
# proved them bit-identical now hold the runtime to 50-digit references.

def _degree12_vectors():
    """Several thousand degree-12 coefficient vectors: random dense and wide-magnitude ones,
    products of known real roots and complex pairs (in double arithmetic), close pairs ~1e-4
    apart, double roots (exact and rounded), roots on the seam tau = +-1, zero or few-ulp
    leading / trailing coefficients, and a few non-finite / zero ones (statuses)."""
    rng = np.random.default_rng([SEED, 12])
    P = np.polynomial.polynomial
    out = []

    def product(taus, npairs, scale):
        c = np.array([scale])
        for t in taus:
            c = P.polymul(c, [-t, 1.0])
        for _ in range(npairs):
            re, im = rng.uniform(-3, 3), rng.uniform(0.01, 2)
            c = P.polymul(c, [re * re + im * im, -2 * re, 1.0])
        c = list(c) + [0.0] * (13 - len(c))
        return c[:13]

    def random_taus(k):
        return list(np.tan(rng.uniform(-np.pi / 2, np.pi / 2, k)))

    for _ in range(800):                                       # dense
        out.append(list(rng.standard_normal(13) * 10.0 ** rng.uniform(-8, 8)))
    for _ in range(400):                                       # wide magnitudes
        out.append(list(rng.choice([-1.0, 1.0], 13) * 10.0 ** rng.uniform(-6, 8, 13)))
    for _ in range(1000):                                      # known real roots
        k = int(rng.integers(0, 13))
        out.append(product(random_taus(k), (12 - k) // 2, 10.0 ** rng.uniform(-3, 5)))
    for _ in range(800):                                       # close pairs ~1e-4 apart
        k = int(rng.integers(2, 13))
        taus = random_taus(k - 2)
        t0 = float(np.tan(rng.uniform(-np.pi / 2, np.pi / 2)))
        taus += [t0, t0 + rng.choice([-1, 1]) * 1e-4 * rng.uniform(0.3, 3) * (1 + t0 * t0)]
        out.append(product(taus, (12 - k) // 2, 10.0 ** rng.uniform(-3, 5)))
    for _ in range(800):                                       # double roots
        k = int(rng.integers(2, 13))
        t0 = (float(rng.integers(-16, 17)) / 8 if rng.random() < 0.5
              else float(np.tan(rng.uniform(-np.pi / 2, np.pi / 2))))
        taus = random_taus(k - 2) + [t0, t0]
        out.append(product(taus, (12 - k) // 2, 2.0 ** int(rng.integers(-4, 8))))
    for _ in range(500):            # near rule 5's thresholds: pairs 1e-6..1e-4 apart, residues
        k = int(rng.integers(2, 13))  # of up to 160 ulps of the largest coefficient (CR_ULPS 64)
        t0 = float(np.tan(rng.uniform(-np.pi / 2, np.pi / 2)))
        gap = 10.0 ** rng.uniform(-6, -4) * (1 + t0 * t0)
        c = product(random_taus(k - 2) + [t0, t0 + gap], (12 - k) // 2, 1.0)
        big = max(map(abs, c))
        ulps = 160 * rng.random()
        out.append([x + rng.uniform(-1, 1) * ulps * 2.2e-16 * big for x in c])
    for _ in range(600):                                       # seam: (1 -+ tau)^2 factors
        seam = [[1.0, 1.0], [1.0, -1.0], [1.0, 0.0, -1.0]][int(rng.integers(0, 3))]
        f = P.polymul(seam, seam)
        k = int(rng.integers(0, 13 - (len(f) - 1)))
        c = P.polymul(f, product(random_taus(k), 0, 10.0 ** rng.uniform(-2, 4))[:k + 1])
        c = list(c) + [0.0] * 13
        out.append(c[:13])
    for _ in range(1000):                                      # zeros / residues at the ends
        base = out[int(rng.integers(0, len(out)))][:]
        lo, hi = int(rng.integers(0, 4)), int(rng.integers(0, 4))
        big = max(map(abs, base)) or 1.0
        residue = rng.random() < 0.4
        for i in range(lo):
            base[i] = rng.uniform(-8, 8) * 2.2e-16 * big if residue else 0.0
        for i in range(hi):
            base[12 - i] = rng.uniform(-8, 8) * 2.2e-16 * big if residue else 0.0
        if max(map(abs, base)) == 0.0:
            base[6] = 1.0
        out.append(base)
    nan_inf = [float("nan"), float("inf"), -float("inf")]
    for i in range(13):                                        # statuses
        v = [1.0] * 13
        v[i] = nan_inf[i % 3]
        out.append(v)
    out.append([0.0] * 13)
    out.append([-0.0] * 13)
    return [[float(x) for x in v] for v in out]


def _near_double(sigma) -> bool:
    """Two roots (in tau) within 1e-3 of each other, relatively, or a root nearly real."""
    nonzero = [i for i, x in enumerate(sigma) if x != 0]
    roots = np.roots(list(reversed(sigma[nonzero[0]:nonzero[-1] + 1])))
    scale = 1 + np.abs(roots)
    nearly_real = (np.abs(roots.imag) > 0) & (np.abs(roots.imag) < 1e-3 * scale)
    gaps = np.abs(roots[:, None] - roots[None, :]) + np.eye(len(roots))
    return bool(np.any(nearly_real) or np.any(gaps < 1e-3 * scale[:, None]))


def test_degree12_hard_vectors_against_mpmath(rt):
    """Doughty's degree: a sample of the hard vectors (close pairs, double roots, roots on the
    seam, tiny leading or trailing coefficients) has the real roots of mpmath.polyroots at
    50 digits, where those are unambiguous; the non-finite and zero ones fail with a status."""
    vectors = _degree12_vectors()
    checked = 0
    for v in vectors[::40]:
        status, got = call(rt, v)
        if not all(map(math.isfinite, v)):
            assert status == ERR_NONFINITE, v
            continue
        if not any(v):
            assert status == ERR_ZERO, v
            continue
        assert status == OK, v
        if _near_double(v):      # double roots and close pairs: their count is rounding's
            continue
        ref = _mp_reference(v)
        if ref is None:
            continue
        assert_roots(got, ref, tol=1e-7)
        checked += 1
    assert checked > 60


# ---------------------------------------------------------------------------- reads and writes

@pytest.mark.parametrize("degree", range(1, SWEPT_DEGREE + 1))
def test_reads_exactly_degree_plus_one_coefficients(rt, degree):
    """sigma in an array of exactly degree + 1 doubles (see call), and again inside a buffer
    padded with NaN on both sides: a read outside sigma[0..degree] would see a NaN and report
    ERR_NONFINITE. theta is padded with sentinels: only theta[0..n_roots) is written."""
    ffi, lib = rt
    rng = np.random.default_rng([SEED, 2, degree])
    pad = 8
    for trial in range(4):
        if trial < 2:
            sigma = [float(x) for x in rng.standard_normal(degree + 1)]
        else:
            nreal = degree - 2 * int(rng.integers(0, degree // 2 + 1))
            anchors = [[0.0], [math.pi]][trial % 2] if nreal >= 1 else []
            sigma, _ = known_case(rng, degree, nreal, anchors)
        status, exact = call(rt, sigma)
        assert status == OK
        buf = ffi.new("double[]", [math.nan] * pad + sigma + [math.nan] * pad)
        th = ffi.new("double[]", [7.0] * (degree + pad))
        n = ffi.new("int *", -1)
        assert lib.codegen_poly_real_roots(buf + pad, degree, th, n) == OK
        assert list(th[0:n[0]]) == exact
        assert list(th[n[0]:degree + pad]) == [7.0] * (degree + pad - n[0])


@pytest.mark.slow   # ~50 s under ASan and UBSan: make test-all (CI)
def test_sanitized_driver(tmp_path, sanitizer):
    """drivers/roots_driver.c under AddressSanitizer + UBSan: every degree 1..CODEGEN_MAX_DEGREE
    with heap blocks of exactly degree + 1 coefficients and degree roots."""
    exe = tmp_path / "roots_driver"
    subprocess.run([sanitizer.cc, *sanitizer.flags, f"-I{RUNTIME}", str(DRIVER_SRC),
                    str(RUNTIME_SRC), "-lm",
                    "-o", str(exe)], check=True, capture_output=True, text=True)
    # The runtime allocates nothing, and the driver frees what it allocates; leak checking is
    # off only because LeakSanitizer cannot run under some tracers/containers.
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0", UBSAN_OPTIONS="print_stacktrace=1")
    r = subprocess.run([str(exe), "300"], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("ok ")


# ---------------------------------------------------------------------------- statuses

def test_status_codes(rt):
    """NULL pointers, NaN / inf coefficients, the zero polynomial, a bad degree; the values 0..4
    as documented; on error, theta and n_roots untouched."""
    ffi, lib = rt
    assert (lib.CODEGEN_ROOTS_OK, lib.CODEGEN_ROOTS_ERR_NULL_POINTER, lib.CODEGEN_ROOTS_ERR_NONFINITE,
            lib.CODEGEN_ROOTS_ERR_ZERO_POLYNOMIAL, lib.CODEGEN_ROOTS_ERR_DEGREE) == (0, 1, 2, 3, 4)
    assert lib.CODEGEN_MAX_DEGREE == MAX_DEGREE

    def run(sigma, degree, null=()):
        s = ffi.NULL if "sigma" in null else ffi.new("double[]", sigma)
        th = ffi.NULL if "theta" in null else ffi.new("double[]", [5.0] * max(degree, 1))
        n = ffi.NULL if "n" in null else ffi.new("int *", -7)
        status = lib.codegen_poly_real_roots(s, degree, th, n)
        if status != OK:
            if th != ffi.NULL:
                assert list(th[0:max(degree, 1)]) == [5.0] * max(degree, 1)
            if n != ffi.NULL:
                assert n[0] == -7
        return status

    good = [1.0, -3.0, 2.0]                                   # roots tau = 1, 2
    assert run(good, 2) == OK
    for null in (("sigma",), ("theta",), ("n",), ("sigma", "theta", "n")):
        assert run(good, 2, null) == ERR_NULL
    for bad in (math.nan, math.inf, -math.inf):
        for i in range(3):
            v = good[:]
            v[i] = bad
            assert run(v, 2) == ERR_NONFINITE
    for degree in (1, 12, MAX_DEGREE):
        assert run([0.0] * (degree + 1), degree) == ERR_ZERO
        assert run([-0.0] * (degree + 1), degree) == ERR_ZERO
    # a NaN is reported before the zero test, whatever its position
    assert run([0.0, 0.0, math.nan], 2) == ERR_NONFINITE
    # the degree is checked first, before any pointer is used or anything is read
    for degree in (0, -1, MAX_DEGREE + 1, 1000, -(2**31)):
        assert run([1.0] * 2, degree) == ERR_DEGREE
        assert run([1.0] * 2, degree, ("sigma", "theta", "n")) == ERR_DEGREE
    # degree 33 with 34 good coefficients: still refused
    assert run([1.0] * (MAX_DEGREE + 2), MAX_DEGREE + 1) == ERR_DEGREE


def test_scale_invariance_and_simple_cases(rt):
    """Power-of-two scaling changes nothing (bit for bit); degree 1 and 2 by hand."""
    assert roots_of(rt, [0.0, 1.0]) == [0.0]                  # tau = 0
    assert roots_of(rt, [1.0, 0.0]) == [math.pi]              # tau = infinity
    assert roots_of(rt, [-1.0, 1.0]) == [math.pi / 2]         # tau = 1, on the seam
    assert roots_of(rt, [1.0, 0.0, 1.0]) == []                # tau^2 + 1
    assert roots_of(rt, [0.0, 0.0, 1.0]) == [0.0]             # double root at 0, once
    assert roots_of(rt, [1.0, 0.0, 0.0]) == [math.pi]         # double root at pi, once
    rng = np.random.default_rng([SEED, 3])
    for degree in (3, 12, 32):
        for _ in range(20):
            sigma = [float(x) for x in rng.standard_normal(degree + 1)]
            base = roots_of(rt, sigma)
            for e in (-1000, -30, 7, 900):
                scaled = [math.ldexp(x, e) for x in sigma]
                assert [x.hex() for x in roots_of(rt, scaled)] == [x.hex() for x in base]
