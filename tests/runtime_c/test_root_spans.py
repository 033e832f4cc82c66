"""codegen_poly_root_spans (runtime/codegen_roots.c) on its own: where the real roots
of every polynomial within bounds on its coefficients may lie. The polynomials are products of
chosen factors, real roots and complex pairs, multiplied out exactly (fractions), rounded to
double, each coefficient's bound its rounding error plus any extra a case adds: so the chosen
roots are the exact polynomial's, known without any root finder. Checked: every real root
lies in a span (the proof that none is missed), a simple span holds exactly one real root of
multiplicity one, the spans are sorted and disjoint on the circle, and a polynomial drawn
within the bounds keeps its real roots in the spans too (mpmath at 60 digits).
"""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from .conftest import RUNTIME
from .test_runtime_roots import RUNTIME_CDEF, RUNTIME_SRC, _build

CDEF = RUNTIME_CDEF.replace("CODEGEN_ROOTS_ERR_DEGREE = 4",
                            "CODEGEN_ROOTS_ERR_DEGREE = 4, CODEGEN_ROOTS_UNPROVEN = 5") + """
typedef struct codegen_root_span { double lo, hi; double theta; double free_lo, free_hi, reach_lo, reach_hi; int simple; } codegen_root_span;
codegen_roots_status codegen_poly_root_spans(const double *sigma, const double *bound, int degree,
                                             codegen_root_span *spans, int *n_spans,
                                             double *work);
codegen_roots_status codegen_poly_real_roots_work(const double *sigma, int degree, double *theta,
                                                  int *n_roots, double *work);
codegen_roots_status codegen_poly_real_roots_after_spans(const double *sigma, int degree,
                                                         double *theta, int *n_roots,
                                                         double *work);
"""
OK, UNPROVEN = 0, 5
TWO_PI = 2 * math.pi


@pytest.fixture(scope="module")
def spans_lib(tmp_path_factory):
    d = tmp_path_factory.mktemp("root_spans")
    return _build(d, "_root_spans_test", CDEF, '#include "codegen_runtime.h"', [RUNTIME_SRC],
                  [RUNTIME])


def exact_polynomial(real_roots, pairs, lead=Fraction(1), at_infinity=0):
    """Coefficients (lowest first, exact) of lead * prod (tau - r) * prod (tau^2 - 2 a tau +
    a^2 + b^2), with at_infinity zero coefficients on top (roots at tau = infinity)."""
    coeffs = [Fraction(lead)]
    factors = [[-Fraction(r), Fraction(1)] for r in real_roots]
    factors += [[Fraction(a) ** 2 + Fraction(b) ** 2, -2 * Fraction(a), Fraction(1)]
                for a, b in pairs]
    for f in factors:
        out = [Fraction(0)] * (len(coeffs) + len(f) - 1)
        for i, c in enumerate(coeffs):
            for j, g in enumerate(f):
                out[i + j] += c * g
        coeffs = out
    return coeffs + [Fraction(0)] * at_infinity


def rounded(coeffs, extra=0.0):
    """The doubles nearest the exact coefficients, and a bound on each one's error (its
    rounding error rounded up, plus extra times the largest coefficient)."""
    sigma = [float(c) for c in coeffs]
    size = max(abs(s) for s in sigma)
    bound = [float(abs(Fraction(s) - c)) * (1 + 2 ** -50) + extra * size
             for s, c in zip(sigma, coeffs)]
    return sigma, bound


def spans_of(spans_lib, sigma, bound):
    ffi, lib = spans_lib
    degree = len(sigma) - 1
    spans, n = ffi.new("codegen_root_span[]", degree), ffi.new("int *", -1)
    work = ffi.new("double[]", 16 * degree + 16)        # CODEGEN_SPANS_WORK(degree)
    status = lib.codegen_poly_root_spans(ffi.new("double[]", sigma), ffi.new("double[]", bound),
                                         degree, spans, n, work)
    return status, [(s.lo, s.hi, s.theta, s.simple) for s in spans[0:max(n[0], 0)]]


def covers(span, theta):
    lo, hi = span[0], span[1]
    return lo <= theta <= hi or lo <= theta + TWO_PI <= hi


def check(spans, real_thetas, multiplicity):
    """real_thetas: every real root's angle; multiplicity: of each."""
    for a, b in zip(spans, spans[1:]):
        assert a[0] <= a[1] < b[0] <= b[1], spans
    if len(spans) > 1:
        assert spans[-1][1] < spans[0][0] + TWO_PI, spans
    for s in spans:
        assert -math.pi - 1e-9 < s[0] <= math.pi and s[0] <= s[2] <= s[1], s
    for theta in real_thetas:
        assert any(covers(s, theta) for s in spans), (theta, spans)
    for s in spans:
        if s[3]:
            inside = [i for i, t in enumerate(real_thetas) if covers(s, t)]
            assert len(inside) == 1 and multiplicity[inside[0]] == 1, (s, real_thetas)


