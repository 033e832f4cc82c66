"""Tests for templates/c/doughty_roots.c: doughty_poly_real_roots.

Called through the project's cffi extension, i.e. the copy in generated/ as shipped (its strict
compilation is tested in test_generation.py).
References: roots built exactly, mpmath.polyroots at 50+ digits on the exact double coefficients,
and exact Sturm counts (sympy) for integer polynomials.
"""
import math
import random
from fractions import Fraction

import mpmath
import pytest
import sympy
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from codegen.api import load

api = load("doughty")
_ffi, _lib = api.ffi, api.lib


OK, ERR_NULL, ERR_NONFINITE, ERR_ZERO = (api.STATUS[k] for k in (
    "OK", "ERR_NULL_POINTER", "ERR_NONFINITE", "ERR_ZERO_POLYNOMIAL"))


@pytest.fixture(scope="session")
def clib():
    """(ffi, lib) exposing doughty_poly_real_roots, from the project's extension."""
    return _ffi, _lib


def call(clib, sigma):
    ffi, lib = clib
    s = ffi.new("double[13]", [float(x) for x in sigma])
    th = ffi.new("double[12]")
    n = ffi.new("int *", -1)
    status = lib.doughty_poly_real_roots(s, th, n)
    if status != OK:
        return status, None
    assert 0 <= n[0] <= 12
    return status, list(th[0:n[0]])


def roots_of(clib, sigma):
    status, got = call(clib, sigma)
    assert status == OK
    assert got == sorted(got)
    assert all(-math.pi < t <= math.pi for t in got)
    return got


# ---------------------------------------------------------------- references and helpers

def poly_from_theta(thetas, pairs=(), scale=1.0):
    """sigma (low to high) of scale * prod (cos(t/2) tau - sin(t/2)) * prod |tau - z|^2, exact in
    mpmath then rounded once. A theta of pi gives a degree drop (root at tau = infinity)."""
    with mpmath.workdps(60):
        c = [mpmath.mpf(scale)]                           # high to low
        for t in thetas:
            a, b = mpmath.cos(mpmath.mpf(t) / 2), -mpmath.sin(mpmath.mpf(t) / 2)
            c = [x * a + y * b for x, y in zip(c + [0], [0] + c)]
        for re, im in pairs:
            q = [mpmath.mpf(1), -2 * mpmath.mpf(re), mpmath.mpf(re) ** 2 + mpmath.mpf(im) ** 2]
            c = [sum(c[i - j] * q[j] for j in range(3) if 0 <= i - j < len(c))
                 for i in range(len(c) + 2)]
        low = [float(x) for x in reversed(c)]
    assert len(low) <= 13
    return low + [0.0] * (13 - len(low))


def poly_from_tau(taus, pairs=(), scale=1.0):
    return poly_from_theta([2 * math.atan(t) for t in taus], pairs, scale)


