"""The equilibria that `analyze` reports, against an independent scan of (43).

The analysis finds its roots as real roots of the squared polynomial (45) and labels each
genuine or extraneous. Here the same roots are found without the polynomial: G(theta) of (43),
typed in from the paper (not the generated code), is scanned over the whole circle and every
sign change is refined with brentq. The roots that squaring adds are the roots of the twin
function with l_ND -> -l_ND (see `branch`), scanned the same way. Then:

* for Table 2 and for random parameter sets (hypothesis), the genuine roots of `analyze`
  are exactly the roots of G, and its extraneous roots exactly those of the twin;
* residuals: genuine roots zero (43) to rounding, extraneous ones clearly do not;
* the linearisation (46)-(55) at the stable equilibria of Table 2 predicts the decay and
  oscillation of the nonlinear reduced equation (36), integrated numerically.

Known bugs are pinned by strict xfails (they turn into failures once fixed: drop the marker).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, reject, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from codegen.api import load

api = load("doughty")
from codegen.runtime.analysis import analyze

GRID = 20000           # scan points on the circle (spacing 3.1e-4 rad)
MIN_SEPARATION = 1e-6  # rad; closer root pairs are ill-posed for a scan and are filtered out
CLOSE_PAIR = 1e-4      # rad; (45) does not resolve pairs closer than ~3e-5 rad (DR_PAIR)


# --------------------------------------------------------------------------------------------
# The independent scan
# --------------------------------------------------------------------------------------------

def branch(p, theta, sign=+1):
    """G(theta) of (43) for sign=+1, or its squaring twin for sign=-1; and its term size.

    With alpha = -k l_ND P sin, beta = k P sin + e4 cos and P = H a + (L^2 - 2 L a) cos,
    r G = alpha + beta r, and (45) is (1 + tau^2)^6 (beta r + alpha)(beta r - alpha) = 0: its
    real roots are the roots of G and of (beta r - alpha)/r, which is G with l_ND -> -l_ND.
    Works for complex theta (used for complex-step derivatives); the size is then meaningless.
    """
    s, c = np.sin(theta), np.cos(theta)
    r = np.sqrt(((p.L - p.a) * s) ** 2 + (p.H - p.a * c) ** 2)
    P = p.H * p.a + (p.L ** 2 - 2 * p.L * p.a) * c
    e4 = (-p.F + (p.m_B + p.m_C / 2) * p.g) * p.L
    spring = p.k * P * s / r
    value = spring * (r - sign * p.l_ND) + e4 * c
    size = np.abs(spring * r) + np.abs(spring * p.l_ND) + np.abs(e4 * c)
    return value, size


def circular_distance(a, b):
    d = np.abs(np.asarray(a) - np.asarray(b)) % (2 * np.pi)
    return np.minimum(d, 2 * np.pi - d)


def wrap(theta):
    """Into (-pi, pi]."""
    theta = np.asarray(theta, dtype=float)
    theta = np.where(theta > np.pi, theta - 2 * np.pi, theta)
    return np.where(theta <= -np.pi, theta + 2 * np.pi, theta)


@dataclass
class Scan:
    roots: np.ndarray       # roots in (-pi, pi], ascending
    scale: float            # max over the circle of the term size: the size of G
    tangency: float         # min |G| / scale over the critical points of G (inf if none)


def slope(p, theta, sign=+1):
    """dG/dtheta by complex step (exact to rounding)."""
    return branch(p, theta + 1e-30j, sign)[0].imag / 1e-30


def _samples(df, lo, hi, n):
    """n + 1 points on [lo, hi] plus the critical points (sign changes of df) between them."""
    theta = np.linspace(lo, hi, n + 1)
    slopes = df(theta)
    crit = [brentq(df, theta[i], theta[i + 1], xtol=1e-15)
            for i in np.flatnonzero(slopes[:-1] * slopes[1:] < 0)]
    return theta, np.array(crit)


def scan(p, sign=+1, n=GRID) -> Scan:
    """Roots of branch(p, ., sign) on the circle.

    The grid is offset by half a step, so that 0 and +-pi (frequent roots) are never grid
    points, and its last point is its first plus 2 pi, so that a root at +-pi is bracketed
    like any other. A grid can step over a close pair of roots; to be fair to the analysis the
    scan is adaptive: it adds the critical points of G (sign changes of dG/dtheta, by complex
    step, refined with brentq), which splits any pair with one extremum between its roots, and
    it resamples (1000 points plus critical points) every interval where |G| at both ends is
    within reach of the slope there, which resolves clusters of three or more (they occur
    where the spring nearly collapses). Bracketed "roots" where |G| is not small are jumps of
    G where r = 0 (G is bounded there, no poles: P sin / r stays finite) and are dropped.
    """
    def f(t):
        return branch(p, t, sign)[0]

    def df(t):
        return slope(p, t, sign)

    with np.errstate(invalid="ignore", divide="ignore"):
        h = 2 * np.pi / n
        theta, crit = _samples(df, -np.pi + 0.5 * h, np.pi + 0.5 * h, n)
        scale = float(np.nanmax(branch(p, theta, sign)[1]))
        points = np.sort(np.concatenate([theta, crit]))
        values, slopes = f(points), np.abs(df(points))
        reach = np.diff(points) * np.maximum(slopes[:-1], slopes[1:])
        near = np.minimum(np.abs(values[:-1]), np.abs(values[1:])) <= 2 * reach
        extra = [_samples(df, points[i], points[i + 1], 1000) for i in np.flatnonzero(near)]
        if extra:
            crit = np.concatenate([crit] + [c for _, c in extra])
            points = np.unique(np.concatenate([points] + [t for t, c in extra] + [crit]))
        values = f(points)
        found = list(points[values == 0])
        for i in np.flatnonzero(values[:-1] * values[1:] < 0):
            root = brentq(f, points[i], points[i + 1], xtol=1e-15)
            if abs(f(root)) <= 1e-9 * scale:
                found.append(root)
        tangency = min((abs(f(c)) / scale for c in crit), default=math.inf)
    roots = np.sort(wrap(np.array(found, dtype=float)))
    if len(roots) > 1 and circular_distance(roots[0], roots[-1]) < 1e-13:
        roots = roots[1:]   # the same root seen from both ends of the grid
    return Scan(roots, scale, tangency)


def closest_pair(angles) -> float:
    angles = np.sort(np.asarray(angles, dtype=float))
    if len(angles) < 2:
        return math.inf
    gaps = np.diff(np.concatenate([angles, angles[:1] + 2 * np.pi]))
    return float(np.min(gaps))


def assert_same_angles(found, expected, tol, what):
    found, expected = np.asarray(found, dtype=float), np.asarray(expected, dtype=float)
    assert len(found) == len(expected), (
        f"{what}: analysis {np.degrees(found)} deg, scan {np.degrees(expected)} deg")
    for t in found:
        d = float(np.min(circular_distance(t, expected)))
        assert d <= tol, (f"{what}: analysis root {math.degrees(t):.9f} deg has no scan root "
                          f"within {tol:g} rad (nearest {d:.2e}); scan {np.degrees(expected)}")


def spring_length(p, theta) -> float:
    """r of (34)."""
    return math.hypot((p.L - p.a) * math.sin(theta), p.H - p.a * math.cos(theta))


def min_spring_length(p) -> float:
    """min over theta of r (34): r^2 is a quadratic A c^2 + B c + C in c = cos(theta)."""
    A = p.a ** 2 - (p.L - p.a) ** 2
    B = -2 * p.a * p.H
    C = (p.L - p.a) ** 2 + p.H ** 2
    candidates = [A + B + C, A - B + C]
    if A > 0 and abs(B / (2 * A)) <= 1:
        candidates.append(C - B * B / (4 * A))
    return math.sqrt(max(0.0, min(candidates)))


def certified_real_roots(sigma) -> int:
    """The number of real roots of (45) with exactly these (double) coefficients, certified:
    mpmath locates them, then exact rational evaluation shows a sign change of the polynomial
    between consecutive midpoints (one simple root in each interval)."""
    assert sigma[-1] != 0   # no root at tau = infinity to account for
    roots = mpmath.polyroots([mpmath.mpf(c) for c in reversed(sigma)], maxsteps=500,
                             extraprec=1000)
    real = sorted(float(z.real) for z in roots if abs(z.imag) <= 1e-30 * max(1, abs(z)))
    cuts = [real[0] - 1] + [(a + b) / 2 for a, b in zip(real, real[1:])] + [real[-1] + 1]

    def p(x):
        x = Fraction(x)
        return sum(Fraction(c) * x ** i for i, c in enumerate(sigma))

    values = [p(x) for x in cuts]
    assert all(a * b < 0 for a, b in zip(values, values[1:])), "not certified"
    return len(real)


def check_against_scan(p, result, genuine_scan, twin_scan):
    """The assertions shared by Table 2 and the random parameter sets."""
    genuine = [r for r in result.roots if r.genuine]
    extraneous = [r for r in result.roots if not r.genuine]
    for r in result.roots:
        assert -np.pi < r.theta <= np.pi
    # Genuine roots are polished on (43): they must sit on the scan's roots to ~1e-9 rad.
    assert_same_angles([r.theta for r in genuine], genuine_scan.roots, 1e-9, "genuine roots")
    # Extraneous roots come unpolished from (45); 1e-7 rad still separates every pair kept.
    # Two known limits of (45), left out of the comparison:
    # * where the spring nearly collapses (r < 1e-3 L, only when a ~ L or H ~ +-a), both r and
    #   P (so alpha) nearly vanish, (45) = beta^2 r^2 - alpha^2 is tiny, and a complex pair
    #   passing near the real axis may be reported as a (double) real root: an extra
    #   extraneous root, harmless to the equilibria;
    # * pairs of roots closer than CLOSE_PAIR are reported as one root by design (DR_PAIR in
    #   doughty_roots.c), losing the extraneous partner of a genuine root
    #   (test_close_pairs_keep_their_equilibria); the reported ones must still be real, and
    #   the missing ones must have a close partner.
    def regular(angles):
        return [t for t in angles if spring_length(p, t) >= 1e-3 * p.L]

    extraneous_angles = regular([r.theta for r in extraneous])
    twin_roots = np.array(regular(twin_scan.roots))
    if closest_pair(np.concatenate([genuine_scan.roots, twin_scan.roots])) >= CLOSE_PAIR:
        assert_same_angles(extraneous_angles, twin_roots, 1e-7, "extraneous roots")
    else:
        for t in extraneous_angles:
            assert float(np.min(circular_distance(t, twin_roots))) <= 1e-7, t
        reported = np.array([r.theta for r in result.roots])
        for t in twin_roots:
            assert float(np.min(circular_distance(t, reported))) <= CLOSE_PAIR, t

    scale = genuine_scan.scale
    for r in genuine:
        # Zero to rounding: of the terms, and of theta itself where G is steep.
        rounding = 1e-12 * scale + 16 * np.finfo(float).eps * max(abs(r.theta), 1.0) * abs(
            slope(p, r.theta))
        assert abs(branch(p, r.theta)[0]) <= rounding, r
        assert abs(r.residual) <= rounding, r
        assert r.relative_residual <= 1e-12, r
    for r in extraneous:
        # Clearly not an equilibrium: G is far above its rounding level (~1e-16 scale).
        assert abs(branch(p, r.theta)[0]) >= 1e-10 * scale, r
        assert abs(r.residual) >= 1e-10 * scale, r
        assert r.relative_residual >= 1e-9, r


# --------------------------------------------------------------------------------------------
# Table 2
# --------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def table2():
    p = api.example_params()
    return p, analyze(p), scan(p, +1), scan(p, -1)


def test_compiled_residual_is_the_papers_equation_43(table2):
    """The scan is only independent if G is typed from the paper: it must match the library."""
    p, _, genuine_scan, _ = table2
    theta = np.linspace(-np.pi, np.pi, 4001)[1:]
    compiled = api.equilibrium_residual(p, theta).residual
    assert np.max(np.abs(compiled - branch(p, theta)[0])) <= 1e-12 * genuine_scan.scale


def test_table2_genuine_and_extraneous_roots_match_the_scan(table2):
    p, result, genuine_scan, twin_scan = table2
    assert len(genuine_scan.roots) == 6 and len(twin_scan.roots) == 4
    assert closest_pair(np.concatenate([genuine_scan.roots, twin_scan.roots])) > 4e-4
    check_against_scan(p, result, genuine_scan, twin_scan)


def test_scan_finds_close_pairs_between_grid_points():
    """The critical-point refinement is what makes the scan fair: the four roots near +-92.4
    deg come in two pairs 0.027 deg apart; with a coarse grid (0.5 deg) only the critical
    points can split them."""
    p = api.example_params()
    fine = scan(p, +1).roots
    coarse = scan(p, +1, n=720).roots
    assert len(coarse) == len(fine) == 6
    assert np.max(circular_distance(coarse, fine)) < 1e-12
    both = np.sort(np.concatenate([scan(p, +1, n=720).roots, scan(p, -1, n=720).roots]))
    assert len(both) == 10


def test_table2_with_balanced_force_has_a_genuine_equilibrium_at_180_deg():
    """F = (m_B + m_C/2) g: e4 = 0, so sin(theta) factors out of (43) and theta_E = pi."""
    base = api.example_params()
    p = api.example_params(F=(base.m_B + base.m_C / 2) * base.g)
    result = analyze(p)
    at_pi = [r for r in result.roots if circular_distance(r.theta, np.pi) <= 1e-9]
    assert at_pi and all(r.genuine for r in at_pi)
    assert any(r.theta == np.pi for r in at_pi)   # reported as +pi, not -pi


# --------------------------------------------------------------------------------------------
# Random parameter sets
# --------------------------------------------------------------------------------------------

@st.composite
def parameter_sets(draw):
    L = draw(st.floats(0.1, 3.0))
    values = dict(
        H=draw(st.floats(-2.0, 2.0)), L=L, a=draw(st.floats(0.0, 1.0)) * L,
        m_A=draw(st.floats(0.01, 20.0)), m_B=draw(st.floats(0.01, 20.0)),
        m_C=draw(st.floats(0.01, 20.0)), k=draw(st.floats(1.0, 1e5)),
        b=draw(st.floats(0.0, 1e4)), l_ND=draw(st.floats(0.0, 2.0)),
        F=draw(st.floats(-300.0, 300.0)), g=draw(st.floats(0.0, 20.0)))
    return api.example_params(**values)


def natural_size(p) -> float:
    """The size G's terms have unless the mechanism is degenerate: k L^2 and the loads."""
    return p.k * p.L ** 2 + abs(p.F) * p.L + (p.m_B + p.m_C) * p.g * p.L