def theta_of(tau):
    return math.pi if tau == math.inf else 2 * math.atan(tau)


def test_well_separated_roots_are_simple_spans(spans_lib):
    roots = [-3.0, -0.5, 0.25, 2.0, 40.0]
    sigma, bound = rounded(exact_polynomial(roots, [(0.3, 1.1), (-2.0, 0.5)]))
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == OK
    assert len(spans) == 5 and all(s[3] for s in spans)
    check(spans, [theta_of(r) for r in roots], [1] * 5)
    for s, r in zip(spans, sorted(roots, key=theta_of)):
        assert abs(s[2] - theta_of(r)) <= 1e-12 and s[1] - s[0] <= 1e-10


def test_a_root_at_infinity_is_pi(spans_lib):
    # the leading coefficient exactly zero (and so its bound): a root at theta = pi
    sigma, bound = rounded(exact_polynomial([0.5, -1.5], [(0.0, 2.0)], at_infinity=1))
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == OK
    check(spans, [theta_of(0.5), theta_of(-1.5), math.pi], [1, 1, 1])
    at_pi = [s for s in spans if covers(s, math.pi)]
    assert len(at_pi) == 1 and at_pi[0][3] and at_pi[0][0] < math.pi < at_pi[0][1]


def test_a_root_at_infinity_beside_a_double_root_near_pi_is_kept(spans_lib):
    # hypothesis found it: Aberth left the exact root at u = 1/tau = 0 a hair off the real
    # axis, and its disc, a few ulps wide, never reached it
    real = [-48.0, 1.0, 11.0, -48.0]
    sigma, bound = rounded(exact_polynomial(real, [], at_infinity=1))
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == OK
    thetas = [theta_of(r) for r in real] + [math.pi]
    check(spans, thetas, [thetas.count(t) for t in thetas])
    # two exact roots there: never a simple span at pi, if proven at all
    sigma, bound = rounded(exact_polynomial([0.5, -1.5], [], at_infinity=2))
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == UNPROVEN or (check(spans, [theta_of(0.5), theta_of(-1.5), math.pi,
                                                math.pi], [1, 1, 2, 2]) is None)


def test_a_double_root_is_covered_and_never_simple(spans_lib):
    sigma, bound = rounded(exact_polynomial([0.7, 0.7, -0.2], [(1.0, 1.0)]))
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == OK
    check(spans, [theta_of(0.7), theta_of(-0.2)], [2, 1])


def test_a_complex_pair_near_the_axis_is_not_taken_for_a_real_root(spans_lib):
    # the pair 0.4 +- 1e-9 i, and a bound that makes the discs reach the axis
    sigma, bound = rounded(exact_polynomial([-1.0], [(0.4, 1e-9)]), extra=1e-15)
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == OK
    check(spans, [theta_of(-1.0)], [1])
    near = [s for s in spans if covers(s, theta_of(0.4))]
    assert not near or not near[0][3]


def test_a_bound_too_wide_for_the_leading_coefficients_is_unproven(spans_lib):
    sigma, bound = rounded(exact_polynomial([0.5, 2.0], []))
    bound[0] = bound[-1] = 10.0
    assert spans_of(spans_lib, sigma, bound)[0] == UNPROVEN
    assert spans_of(spans_lib, [1.0, math.nan, 1.0], [0.0] * 3)[0] == UNPROVEN
    assert spans_of(spans_lib, [0.0, 0.0, 0.0], [0.0] * 3)[0] == UNPROVEN


def _perturbed_real_roots(sigma, bound, rng):
    """The real roots (angles) of one polynomial drawn within the bounds, at 60 digits."""
    with mpmath.workdps(60):
        c = [mpmath.mpf(s) + mpmath.mpf(b) * mpmath.mpf(rng.uniform(-1, 1))
             for s, b in zip(sigma, bound)]
        while len(c) > 1 and c[-1] == 0:
            c.pop()
        if len(c) < 2:
            return []
        roots = mpmath.polyroots(c[::-1], maxsteps=400, extraprec=400)
        return [float(2 * mpmath.atan(r.real if isinstance(r, mpmath.mpc) else r))
                for r in roots
                if abs(mpmath.im(r)) <= mpmath.mpf(10) ** -40 * max(1, abs(r))]