def reference(sigma, dps=50):
    """Distinct real roots, as sorted theta, of the polynomial with exactly these coefficients."""
    lo = next(i for i, x in enumerate(sigma) if x != 0)
    hi = max(i for i, x in enumerate(sigma) if x != 0)
    out = ([0.0] if lo > 0 else []) + ([math.pi] if hi < 12 else [])
    if hi > lo:
        with mpmath.workdps(dps):
            c = [mpmath.mpf(x) for x in reversed(sigma[lo:hi + 1])]
            try:
                zs = mpmath.polyroots(c, maxsteps=400, extraprec=300)
            except mpmath.libmp.NoConvergence:
                zs = mpmath.polyroots(c, maxsteps=3000, extraprec=3000)
            out += [float(2 * mpmath.atan(z.real)) for z in map(mpmath.mpc, zs)
                    if abs(z.imag) < mpmath.mpf(10) ** (-dps // 3)]
    out.sort()
    distinct = []
    for t in out:
        if not distinct or t - distinct[-1] > 1e-15:
            distinct.append(t)
    if len(distinct) > 1 and distinct[0] + 2 * math.pi - distinct[-1] <= 1e-15:
        distinct.pop(0)
    return distinct


def exact_count(sigma):
    """Distinct real roots on the projective line (tau = infinity is theta = pi), by Sturm."""
    tau = sympy.Symbol("tau")
    count = 1 if sigma[12] == 0 else 0
    hi = max(i for i, x in enumerate(sigma) if x != 0)
    if hi > 0:
        coeffs = [sympy.Rational(Fraction(x)) for x in reversed(sigma[:hi + 1])]
        count += sympy.Poly(coeffs, tau).count_roots()
    return count


def cdist(a, b):
    d = abs(a - b) % (2 * math.pi)
    return min(d, 2 * math.pi - d)


def assert_roots(got, expected, tol=1e-9):
    """Same number of roots, matched in order around the circle, each within tol radians."""
    expected = sorted(expected)
    assert len(got) == len(expected), f"got {got}\nexpected {expected}"
    if not got:
        return
    # allow the match to be rotated across +-pi
    best = min(max(cdist(g, expected[(i + k) % len(got)]) for i, g in enumerate(got))
               for k in range(len(got)))
    assert best <= tol, f"max error {best:.3g}\ngot {got}\nexpected {expected}"


# ---------------------------------------------------------------- prescribed roots

TABLE3_DEG = [12.4726, 8.8080, 0.7032, 92.3711, 176.715, 92.5475, 92.3977, 178.8249, 0.3688,
              92.5174]


@pytest.mark.parametrize("pair", [(0.5, 0.5), (1.0, 0.1), (-1.0, 0.2), (3.0, 1.0), (0.0, 3.0)])
def test_application_like_roots_with_close_pairs(clib, pair):
    """Ten roots of the paper's Table 3: two pairs near tau ~ 1.04 only 0.03 deg apart."""
    thetas = [math.radians(t) for t in TABLE3_DEG]
    sigma = poly_from_theta(thetas, [pair], scale=1e3)
    got = roots_of(clib, sigma)
    assert_roots(got, reference(sigma))
    # Rounding the coefficients once already moves these ill-conditioned pairs (by up to 5e-5
    # rad when the complex pair is near them): the exact-coefficient reference above is the test.
    assert_roots(got, thetas, tol=1e-4)


def test_degree_12_all_real(clib):
    thetas = [-3.0, -2.5, -1.9, -1.2, -0.7, -0.2, 0.1, 0.6, 1.3, 1.8, 2.4, 3.1]
    sigma = poly_from_theta(thetas)
    assert_roots(roots_of(clib, sigma), reference(sigma))
    assert_roots(roots_of(clib, sigma), thetas)


@pytest.mark.parametrize("degree", range(1, 13))
def test_known_roots_each_degree(clib, degree):
    """Degree 1..12 polynomials: prescribed real roots plus complex pairs. Degree < 12 means
    sigma_12 = 0, i.e. an extra root at theta = pi."""
    rng = random.Random(degree)
    npairs = rng.randint(0, degree // 2)
    nreal = degree - 2 * npairs
    thetas = [-3.0 + 6.0 * (i + rng.random() * 0.8) / max(nreal, 1) for i in range(nreal)]
    pairs = [(rng.uniform(-2, 2), rng.uniform(0.2, 2)) for _ in range(npairs)]
    sigma = poly_from_theta(thetas, pairs, scale=rng.choice([1e-3, 1.0, 1e4]))
    expected = thetas + ([math.pi] if degree < 12 else [])
    got = roots_of(clib, sigma)
    assert_roots(got, expected)
    assert_roots(got, reference(sigma))


@pytest.mark.parametrize("t0", [1.04, -1.04, 0.0, 2.5e-4, 1e-3])
def test_close_pairs(clib, t0):
    """Two pairs 5e-4 apart in tau (0.03 deg in theta), near tau = t0."""
    taus = [t0, t0 + 5e-4, t0 + 3e-3, t0 + 3.5e-3, -0.4, 3.0, 0.6]
    sigma = poly_from_tau(taus, [(0.3, 0.7), (-2.0, 1.0)], scale=1e5)
    got = roots_of(clib, sigma)
    assert_roots(got, reference(sigma))
    assert_roots(got, [2 * math.atan(t) for t in taus] + [math.pi], tol=1e-6)


# ---------------------------------------------------------------- tau = infinity, multiplicity

def test_leading_coefficient_exactly_zero(clib):
    thetas = [-2.0, -0.5, 0.3, 1.1, 2.7]
    sigma = poly_from_theta(thetas + [math.pi])   # cos(pi/2) is not exactly 0 in double
    sigma[6] = 0.0
    assert sigma[6:] == [0.0] * 7
    got = roots_of(clib, sigma)
    assert got[-1] == math.pi
    assert_roots(got, thetas + [math.pi])


@pytest.mark.parametrize("rel", [1e-14, -1e-14, 1e-10])
def test_leading_coefficient_nearly_zero(clib, rel):
    """sigma_12 tiny relative to the rest: a simple root near theta = +-pi."""
    thetas = [-2.2, -1.0, -0.1, 0.4, 1.5, 2.9, 0.9, -2.9, 2.0, -1.7, 0.05]
    sigma = poly_from_theta(thetas)
    sigma = [x / max(map(abs, sigma)) for x in sigma[:12]] + [rel]
    got = roots_of(clib, sigma)
    assert_roots(got, reference(sigma))
    assert min(cdist(t, math.pi) for t in got) < 1e-6


def test_double_root_at_pi_from_degree_drop(clib):
    """sigma_12 = sigma_11 = 0: tau = infinity is a double root, reported once as pi."""
    thetas = [-2.5, -1.0, 0.2, 0.8, 1.9, 2.6]
    sigma = poly_from_theta(thetas, [(0.5, 0.5), (-1.0, 2.0)])
    assert sigma[10] != 0 and sigma[11] == sigma[12] == 0
    assert_roots(roots_of(clib, sigma), thetas + [math.pi])


def test_double_root_at_zero_from_tau_squared(clib):
    thetas = [-2.5, -1.0, 0.8, 1.9]
    sigma = poly_from_theta(thetas, [(0.5, 0.5), (-1.0, 2.0), (2.0, 0.3)])
    sigma = [0.0, 0.0] + sigma[:11]
    assert sigma[12] != 0
    assert_roots(roots_of(clib, sigma), thetas + [0.0])


def test_sin_squared_factor(clib):
    """sin^2(theta) -> tau^2 factor and degree drop by 2: double roots at 0 and pi, once each."""
    thetas = [-2.0, -0.6, 1.2, 2.8]
    sigma = poly_from_theta(thetas, [(0.7, 0.9), (-0.4, 0.25)], scale=3.7e6)
    sigma = [0.0, 0.0] + sigma[:9] + [0.0, 0.0]
    got = roots_of(clib, sigma)
    assert got.count(0.0) == 1 and got.count(math.pi) == 1
    assert_roots(got, thetas + [0.0, math.pi])


@pytest.mark.parametrize("seed", range(6))
def test_sin_squared_factor_with_rounding_residues(clib, seed):
    """As above, but sigma_0, sigma_1, sigma_11, sigma_12 are not exactly zero: residues of a few
    ulps of the largest coefficient, as computed coefficients that should vanish would be.
    The double roots at 0 and pi must still be reported, once each."""
    rng = random.Random(seed)
    thetas = [-2.0, -0.6, 1.2, 2.8]
    sigma = poly_from_theta(thetas, [(0.7, 0.9), (-0.4, 0.25)], scale=rng.uniform(1, 1e3))
    big = max(map(abs, sigma))
    residue = [rng.choice([-1, 1]) * rng.uniform(0, 8) * 2.2e-16 * big for _ in range(4)]
    sigma = residue[:2] + sigma[:9] + residue[2:]
    got = roots_of(clib, sigma)
    assert_roots(got, thetas + [0.0, math.pi], tol=1e-6)


def _expand(taus_low_to_high_factors):
    c = [1]
    for f in taus_low_to_high_factors:
        c = [sum(c[i - j] * f[j] for j in range(len(f)) if 0 <= i - j < len(c))
             for i in range(len(c) + len(f) - 1)]
    return [float(x) for x in c] + [0.0] * (13 - len(c))


@pytest.mark.parametrize("factors, roots_tau", [
    # dyadic factors (low to high): every coefficient exact, every multiple root exact
    ([[-1, 2], [-1, 2], [3, 1], [1, 1, 1]], [0.5, -3.0]),                    # double at 0.5
    ([[-1, 4], [-1, 4], [-1, 4], [2, 1], [5, -1], [1, 0, 4]], [0.25, -2.0, 5.0]),  # triple
    ([[-1, 1], [-1, 1], [1, 1], [1, 1], [-3, 1], [1, 0, 1]], [1.0, -1.0, 3.0]),  # seam tau = +-1
    ([[-3, 1], [-3, 1], [1, 8], [1, 8], [1, 1, 1], [7, 0, 1], [-2, 1]], [3.0, -0.125, 2.0]),
])
def test_exact_multiple_roots_reported_once(clib, factors, roots_tau):
    sigma = _expand(factors)
    expected = [2 * math.atan(t) for t in roots_tau]
    if sigma[12] == 0:
        expected.append(math.pi)
    assert_roots(roots_of(clib, sigma), expected, tol=1e-12)


@pytest.mark.parametrize("r", [0.3, -0.7, 1.7, -2.9, 0.01])
def test_rounded_double_root_reported_once(clib, r):
    """A double root whose coefficients were computed in double arithmetic (so it is split into
    a close pair or a complex pair by rounding) is still one root."""
    c = [1.0]
    for t in [r, r, 0.4, -1.3, 2.2]:
        c = [a - t * b for a, b in zip(c + [0.0], [0.0] + c)]     # high to low, in floats
    sigma = list(reversed(c)) + [0.0] * (13 - len(c))
    got = roots_of(clib, sigma)
    expected = [2 * math.atan(t) for t in (r, 0.4, -1.3, 2.2)] + [math.pi]
    assert_roots(got, expected, tol=1e-6)


# ---------------------------------------------------------------- double roots on the chart seam

HALF_PI = math.pi / 2

# sigma from the application's degenerate mechanisms (k = 0; H = 0 with k = g = 1 and with
# k = g = 3; H = 0). The exact polynomials have a factor cos^2(theta), i.e. (1 - tau^2)^2:
# double roots at theta = +-90 deg, the charts' seam tau = +-1. Rounding split them into
# complex pairs (real parts within 2e-17 of +-1, imaginary parts 8e-11 .. 6e-9) or, for the
# second, into real pairs ~1e-8 apart straddling the seam. Only the fourth has other real roots.
APPLICATION_SEAM_CASES = [
    [6.685740933115995, -0.0, 7822.31689174572, -0.0, 314.229823856452, 0.0, -15644.63378349144,
     0.0, -648.516870512252, 0.0, 7822.31689174572, 0.0, 327.601305722684],
    [0.19026349577573148, 0.09712260419478268, 0.9033850618848147, 0.35769577264066715,
     -0.15701021116697406, -0.45481837683544984, -1.8732766929871447, -0.4548183768354498,
     -0.15701021116697406, 0.35769577264066715, 0.9033850618848147, 0.09712260419478268,
     0.19026349577573148],
    [1.7123714619815833, 0.8741034377530436, 8.130465556963332, 3.2192619537660025,
     -1.4130919005027667, -4.093365391519046, -16.859490236884294, -4.093365391519046,
     -1.4130919005027667, 3.2192619537660025, 8.130465556963332, 0.8741034377530436,
     1.7123714619815833],
    [60.171668398044, -8312.676694827749, -59735.5350931141, -1042779.1098289477,
     35727655.376331605, 1051091.7865237754, -71335960.02581377, 1051091.7865237754,
     35727655.376331605, -1042779.1098289477, -59735.53509311413, -8312.676694827749,
     60.171668398044],
]


def assert_seam_roots(got, sigma, seam):
    """Each seam root reported once, exactly; the others as the exact-coefficient reference."""
    for t in seam:
        assert got.count(t) == 1, f"{t} not reported exactly once in {got}"
    far = [t for t in reference(sigma) if all(cdist(t, s) > 1e-4 for s in seam)]
    assert_roots(got, far + seam)


@pytest.mark.parametrize("sigma", APPLICATION_SEAM_CASES)
def test_application_double_roots_on_the_seam(clib, sigma):
    assert_seam_roots(roots_of(clib, sigma), sigma, [-HALF_PI, HALF_PI])


SEAM_FACTORS = {                                  # low to high; tau = +-1 is theta = +-90 deg
    "1-tau^2 squared": ([[1, 0, -1], [1, 0, -1]], [-HALF_PI, HALF_PI]),
    "1+tau squared": ([[1, 1], [1, 1]], [-HALF_PI]),
    "1-tau squared": ([[1, -1], [1, -1]], [HALF_PI]),
}


@pytest.mark.parametrize("name", SEAM_FACTORS)
@pytest.mark.parametrize("rest", [[], [[-3, 1], [1, 0, 4]], [[1, 2], [5, -1], [1, 1, 1], [2, 0, 1]],
                                  [[1, 8], [1, 8], [3, -2], [1, 0, 1], [1, 0, 1]]])
@pytest.mark.parametrize("reverse", [False, True])
def test_exact_double_roots_on_the_seam(clib, name, rest, reverse):
    """Integer coefficients: the seam's double roots are exact. (The quadratic factors have no
    real roots.)"""
    factors, seam = SEAM_FACTORS[name]
    sigma = _expand(factors + rest)
    others = {2 * math.atan(-f[0] / f[1]) for f in rest if len(f) == 2}
    if sigma[12] == 0:
        others.add(math.pi)
    if reverse:                                   # tau -> 1/tau: theta -> pi - theta (mod 2 pi)
        sigma.reverse()
        seam = [math.pi - t if t > 0 else -math.pi - t for t in seam]
        others = {math.pi - t for t in others}
    got = roots_of(clib, sigma)
    assert all(got.count(t) == 1 for t in seam), got
    assert_roots(got, seam + list(others), tol=1e-12)


@pytest.mark.parametrize("name", SEAM_FACTORS)
@pytest.mark.parametrize("seed", range(10))
def test_rounded_double_roots_on_the_seam(clib, name, seed):
    """As the application's: the other factors, the scale and the products are not exact, and
    every coefficient carries a residue of up to 4 ulps of the largest, so that each double root
    on the seam is split into a complex pair or a real pair ~1e-8 apart straddling the seam (the
    seeds give 12 of the one, 28 of the other). One root each, exactly on the seam."""
    factors, seam = SEAM_FACTORS[name]
    rng = random.Random(seed)
    others = [rng.choice([-1, 1]) * rng.uniform(1.1, 3) ** rng.choice([-1, 1])
              for _ in range(rng.randint(0, 3))]
    scale = rng.uniform(0.1, 1e4)
    c = [scale * x for x in _expand(factors)[:len(factors) * len(factors[0]) - 1]]
    for t in others:
        c = [a - t * b for a, b in zip([0.0] + c, c + [0.0])]
    for _ in range(rng.randint(0, 3)):
        re, im = rng.uniform(-2, 2), rng.uniform(0.1, 2)
        q = [re * re + im * im, -2 * re, 1.0]
        c = [sum(c[i - j] * q[j] for j in range(3) if 0 <= i - j < len(c))
             for i in range(len(c) + 2)]
    big = max(map(abs, c))
    c = [x + rng.uniform(-4, 4) * 2.2e-16 * big for x in c]
    c[0] += (-1) ** seed * 4 * 2.2e-16 * big
    sigma = c + [0.0] * (13 - len(c))
    assert_seam_roots(roots_of(clib, sigma), sigma, seam)


@pytest.mark.parametrize("name, t0", [(n, t) for n in SEAM_FACTORS for t in (0, 2.5e-4, 0.5, -0.6)]
                         + [("1-tau^2 squared", 1.04), ("1+tau squared", 1.04),
                            ("1-tau squared", -1.04)])
def test_double_roots_on_the_seam_with_close_pairs(clib, name, t0):
    """Two pairs 5e-4 apart (as in test_close_pairs) beside double roots on the seam (exact
    product, rounded once): the pairs stay two roots each, each seam root is one. (Left out:
    a seam double root 0.04 from such pairs, e.g. (1 - tau)^2 with t0 = 1.04. Both are then so
    ill-conditioned that rounding alone splits the double root by more than DR_PAIR.)"""
    factors, seam = SEAM_FACTORS[name]
    taus = [t0, t0 + 5e-4, t0 + 3e-3, t0 + 3.5e-3]
    c = [Fraction(x) for x in _expand(factors)[:len(factors) * len(factors[0]) - 1]]
    for f in [[-Fraction(t), 1] for t in taus] + [[Fraction(3, 5), -1, 1], [5, 4, 1]]:
        c = [sum(c[i - j] * f[j] for j in range(len(f)) if 0 <= i - j < len(c))
             for i in range(len(c) + len(f) - 1)]
    sigma = [float(100000 * x) for x in c] + [0.0] * (13 - len(c))
    got = roots_of(clib, sigma)
    assert_seam_roots(got, sigma, seam)
    # the exact product's roots: the rounding moves these ill-conditioned pairs by up to 5e-5
    expected = [2 * math.atan(t) for t in taus] + seam + ([math.pi] if sigma[12] == 0 else [])
    assert_roots(got, expected, tol=1e-4)


def test_wide_coefficient_magnitudes(clib):
    rng = random.Random(7)
    for _ in range(15):
        sigma = [rng.choice([-1, 1]) * 10 ** rng.uniform(-6, 8) for _ in range(13)]
        assert_roots(roots_of(clib, sigma), reference(sigma))


def test_roots_at_wide_scales(clib):
    """Roots from tau = 1e-3 to 1e3 give coefficients over ~1e-6 .. 1e8."""
    taus = [1e-3, -2e-3, 3e-3, 0.05, -0.3, 1.0, 7.0, -40.0, 1e3, -2e3]
    with mpmath.workdps(50):
        c = [mpmath.mpf(0.15)]                                  # high to low
        for t in taus:
            c = [a - t * b for a, b in zip(c + [0], [0] + c)]
        c = [a + b * mpmath.mpf("0.4") + d * mpmath.mpf("0.0401")   # * (tau^2 + 0.4 tau + 0.0401)
             for a, b, d in zip(c + [0, 0], [0] + c + [0], [0, 0] + c)]
        sigma = [float(x) for x in reversed(c)]
    mags = [abs(x) for x in sigma]
    assert max(mags) > 1e7 and min(mags) < 1e-3
    got = roots_of(clib, sigma)
    assert_roots(got, reference(sigma))
    assert_roots(got, [2 * math.atan(t) for t in taus], tol=1e-9)


# ---------------------------------------------------------------- errors

SENTINEL = [-7.25] * 12


def _call_raw(clib, sigma):
    ffi, lib = clib
    s = ffi.new("double[13]", sigma)
    th = ffi.new("double[12]", SENTINEL)
    n = ffi.new("int *", -3)
    return lib.doughty_poly_real_roots(s, th, n), list(th), n[0]


def test_zero_polynomial(clib):
    status, th, n = _call_raw(clib, [0.0] * 12 + [-0.0])
    assert status == ERR_ZERO and th == SENTINEL and n == -3


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("where", [0, 5, 12])
def test_nonfinite(clib, bad, where):
    sigma = [1.0] * 13
    sigma[where] = bad
    status, th, n = _call_raw(clib, sigma)
    assert status == ERR_NONFINITE and th == SENTINEL and n == -3


def test_null_pointers(clib):
    ffi, lib = clib
    s = ffi.new("double[13]", [1.0] * 13)
    th = ffi.new("double[12]", SENTINEL)
    n = ffi.new("int *", -3)
    assert lib.doughty_poly_real_roots(ffi.NULL, th, n) == ERR_NULL
    assert lib.doughty_poly_real_roots(s, ffi.NULL, n) == ERR_NULL
    assert lib.doughty_poly_real_roots(s, th, ffi.NULL) == ERR_NULL
    assert list(th) == SENTINEL and n[0] == -3


# ---------------------------------------------------------------- properties

def _separated(thetas, gap):
    t = sorted(thetas)
    return all(b - a >= gap for a, b in zip(t, t[1:])) and \
        (len(t) < 2 or t[0] + 2 * math.pi - t[-1] >= gap)


real_roots = st.lists(st.floats(-math.pi, math.pi), max_size=12)
complex_pairs = st.lists(st.tuples(st.floats(-3, 3), st.floats(0.1, 3)), max_size=6)
scales = st.floats(-3, 3).map(lambda e: 10.0 ** e)


def _with_infinity(thetas, pairs):
    """The prescribed roots, plus theta = pi when the degree is below 12 (sigma_12 = 0)."""
    return list(thetas) + ([math.pi] if len(thetas) + 2 * len(pairs) < 12 else [])


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(real_roots, complex_pairs, scales)
def test_matches_mpmath_reference(clib, thetas, pairs, scale):
    expected = _with_infinity(thetas, pairs)
    assume(len(thetas) + 2 * len(pairs) <= 12 and _separated(expected, 1e-3))
    sigma = poly_from_theta(thetas, pairs, scale)
    got = roots_of(clib, sigma)
    assert_roots(got, reference(sigma))
    assert_roots(got, expected, tol=1e-6)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(real_roots, complex_pairs, st.integers(-600, 600), st.sampled_from([1e100, 1e-100]))
def test_scale_invariance(clib, thetas, pairs, k, decimal):
    assume(len(thetas) + 2 * len(pairs) <= 12)
    assume(_separated(_with_infinity(thetas, pairs), 1e-3))
    sigma = poly_from_theta(thetas, pairs)
    base = roots_of(clib, sigma)
    # powers of two scale exactly (barring overflow and subnormals): bit-identical results
    scaled = [math.ldexp(x, k) for x in sigma]
    assume(all(math.ldexp(y, -k) == x for x, y in zip(sigma, scaled)))
    assert roots_of(clib, scaled) == base
    # 1e+-100 rounds each coefficient once: same roots to rounding, or (an ill-conditioned root
    # that rounding really moves, e.g. tau = 0.93 beside a triple complex pair 1 +- 0.25i, by
    # 1.2e-9 rad) those of the rounded coefficients
    rounded = [x * decimal for x in sigma]
    got = roots_of(clib, rounded)
    try:
        assert_roots(got, base, tol=1e-9)
    except AssertionError:
        assert_roots(got, reference(rounded))


@settings(max_examples=300, deadline=None)
@given(st.lists(st.integers(-20, 20) | st.just(0), min_size=13, max_size=13))
def test_count_matches_sturm_for_integer_coefficients(clib, coeffs):
    assume(any(coeffs))
    sigma = [float(c) for c in coeffs]
    assert len(roots_of(clib, sigma)) == exact_count(sigma)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from([[1, -1], [1, 1], [0, 1], [-2, 1], [1, 2], [1, 0, 1], [-1, 0, 1],
                                 [2, -3, 1], [-2, 0, 1], [1, 1, 1], [-3, 1], [1, -3]]),
                min_size=1, max_size=8),
       st.booleans())
def test_count_matches_sturm_for_products_with_multiple_roots(clib, factors, reverse):
    """Exact integer products: repeated roots, roots on the chart seam tau = +-1, at 0, at pi."""
    c = [1]
    for f in factors:
        if len(c) + len(f) - 1 > 13:
            break
        c = [sum(c[i - j] * f[j] for j in range(len(f)) if 0 <= i - j < len(c))
             for i in range(len(c) + len(f) - 1)]
    sigma = [float(x) for x in c] + [0.0] * (13 - len(c))
    if reverse:
        sigma.reverse()
    assert len(roots_of(clib, sigma)) == exact_count(sigma)