def analyze_or_reject(p):
    """analyze(p), where it may fail: only where r = 0 at a root (documented in doughty.h),
    or where G vanishes identically (e.g. H = 0, a = L/2: r = L/2 for every theta, P = 0;
    with e4 = 0 every angle is an equilibrium and (45) is the zero polynomial). Such sets are
    rejected; any other failure fails the test."""
    try:
        return analyze(p)
    except api.LibraryError as error:
        if error.code == "ERR_EVERY_ANGLE":
            assert scan(p, +1).scale <= 1e-12 * natural_size(p), (error, p)
        else:
            assert error.code == "ERR_SINGULAR_STATE", error
            assert min_spring_length(p) < 1e-6 * p.L, (error, p)
        reject()


@st.composite
def near_table2(draw):
    """Table 2 perturbed by up to 3 % per parameter: keeps its two close pairs near +-92 deg;
    F within a relative 1e-3 of (m_B + m_C/2) g brings sigma_12 near zero (a root near 180)."""
    base = api.example_params()
    values = {n: getattr(base, n) * (1 + draw(st.floats(-0.03, 0.03)))
              for n in api.PARAMETER_NAMES}
    if draw(st.booleans()):
        balance = (values["m_B"] + values["m_C"] / 2) * values["g"]
        values["F"] = balance * (1 + draw(st.sampled_from([-1, 1])) * 10 ** draw(st.floats(-9, -3)))
    return api.example_params(**values)