def test_a_cluster_near_plus_minus_i_leaves_every_real_root_simple(spans_lib):
    """The slider-crank's sigma at its example, rebuilt from its roots (mpmath): ten real ones
    from 0.0099 to 37.8 and seven complex pairs, four of them within 0.08 of +-i, where the
    outermost Fourier terms are small. Every real root is proven in a span of its own."""
    real = [-23.2305, -1.30022, -0.0580039, -0.0536696, 0.00988584, 0.0733879, 1.68822,
            20.9523, 36.1523, 37.7904]
    pairs = [(-0.0575669, 1.05314), (-0.0289763, 1.02862), (0.0264245, 0.972169),
             (0.043034, 0.950091), (-0.00785973, 0.496104), (0.0196355, 0.620778),
             (0.0259984, 0.371988)]
    sigma, bound = rounded(exact_polynomial(real, pairs))
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status == OK
    thetas = [theta_of(r) for r in real]
    check(spans, thetas, [1] * len(thetas))
    assert len(spans) == len(real) and all(s[3] for s in spans)


@settings(max_examples=40, deadline=None)
@given(real=st.lists(st.floats(-50, 50, allow_nan=False).filter(lambda x: abs(x) > 1e-3),
                     min_size=0, max_size=8),
       near_i=st.lists(st.tuples(st.floats(-0.1, 0.1), st.floats(0.9, 1.1)), min_size=1,
                       max_size=5),
       extra=st.sampled_from([0.0, 1e-15]))
def test_every_real_root_is_in_a_span_beside_clusters_near_plus_minus_i(
        spans_lib, real, near_i, extra):
    """Complex pairs clustered around +-i (where aberth_start takes its starts from the
    polynomial in e^(i theta)) beside real roots: none of the real ones is missed."""
    sigma, bound = rounded(exact_polynomial(real, near_i), extra)
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status in (OK, UNPROVEN)
    if status == OK:
        thetas = [theta_of(r) for r in real]
        check(spans, thetas, [thetas.count(t) for t in thetas])


@settings(max_examples=60, deadline=None)
@given(real=st.lists(st.floats(-50, 50, allow_nan=False).filter(lambda x: abs(x) > 1e-3),
                     min_size=0, max_size=8),
       pairs=st.lists(st.tuples(st.floats(-5, 5), st.floats(1e-6, 5)), max_size=3),
       doubled=st.booleans(), extra=st.sampled_from([0.0, 1e-15, 1e-12]),
       infinite=st.integers(0, 1), seed=st.integers(0, 2**32 - 1))
def test_every_real_root_of_every_polynomial_within_the_bounds_is_in_a_span(
        spans_lib, real, pairs, doubled, extra, infinite, seed):
    real = real + real[:1] if doubled else real
    coeffs = exact_polynomial(real, pairs, at_infinity=infinite)
    if len(coeffs) < 2:
        return
    sigma, bound = rounded(coeffs, extra)
    status, spans = spans_of(spans_lib, sigma, bound)
    assert status in (OK, UNPROVEN)
    if status != OK:
        return
    thetas = [theta_of(r) for r in real] + [math.pi] * infinite
    check(spans, thetas, [thetas.count(t) for t in thetas])
    rng = np.random.default_rng(seed)
    for theta in _perturbed_real_roots(sigma, bound, rng):
        assert any(covers(s, theta) or covers(s, theta + 1e-12) or covers(s, theta - 1e-12)
                   for s in spans), (theta, spans)


@settings(max_examples=60, deadline=None)
@given(real=st.lists(st.floats(-50, 50, allow_nan=False).filter(lambda x: abs(x) > 1e-3),
                     min_size=0, max_size=8),
       pairs=st.lists(st.tuples(st.floats(-5, 5), st.floats(1e-6, 5)), max_size=3),
       doubled=st.booleans(), infinite=st.integers(0, 1), zero=st.booleans())
def test_real_roots_after_the_spans_are_those_found_afresh_bit_for_bit(
        spans_lib, real, pairs, doubled, infinite, zero):
    """The finder that reuses the spans' iteration (where its polynomial is theirs) and the
    one that runs its own give the same roots, bit for bit: a vanishing end coefficient
    (a root at 0 or at infinity) and clusters included."""
    ffi, lib = spans_lib
    real = real + real[:1] if doubled else real
    coeffs = exact_polynomial(real + [0] * zero, pairs, at_infinity=infinite)
    if len(coeffs) < 2:
        return
    sigma, bound = rounded(coeffs, 1e-15)
    degree = len(sigma) - 1
    c_sigma = ffi.new("double[]", sigma)
    found = []
    for after_spans in (False, True):
        work = ffi.new("double[]", 16 * degree + 16)
        if after_spans:
            spans, n = ffi.new("codegen_root_span[]", degree), ffi.new("int *")
            if lib.codegen_poly_root_spans(c_sigma, ffi.new("double[]", bound), degree, spans,
                                           n, work) != OK:
                return
        theta, count = ffi.new("double[]", degree), ffi.new("int *", -1)
        run = (lib.codegen_poly_real_roots_after_spans if after_spans
               else lib.codegen_poly_real_roots_work)
        status = run(c_sigma, degree, theta, count, work)
        found.append((status, [float(t).hex() for t in theta[0:max(count[0], 0)]]))
    assert found[0] == found[1]