@pytest.mark.slow   # 1,500 sets, ~100 s: make test-all (CI)
@settings(max_examples=1500, deadline=None,
          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(st.one_of(parameter_sets(), near_table2()))
def test_random_parameter_sets_match_the_scan(p):
    # r = 0 somewhere makes G jump (not a pole); r nearly 0 makes it change over an angle of
    # ~r_min/L, with clusters of roots there (test_nearly_collapsed_spring): kept out.
    assume(min_spring_length(p) > 1e-4 * p.L)
    result = analyze_or_reject(p)
    genuine_scan, twin_scan = scan(p, +1), scan(p, -1)
    # Fairness filter: a root pair closer than 1e-6 rad (including the exact coincidences of
    # l_ND = 0 or e4 = 0, where a genuine and an extraneous root merge into a double root of
    # (45)), or a tangency of G (a double root of (43)), is not a question a scan can settle.
    assume(closest_pair(np.concatenate([genuine_scan.roots, twin_scan.roots]))
           >= MIN_SEPARATION)
    assume(min(genuine_scan.tangency, twin_scan.tangency) > 1e-10)
    # Near-neutral mechanisms (e.g. H ~ 0, a = L/2, e4 ~ 0: r ~ L/2 for every theta), where
    # all of G is tiny next to k L^2: (45), computed in expanded form, then holds rounding
    # only (H = F = 1e-20 with a = L/2 gives no roots where tan(theta) = -2 has two).
    assume(genuine_scan.scale >= 1e-6 * natural_size(p))
    check_against_scan(p, result, genuine_scan, twin_scan)


def balanced_sets(count, seed=20240611):
    """Random sets (the hypothesis box, k log-uniform) with F = (m_B + m_C/2) g, so e4 = 0:
    sin(theta) factors out of (43), theta = 0 and pi are equilibria, and so is P = 0; each
    is a root of both branches (a double root of (45)). Seeded numpy rather than hypothesis:
    the same 200 sets every run, counted per failure kind."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        L = rng.uniform(0.1, 3.0)
        m_B, m_C, g = rng.uniform(0.01, 20.0), rng.uniform(0.01, 20.0), rng.uniform(0.0, 20.0)
        p = api.example_params(
            H=rng.uniform(-2.0, 2.0), L=L, a=rng.uniform(0.0, L), m_A=rng.uniform(0.01, 20.0),
            m_B=m_B, m_C=m_C, k=10 ** rng.uniform(0.0, 5.0), b=rng.uniform(0.0, 1e4),
            l_ND=rng.uniform(0.0, 2.0), F=(m_B + m_C / 2) * g, g=g)
        if min_spring_length(p) > 1e-6 * p.L:
            yield p


def test_balanced_force_reports_every_equilibrium_including_180_deg():
    failures = {"pi not genuine": [], "0 not genuine": [], "genuine set differs": []}
    for p in balanced_sets(200):
        genuine = np.array([r.theta for r in analyze(p).roots if r.genuine])
        if not np.any(circular_distance(genuine, np.pi) <= 1e-9):
            failures["pi not genuine"].append(p)
        if not np.any(np.abs(genuine) <= 1e-9):
            failures["0 not genuine"].append(p)
        try:
            assert_same_angles(genuine, scan(p, +1).roots, 1e-9, "genuine roots")
        except AssertionError:
            failures["genuine set differs"].append(p)
    assert not any(failures.values()), {k: (len(v), v[:1]) for k, v in failures.items()}


def test_balanced_force_reports_180_deg_as_plus_pi():
    """Regression: the build of 03:15 reported theta_E = pi as -pi + 4.4e-16 (-180.0000 in the
    table) in 38 of these 200 sets."""
    negative = [p for p in balanced_sets(200)
                if any(circular_distance(r.theta, np.pi) <= 1e-9 and r.theta < 0
                       for r in analyze(p).roots)]
    assert not negative, (len(negative), negative[:1])


def test_balanced_force_minimal_case_all_equilibria_genuine():
    """Regression: equilibria at +-102.84 (P = 0), 0 and 180 deg, each a root of both branches;
    the build of 03:12 labelled all but 180 extraneous."""
    base = api.example_params()
    p = api.example_params(H=-0.04, a=0.5, F=(base.m_B + base.m_C / 2) * base.g)
    genuine_scan = scan(p, +1)
    assert len(genuine_scan.roots) == 4
    assert_same_angles([r.theta for r in analyze(p).equilibria], genuine_scan.roots, 1e-9,
                       "genuine roots")


@pytest.mark.parametrize("overrides", [
    pytest.param(dict(H=-0.04, L=0.16, a=0.09, m_B=14.6, m_C=10.5, k=650.0, l_ND=1.2, g=5.0),
                 id="pi-was-extraneous"),
    pytest.param(dict(H=-0.04, a=0.5, l_ND=0.5), id="minus-pi"),
])
def test_balanced_force_minimal_case_pi_is_genuine_and_positive(overrides):
    p = api.example_params(**overrides)
    p = api.example_params(**overrides, F=(p.m_B + p.m_C / 2) * p.g)
    at_pi = [r for r in analyze(p).roots if circular_distance(r.theta, np.pi) <= 1e-9]
    assert len(at_pi) == 1 and at_pi[0].genuine and at_pi[0].theta == np.pi, at_pi


def test_nearly_coincident_pairs_keep_their_equilibria():
    """Regression: l_ND = 1e-9 puts each extraneous root ~1e-9 rad from a genuine one; (45)
    reports each pair once. The build of 03:12 labelled 2 of the 4 equilibria (-92.387 and
    178.266 deg) extraneous."""
    p = api.example_params(l_ND=1e-9)
    genuine_scan = scan(p, +1)
    assert len(genuine_scan.roots) == 4
    assert_same_angles([r.theta for r in analyze(p).equilibria], genuine_scan.roots, 1e-9,
                       "genuine roots")


def test_extraneous_partners_beside_equilibria_are_kept():
    """Regression (set 30 of a sample within +-50 % of Table 2): an extraneous root 1.4e-7 rad
    from each equilibrium near +-92.19 deg, farther apart than rounding splits one root but
    closer than the root finder resolves. A search for a genuine twin of the reported root used
    to make it the equilibrium and lose its partner (8 roots reported); every one of sigma's
    certified real roots is reported now."""
    p = api.example_params(H=0.17943721837083076, L=1.1387905837489576, a=0.18578858160643913,
                           m_A=0.22156310061456413, m_B=0.09057232945011454,
                           m_C=10.212338786681782, k=4321.7512794163995, b=1266.0853068966742,
                           l_ND=0.19614311517829597, F=64.50523046866044, g=12.406959060712785)
    result = analyze(p)
    assert len(result.roots) == certified_real_roots(result.sigma) == 10
    check_against_scan(p, result, scan(p, +1), scan(p, -1))


@pytest.mark.parametrize("overrides", [
    # two pairs at +-57.6076 deg (P = 0), 1.4e-6 rad apart
    dict(H=1.0, L=2.0, a=1.875, m_A=1.0, m_B=1.0, m_C=1.0, k=16626.0, b=0.0, l_ND=2.0,
         F=1.0, g=1.0),
    # a pair at -0.00025 / +0.00024 deg, 8.6e-6 rad apart
    dict(H=0.875, L=1.125, a=0.84375, m_A=1.0, m_B=1.0, m_C=1.0, k=19335.0, b=0.0,
         l_ND=2.0, F=0.5, g=0.0),
], ids=["P=0-pairs", "zero-pair"])
def test_close_pairs_keep_their_equilibria(overrides):
    """A genuine and an extraneous root closer than the root finder resolves (DR_PAIR in
    doughty_roots.c, ~3e-5 rad) come back as one root. (45) with these very double
    coefficients does have both (certified_real_roots: 10 and 4 real roots, where analyze
    reports 8 and 3), so the extraneous partner is lost; what must hold is that the
    equilibria are all there, and that only such partners are missing."""
    p = api.example_params(**overrides)
    result = analyze(p)
    genuine_scan, twin_scan = scan(p, +1), scan(p, -1)
    assert certified_real_roots(result.sigma) == len(genuine_scan.roots) + len(twin_scan.roots)
    assert_same_angles([r.theta for r in result.equilibria], genuine_scan.roots, 1e-9,
                       "genuine roots")
    reported = np.array([r.theta for r in result.roots])
    for t in twin_scan.roots:
        assert float(np.min(circular_distance(t, reported))) <= CLOSE_PAIR


@pytest.mark.parametrize("overrides", [
    dict(H=0.0), dict(H=0.0, F=0.0), dict(H=0.0, l_ND=0.5), dict(H=0.0, a=0.6), dict(a=0.0)])
def test_roots_of_both_branches_are_genuine(overrides):
    """H = 0 or a = 0 makes P (so alpha) proportional to cos(theta): theta = +-90 deg zeroes
    both branches, a double root of (45), and is an equilibrium."""
    p = api.example_params(**overrides)
    result = analyze(p)
    genuine_scan, twin_scan = scan(p, +1), scan(p, -1)
    assert np.min(circular_distance(np.pi / 2, genuine_scan.roots)) < 1e-12
    assert np.min(circular_distance(np.pi / 2, twin_scan.roots)) < 1e-12
    assert_same_angles([r.theta for r in result.equilibria], genuine_scan.roots, 1e-9,
                       "genuine roots")
    assert_same_angles([r.theta for r in result.roots if not r.genuine],
                       [t for t in twin_scan.roots
                        if np.min(circular_distance(t, genuine_scan.roots)) > 1e-12],
                       1e-7, "extraneous roots")


def test_nearly_collapsed_spring():
    """H = 0 and a = L - 1e-5 (the spring nearly collapses at +-90 deg, r_min = 1e-5 m) with
    F = 51 N, g = 0: G has clusters of three roots 1.5e-4 rad apart at +-90 deg, roots of both
    branches, which the root finder reports merged; the search of the other branches around
    each reported root recovers the equilibria at exactly +-90 deg (once missed, with
    89.9914/90.0086 genuine and -90.0090/-89.9910 extraneous reported instead)."""
    p = api.example_params(H=0.0, L=1.0, a=0.99999, m_A=1.0, m_B=1.0, m_C=1.0, k=1.0, b=0.0,
                           l_ND=0.0078125, F=51.0, g=0.0)
    genuine_scan = scan(p, +1)
    assert len(genuine_scan.roots) == 4
    assert_same_angles([r.theta for r in analyze(p).equilibria], genuine_scan.roots, 1e-9,
                       "genuine roots")


def test_nearly_collapsed_spring_is_settled_by_isolation():
    """The case above, by the isolation route: G itself has no close genuine/extraneous pairs,
    and all four equilibria (two 1.5e-4 rad from +-90 deg, and +-90 deg itself) are proven."""
    p = api.example_params(H=0.0, L=1.0, a=0.99999, m_A=1.0, m_B=1.0, m_C=1.0, k=1.0, b=0.0,
                           l_ND=0.0078125, F=51.0, g=0.0)
    result = analyze(p, "isolate")
    assert all(r.certified for r in result.equilibria) and not result.uncertain
    assert_same_angles([r.theta for r in result.equilibria], scan(p, +1).roots, 1e-9,
                       "genuine roots")


def test_spring_without_free_length():
    """l_ND = 0: alpha = 0, the twin is G itself and every root of (45) is double and genuine
    (the random test filters this case out as a coincident pair). A residual measured against
    the branch values |genuine| + |extraneous| (both ~0 there) would be ~0.5."""
    p = api.example_params(l_ND=0.0)
    result = analyze(p)
    assert len(result.roots) == len(result.equilibria) == 4
    assert_same_angles([r.theta for r in result.roots], scan(p, +1).roots, 1e-9, "roots")
    assert all(abs(r.residual) < 1e-11 for r in result.equilibria)
    assert max(r.relative_residual for r in result.equilibria) <= 1e-12


# --------------------------------------------------------------------------------------------
# The linearisation against the nonlinear reduced equation (36)
# --------------------------------------------------------------------------------------------

def simulate(p, theta_e, t_end, x0=1e-6):
    """x = theta - theta_E from x(0) = x0, xdot(0) = 0 under (36), via the compiled thetaddot.

    x0 = 1e-6 rad keeps the nonlinear terms at ~1e-8 relative; the windows below stop while
    |x| is still >~ 1e-8 rad, since thetaddot near theta_E carries rounding noise of ~1e-14
    rad/s^2 (G cancels there) that an rtol of 1e-10 cannot integrate through cheaply.
    """
    def rhs(_t, y):
        return [y[1], api.angular_acceleration(p, theta_e + y[0], y[1])]

    sol = solve_ivp(rhs, (0.0, t_end), [x0, 0.0], method="DOP853", rtol=1e-10, atol=1e-22,
                    dense_output=True)
    assert sol.success, sol.message
    return sol.sol


def crossings(fun, t0, t1, n=20000):
    t = np.linspace(t0, t1, n)
    v = fun(t)
    return np.array([brentq(fun, t[i], t[i + 1], xtol=1e-14)
                     for i in np.flatnonzero(v[:-1] * v[1:] < 0)])


def stable_equilibria(result, damping):
    return [r for r in result.equilibria if r.stability == "stable" and r.damping == damping]


def test_table2_stable_equilibria():
    """The three genuine roots with K > 0; 178.8 deg (K > 0 too) is extraneous: not an
    equilibrium, so it has no stability at all."""
    result = analyze(api.example_params())
    stable = [r for r in result.roots if r.stability == "stable"]
    assert [r.genuine for r in stable] == [True, True, True]
    assert all(r.K > 0 and r.B > 0 for r in stable)
    extraneous = [r for r in result.roots if r.kind == "extraneous"]
    assert len(extraneous) == 4 and {(r.stability, r.damping) for r in extraneous} == {(None, None)}
    assert len(stable_equilibria(result, "overdamped")) == 2
    assert len(stable_equilibria(result, "underdamped")) == 1


@pytest.mark.parametrize("index", [0, 1])
def test_overdamped_decay_rate_is_the_slow_eigenvalue(index):
    p = api.example_params()
    eq = stable_equilibria(analyze(p), "overdamped")[index]
    assert all(z.imag == 0 for z in eq.eigenvalues)
    fast, slow = sorted(z.real for z in eq.eigenvalues)
    assert fast < 30 * slow < 0     # well separated (-167 or -174 vs -4): one mode remains
    x = simulate(p, eq.theta, 0.65)
    # After t = 0.15 s the fast mode is down by e^{(fast - slow) 0.15} < 1e-10.
    t0, t1 = 0.15, 0.65
    rate = (math.log(x(t1)[0]) - math.log(x(t0)[0])) / (t1 - t0)
    assert rate == pytest.approx(slow, rel=1e-6)      # measured: 3e-8
    # Early on the fast mode shows: the log-slope is not yet the slow eigenvalue.
    early = (math.log(x(0.02)[0]) - math.log(x(0.01)[0])) / 0.01
    assert abs(early - slow) > 1e-2 * abs(slow)


def test_underdamped_period_and_envelope_are_the_eigenvalue():
    p = api.example_params()
    (eq,) = stable_equilibria(analyze(p), "underdamped")
    sigma, omega = eq.eigenvalues[0].real, abs(eq.eigenvalues[0].imag)
    assert sigma < 0 < omega
    x = simulate(p, eq.theta, 2.0)
    zeros = crossings(lambda t: x(t)[0], 0.0, 2.0)
    assert len(zeros) >= 10
    half_periods = np.diff(zeros)
    assert np.ptp(half_periods) < 1e-6 * np.mean(half_periods)   # uniform: a linear motion
    assert 2 * np.mean(half_periods) == pytest.approx(2 * np.pi / omega, rel=1e-7)  # 2e-10
    # At the extrema (xdot = 0) |x| = A e^{sigma t} |cos psi| with one psi: log-linear.
    extrema = crossings(lambda t: x(t)[1], 1e-3, 2.0)
    rate, _ = np.polyfit(extrema, np.log(np.abs(x(extrema)[0])), 1)
    assert rate == pytest.approx(sigma, rel=1e-6)      # measured: 1.5e-9


def test_an_extraneous_root_beside_a_genuine_one_is_kept():
    """Two roots of sigma 1.8e-6 rad apart, one genuine and one extraneous (found by the
    property run): polishing the extraneous one on G reaches the genuine one, which the
    polynomial also found by itself. Merging the two lost the extraneous root; it is now
    studied again on its own branch and kept, each root labelled by the branch that vanishes
    there, and the equilibria are the isolation route's."""
    lib = load("doughty")
    p = lib.example_params(H=0.25, L=2.0, a=0.75, m_A=1.0, m_B=1.0, m_C=0.0, k=11135.0,
                           b=0.0, l_ND=0.25, F=0.125, g=0.0)
    roots = lib.analyze(p, "polynomial").roots
    genuine = [r.theta for r in roots if r.genuine]
    assert genuine == pytest.approx([r.theta for r in lib.analyze(p, "isolate").roots],
                                    abs=1e-12)
    for g in (-1.7594, 1.7594):
        near = [r for r in roots if abs(r.theta - g) < 1e-4]
        assert sorted(r.kind for r in near) == ["equilibrium", "extraneous"], near
        twin = next(r for r in near if r.kind == "extraneous")
        declared, negative_length = lib.equilibrium_branches(p, twin.theta)
        assert abs(negative_length) < 1e-9 * abs(declared), twin
