"""Sanity of the independent numerical references in ``reference_mechanisms.py``.

These tests check the references themselves -- their geometry, assembly modes, assembly
regions, derivatives and equilibria -- against identities and cases with known answers. They
import nothing from ``codegen`` and need no conftest fixture (run with ``--noconftest``).
Deterministic: every random angle comes from a fixed seed.
"""
from __future__ import annotations

import ast
import functools
import math
import os
import sys

import mpmath
import numpy as np
import pytest

try:
    import reference_mechanisms as rm
except ImportError:  # e.g. pytest's importlib import mode: the tests folder is not on the path
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "support"))
    import reference_mechanisms as rm

REFERENCES = rm.REFERENCES
TWO_PI = 2 * math.pi
SEED = 20_240_611

CASES = [(name, mode) for name, ref in REFERENCES.items() for mode in ref.MODES]
CASE_IDS = [f"{name}{mode:+d}" for name, mode in CASES]

#: Equilibria at the example values, degrees (regression of the references' own output;
#: the numbers reported to the compiler's tests).
EXAMPLE_EQUILIBRIA_DEG = {
    ("slider_crank", +1): [-104.872024, 8.394583, 118.720177, 174.534976],
    ("slider_crank", -1): [-6.639322, 176.831119],
    ("four_bar", +1): [-137.312792, -45.967640, 40.813821, 142.718460],
    ("four_bar", -1): [-38.827498, 132.647602],
    ("torsion_pendulum", +1): [27.917734, 90.000000, 152.082266],
    ("doughty", +1): [-92.371323, -8.898065, -0.703161, 12.472611, 92.547578, 176.715491],
}


def _rng(*salt):
    return np.random.default_rng([SEED, *salt])


def _params(name, **changes):
    p = REFERENCES[name].EXAMPLE
    for key in changes:
        assert key in p, key
    p.update(changes)
    return p


@functools.lru_cache(maxsize=None)
def _example_equilibria(name, mode):
    return tuple(REFERENCES[name].equilibria(None, mode))


def _wrap(x):
    """x mapped into (-pi, pi]."""
    y = math.remainder(x, TWO_PI)
    return y + TWO_PI if y <= -math.pi else y


def _same_angles(a, b, tol=1e-9, periodic=True):
    """Two sets of angles agree (on the circle when periodic)."""
    if len(a) != len(b):
        return False
    for x in a:
        dist = [abs(math.remainder(x - y, TWO_PI)) if periodic else abs(x - y) for y in b]
        if min(dist) > tol:
            return False
    return True


def _g(ref, params, theta, mode=+1):
    val = ref.generalized_force(params, theta, mode)
    assert val is not None
    return val


def _g_scale(ref, params, theta, mode=+1):
    """The size of G's terms at theta: the sum of the magnitudes of each part's derivative."""
    terms = ref.generalized_force_terms(params, theta, mode)
    return mpmath.fsum(abs(v) for v in terms.values())


def _random_angles(ref, params, count, salt):
    lo, hi = ref.theta_range(params)
    return list(lo + (hi - lo) * _rng(*salt).random(count))


# --------------------------------------------------------------------------- interface


def test_interface_and_parameter_names():
    names = {
        "slider_crank": ["R", "l", "e", "m_1", "m_2", "m_3", "k", "l_0", "x_S", "y_S", "b", "F",
                         "T", "g"],
        "four_bar": ["d", "a_2", "a_3", "a_4", "m_2", "m_3", "m_4", "k", "l_0", "x_S", "y_S",
                     "b", "T", "g"],
        "torsion_pendulum": ["l", "m", "m_t", "k_t", "theta_0", "c", "F_x", "g"],
        "doughty": ["H", "L", "a", "m_A", "m_B", "m_C", "k", "b", "l_ND", "F", "g"],
    }
    assert set(REFERENCES) == set(names)
    for name, ref in REFERENCES.items():
        assert sorted(ref.EXAMPLE) == sorted(names[name])
        ref.EXAMPLE["g"] = -1.0  # a copy: the example cannot be changed by accident
        assert ref.EXAMPLE["g"] == 9.81
        with pytest.raises(ValueError):
            ref.potential(dict(ref.EXAMPLE, typo=1.0), 0.3)
        missing = ref.EXAMPLE
        del missing["g"]
        with pytest.raises(ValueError):
            ref.potential(missing, 0.3)
    assert REFERENCES["slider_crank"].EXAMPLE == dict(
        R=0.1, l=0.3, e=0.02, m_1=0.5, m_2=1.2, m_3=2.0, k=2000, l_0=0.25, x_S=0.45,
        y_S=0.2, b=40, F=-30, T=0, g=9.81)
    assert REFERENCES["four_bar"].EXAMPLE == dict(
        d=0.4, a_2=0.12, a_3=0.35, a_4=0.3, m_2=0.4, m_3=1.0, m_4=0.8, k=1500, l_0=0.2,
        x_S=0.1, y_S=0.45, b=30, T=0, g=9.81)
    assert REFERENCES["torsion_pendulum"].EXAMPLE == dict(
        l=1.0, m=1.0, m_t=2.0, k_t=20, theta_0=1.5707963267948966, c=0.5, F_x=0, g=9.81)
    assert REFERENCES["doughty"].EXAMPLE == dict(
        H=0.18, L=0.9, a=0.135, m_A=0.194, m_B=0.143, m_C=9.124, k=3500, b=875, l_ND=0.15,
        F=110, g=9.81)
    for name in ("torsion_pendulum", "doughty"):
        with pytest.raises(ValueError):
            REFERENCES[name].positions(None, 0.3, mode=-1)
    tp = REFERENCES["torsion_pendulum"]
    assert tp.theta_range(None) == (math.pi / 2 - math.pi, math.pi / 2 + math.pi)
    for name in ("slider_crank", "four_bar", "doughty"):
        assert REFERENCES[name].theta_range(None) == (-math.pi, math.pi)


def test_references_share_nothing_with_the_derivation():
    """The module imports only the standard library's math, numpy, scipy and mpmath."""
    path = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "support", "reference_mechanisms.py")
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read())
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            imported.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            imported.add((node.module or "").split(".")[0])
    assert imported <= {"__future__", "math", "mpmath", "numpy", "scipy"}, imported


# --------------------------------------------------------------------------- derivatives


@pytest.mark.parametrize("name, mode", CASES, ids=CASE_IDS)
def test_generalized_force_is_the_derivative_of_the_potential(name, mode):
    """A central difference of V (at 30 digits) and the double-precision complex-step scan
    both agree with generalized_force at random angles."""
    ref = REFERENCES[name]
    thetas = _random_angles(ref, None, 6, salt=(len(name), mode + 2))
    g_np = ref.generalized_force_array(None, thetas, mode)
    h = mpmath.mpf("1e-10")
    for theta, gd in zip(thetas, g_np):
        g = _g(ref, None, theta, mode)
        scale = _g_scale(ref, None, theta, mode)
        with mpmath.workdps(30):
            t = mpmath.mpf(theta)
            fd = (ref.potential(None, t + h, mode) - ref.potential(None, t - h, mode)) / (2 * h)
        assert abs(fd - g) <= mpmath.mpf("1e-15") * scale
        assert abs(gd - float(g)) <= 1e-11 * float(scale)
        assert abs(float(mpmath.fsum(ref.generalized_force_terms(None, theta, mode).values()))
                   - float(g)) <= 1e-14 * float(scale)


# --------------------------------------------------------------------------- equilibria


@pytest.mark.parametrize("name, mode", CASES, ids=CASE_IDS)
def test_example_equilibria_are_roots_of_G(name, mode):
    ref = REFERENCES[name]
    eqs = _example_equilibria(name, mode)
    lo, hi = ref.theta_range(None)
    assert eqs and list(eqs) == sorted(eqs) and len(set(eqs)) == len(eqs)
    for x in eqs:
        assert lo < x <= hi
        assert ref.positions(None, x, mode) is not None
        g = _g(ref, None, x, mode)
        with mpmath.workdps(30):
            dg = (_g(ref, None, x + 1e-7, mode) - _g(ref, None, x - 1e-7, mode)) / 2e-7
        # Tiny relative to G's terms, up to what rounding x to a float can leave.
        assert abs(g) <= 1e-12 * _g_scale(ref, None, x, mode) + 4 * abs(dg) * math.ulp(x)
        # A genuine sign change, G shrinking towards x (a simple root, not a jump).
        gl, gr = _g(ref, None, x - 1e-8, mode), _g(ref, None, x + 1e-8, mode)
        assert gl * gr < 0
        assert abs(abs(gr - gl) / 2e-8 - abs(dg)) <= 1e-3 * abs(dg)


@pytest.mark.parametrize("name, mode", CASES, ids=CASE_IDS)
def test_example_equilibria_regression(name, mode):
    found = [math.degrees(x) for x in _example_equilibria(name, mode)]
    assert found == pytest.approx(EXAMPLE_EQUILIBRIA_DEG[(name, mode)], abs=1e-6)


@pytest.mark.parametrize("name, mode", CASES, ids=CASE_IDS)
def test_equilibria_do_not_depend_on_the_sampling(name, mode):
    ref = REFERENCES[name]
    coarse = ref.equilibria(None, mode, samples=4001)
    assert _same_angles(coarse, _example_equilibria(name, mode), 1e-11, ref.periodic)
    assert ref.equilibria(None, mode) == list(_example_equilibria(name, mode))  # deterministic


def test_scan_finds_every_sign_change_of_an_independent_scan():
    """A plain scan of the high-precision G (coarse: 2 deg) sees no sign change that
    the references' equilibria do not account for."""
    for name, mode in CASES:
        ref = REFERENCES[name]
        lo, hi = ref.theta_range(None)
        grid = np.linspace(lo, hi, 181)
        signs = [1 if _g(ref, None, t, mode) > 0 else -1 for t in grid]
        changes = [(grid[i], grid[i + 1]) for i in range(len(grid) - 1)
                   if signs[i] != signs[i + 1]]
        eqs = _example_equilibria(name, mode)
        for a, b in changes:
            inside = [x for x in eqs if a <= x <= b]
            assert len(inside) % 2 == 1, (name, mode, a, b)
        assert len(changes) <= len(eqs)


# --------------------------------------------------------------------------- modes, mirrors


def _xy(pt):
    return np.array([float(pt[0]), float(pt[1])])


def test_slider_crank_modes_straddle_the_crank_pin():
    """The slide meets the circle of radius l about A at two points symmetric about A's
    vertical: x_B(+1) + x_B(-1) = 2 x_A, with the mode +1 one to the right."""
    ref = REFERENCES["slider_crank"]
    for i, e in enumerate((0.02, -0.15, 0.0)):
        p = _params("slider_crank", e=e)
        for theta in _random_angles(ref, p, 10, salt=(1, i)):
            plus, minus = ref.positions(p, theta, +1), ref.positions(p, theta, -1)
            with mpmath.workdps(30):
                assert abs(plus["B"][0] + minus["B"][0] - 2 * plus["A"][0]) < 1e-25
                assert plus["B"][0] >= plus["A"][0] >= minus["B"][0]
                for pts in (plus, minus):
                    assert pts["B"][1] == e
                    dist = mpmath.sqrt((pts["B"][0] - pts["A"][0]) ** 2
                                       + (pts["B"][1] - pts["A"][1]) ** 2)
                    assert abs(dist - p["l"]) < 1e-25


def test_slider_crank_mirror_through_the_y_axis():
    """Reflecting through the y axis maps the crank at theta to pi - theta, keeps the slide
    y = e and puts the slider on the other side of the pin: mode -1 at pi - theta is the
    mirror image of mode +1 at theta. With S, F and T mirrored too (x_S -> -x_S, F -> -F,
    T -> -T; gravity is symmetric) G changes sign and the equilibria map theta -> pi - theta.
    (The x-axis mirror keeps the mode: mode +1 at -theta with e -> -e.)"""
    ref = REFERENCES["slider_crank"]
    p = _params("slider_crank", T=0.7)
    q = _params("slider_crank", T=-0.7, x_S=-p["x_S"], F=-p["F"])
    e_flip = _params("slider_crank", T=0.7, e=-p["e"])
    for theta in _random_angles(ref, p, 8, salt=(2,)):
        plus = ref.positions(p, theta, +1)
        minus = ref.positions(p, math.pi - theta, -1)
        for point in ("A", "B", "rod_centre"):
            assert np.allclose(_xy(minus[point]), _xy(plus[point]) * [-1, 1], atol=1e-14)
        flipped = ref.positions(e_flip, -theta, +1)
        for point in ("A", "B", "rod_centre"):
            assert np.allclose(_xy(flipped[point]), _xy(plus[point]) * [1, -1], atol=1e-14)
        g_p, g_q = _g(ref, p, theta, +1), _g(ref, q, math.pi - theta, -1)
        assert abs(g_p + g_q) <= 1e-12 * _g_scale(ref, p, theta, +1)
    eq_p = ref.equilibria(p, +1)
    eq_q = ref.equilibria(q, -1)
    assert eq_p and _same_angles(eq_q, [_wrap(math.pi - x) for x in eq_p])


def test_four_bar_modes_are_reflections_across_A_O4():
    """The two intersections of the circles about A and O4 are mirror images across the
    line A-O4; mode +1 is the one left of A -> O4. Both satisfy the loop closure."""
    ref = REFERENCES["four_bar"]
    p = ref.EXAMPLE
    for theta in _random_angles(ref, p, 10, salt=(3,)):
        plus, minus = ref.positions(p, theta, +1), ref.positions(p, theta, -1)
        a, o4 = _xy(plus["A"]), _xy(plus["O4"])
        u = (o4 - a) / np.linalg.norm(o4 - a)
        bp, bm = _xy(plus["B"]) - a, _xy(minus["B"]) - a
        reflected = 2 * np.dot(bp, u) * u - bp
        assert np.allclose(reflected, bm, atol=1e-14)
        assert u[0] * bp[1] - u[1] * bp[0] > 0 > u[0] * bm[1] - u[1] * bm[0]
        with mpmath.workdps(30):
            for pts in (plus, minus):
                for c1, c2, length in (("A", "B", p["a_3"]), ("O4", "B", p["a_4"]),
                                       ("O2", "A", p["a_2"])):
                    d = mpmath.sqrt((pts[c1][0] - pts[c2][0]) ** 2
                                    + (pts[c1][1] - pts[c2][1]) ** 2)
                    assert abs(d - length) < 1e-25


def test_four_bar_mirror_through_the_ground_line():
    """Reflecting through the x axis (the ground line) maps theta to -theta and swaps the
    modes. With y_S -> -y_S, g -> -g and T -> -T, G changes sign and the equilibria of mode
    -1 are the negated equilibria of mode +1."""
    ref = REFERENCES["four_bar"]
    p = _params("four_bar", T=0.9)
    q = _params("four_bar", T=-0.9, y_S=-p["y_S"], g=-p["g"])
    for theta in _random_angles(ref, p, 8, salt=(4,)):
        plus = ref.positions(p, theta, +1)
        minus = ref.positions(p, -theta, -1)
        for point in ("A", "B", "coupler_centre", "rocker_centre"):
            assert np.allclose(_xy(minus[point]), _xy(plus[point]) * [1, -1], atol=1e-14)
        g_p, g_q = _g(ref, p, theta, +1), _g(ref, q, -theta, -1)
        assert abs(g_p + g_q) <= 1e-12 * _g_scale(ref, p, theta, +1)
    eq_p = ref.equilibria(p, +1)
    assert eq_p and _same_angles(ref.equilibria(q, -1), [_wrap(-x) for x in eq_p])


def test_torsion_pendulum_mirror_about_the_vertical():
    """With theta_0 = pi/2 the reflection theta -> pi - theta maps the spring and gravity onto
    themselves and F_x onto -F_x."""
    ref = REFERENCES["torsion_pendulum"]
    eqs = _example_equilibria("torsion_pendulum", +1)
    assert _same_angles([math.pi - x for x in eqs], eqs, 1e-12, periodic=False)
    left = ref.equilibria(_params("torsion_pendulum", F_x=3.0))
    right = ref.equilibria(_params("torsion_pendulum", F_x=-3.0))
    assert left and _same_angles([math.pi - x for x in left], right, 1e-11, periodic=False)


def test_doughty_mirror_through_the_x_axis():
    """Reflecting through the X axis (theta -> -theta, B -> -B, P mirrored, O' fixed) with
    g -> -g and F -> -F negates G and the equilibria."""
    ref = REFERENCES["doughty"]
    p = ref.EXAMPLE
    q = _params("doughty", g=-p["g"], F=-p["F"])
    for theta in _random_angles(ref, p, 6, salt=(5,)):
        a, b = ref.positions(p, theta), ref.positions(q, -theta)
        for point in ("A", "B", "C", "P"):
            assert np.allclose(_xy(b[point]), _xy(a[point]) * [1, -1], atol=1e-14)
        assert abs(_g(ref, p, theta) + _g(ref, q, -theta)) <= 1e-12 * _g_scale(ref, p, theta)
    eqs = _example_equilibria("doughty", +1)
    assert _same_angles(ref.equilibria(q), [_wrap(-x) for x in eqs])


def test_doughty_geometry():
    """A on X, B on Y, |A - B| = L, P on the bar at distance a from B, r = |P - O'| > 0."""
    ref = REFERENCES["doughty"]
    p = ref.EXAMPLE
    for theta in _random_angles(ref, p, 6, salt=(6,)):
        pts = ref.positions(p, theta)
        with mpmath.workdps(30):
            A, B, P = pts["A"], pts["B"], pts["P"]
            assert A[1] == 0 and B[0] == 0
            assert abs(mpmath.hypot(A[0] - B[0], A[1] - B[1]) - p["L"]) < 1e-25
            assert abs(mpmath.hypot(P[0] - B[0], P[1] - B[1]) - p["a"]) < 1e-25
            assert abs(mpmath.hypot(P[0] - A[0], P[1] - A[1]) - (p["L"] - p["a"])) < 1e-25
            assert abs(A[0] - p["L"] * mpmath.cos(theta)) < 1e-25
            assert ref.spring_length(p, theta) >= p["H"] - p["a"]


# --------------------------------------------------------------------------- assembly


def test_examples_assemble_over_the_whole_range():
    """slider_crank: l >= R + |e|; four_bar: |a_3 - a_4| <= d - a_2 and d + a_2 <= a_3 + a_4
    (|A - O4| runs over [d - a_2, d + a_2]); the others have no condition."""
    sc, fb = REFERENCES["slider_crank"].EXAMPLE, REFERENCES["four_bar"].EXAMPLE
    assert sc["l"] >= sc["R"] + abs(sc["e"])
    assert abs(fb["a_3"] - fb["a_4"]) <= fb["d"] - fb["a_2"]
    assert fb["d"] + fb["a_2"] <= fb["a_3"] + fb["a_4"]
    for name, mode in CASES:
        ref = REFERENCES[name]
        lo, hi = ref.theta_range(None)
        grid = np.linspace(lo, hi, 4001)[1:]
        assert all(ref.assembles(None, t) for t in grid[::40])
        assert np.all(np.isfinite(ref.potential_array(None, grid, mode)))
        assert np.all(np.isfinite(ref.generalized_force_array(None, grid, mode)))


SHORT_ROD = dict(l=0.06, e=0.02)  # l < R - |e|: |R sin(theta) - e| <= l on two arcs
NON_GRASHOF = dict(a_2=0.3, a_3=0.15, a_4=0.3)  # |A - O4| in [0.1, 0.7], needs [0.15, 0.45]


def _limits_slider_crank(p):
    """Crank angles where e - R sin(theta) = +-l (the closed-form boundary of the region)."""
    out = []
    for s in ((p["e"] - p["l"]) / p["R"], (p["e"] + p["l"]) / p["R"]):
        if abs(s) <= 1:
            out += [math.asin(s), _wrap(math.pi - math.asin(s))]
    return sorted(out)


def _limits_four_bar(p):
    """Crank angles where |A - O4| = a_3 +- a_4 (law of cosines in the triangle O2 A O4)."""
    out = []
    for dist in (p["a_3"] + p["a_4"], abs(p["a_3"] - p["a_4"])):
        c = (p["a_2"] ** 2 + p["d"] ** 2 - dist**2) / (2 * p["a_2"] * p["d"])
        if abs(c) <= 1:
            out += [math.acos(c), -math.acos(c)]
    return sorted(out)


@pytest.mark.parametrize("name, changes, limits", [
    ("slider_crank", SHORT_ROD, _limits_slider_crank),
    ("four_bar", NON_GRASHOF, _limits_four_bar),
], ids=["slider_crank", "four_bar"])
def test_assembly_regions(name, changes, limits):
    """Where positions() answers, the loop closes in the requested mode; where it returns None,
    a dense sampling of the candidate positions finds no closure; and the region's ends are
    the closed-form limit angles, where the two modes meet."""
    ref = REFERENCES[name]
    p = _params(name, **changes)
    thetas = _random_angles(ref, p, 60, salt=(7, len(name)))
    circle = np.linspace(0, TWO_PI, 3601)
    assembled = 0
    for theta in thetas:
        for mode in (+1, -1):
            pts = ref.positions(p, theta, mode)
            assert (pts is None) == (not ref.assembles(p, theta))
            crank = p["R"] if name == "slider_crank" else p["a_2"]
            a = crank * np.array([math.cos(theta), math.sin(theta)])
            if name == "slider_crank":
                # Candidate B on the circle of radius l about A; the slide is y = e.
                miss = np.abs(a[1] + p["l"] * np.sin(circle) - p["e"])
                reach = abs(a[1] - p["e"]) <= p["l"]
            else:
                # Candidate B on the circle of radius a_4 about O4; need |B - A| = a_3.
                b = np.stack([p["d"] + p["a_4"] * np.cos(circle), p["a_4"] * np.sin(circle)])
                miss = np.abs(np.hypot(b[0] - a[0], b[1] - a[1]) - p["a_3"])
                dist = math.hypot(a[0] - p["d"], a[1])
                reach = abs(p["a_3"] - p["a_4"]) <= dist <= p["a_3"] + p["a_4"]
            assert reach == (pts is not None)
            if pts is None:
                assert miss.min() > 0
                assert ref.potential(p, theta, mode) is None
                assert ref.generalized_force(p, theta, mode) is None
                continue
            assembled += 1
            assert miss.min() < 2e-3  # the sampled circle passes near the closure
            b = _xy(pts["B"])
            if name == "slider_crank":
                assert mode * (b[0] - a[0]) >= 0
                assert abs(math.hypot(*(b - a)) - p["l"]) < 1e-14 and b[1] == p["e"]
            else:
                o4 = np.array([p["d"], 0.0])
                cross = (o4 - a)[0] * (b - a)[1] - (o4 - a)[1] * (b - a)[0]
                assert mode * cross >= 0
                assert abs(math.hypot(*(b - a)) - p["a_3"]) < 1e-14
                assert abs(math.hypot(*(b - o4)) - p["a_4"]) < 1e-14
    assert 0 < assembled < 2 * len(thetas)
    # The region's ends: the reference's assemblability flips exactly at the limit angles.
    grid = np.linspace(-math.pi, math.pi, 36001)
    ok = np.array([ref.assembles(p, t) for t in grid])
    flips = grid[:-1][ok[:-1] != ok[1:]]
    expected = limits(p)
    assert len(flips) == len(expected) == 4
    assert np.allclose(np.sort(flips), expected, atol=2 * (grid[1] - grid[0]))
    for theta_b in expected:
        inside = [t for t in (theta_b - 1e-12, theta_b + 1e-12) if ref.assembles(p, t)]
        assert len(inside) == 1  # the region ends here
        plus = ref.positions(p, inside[0], +1)
        minus = ref.positions(p, inside[0], -1)
        assert np.allclose(_xy(plus["B"]), _xy(minus["B"]), atol=1e-5)


@pytest.mark.parametrize("name, changes, limits", [
    ("slider_crank", SHORT_ROD, _limits_slider_crank),
    ("four_bar", NON_GRASHOF, _limits_four_bar),
], ids=["slider_crank", "four_bar"])
def test_limit_positions_are_not_equilibria(name, changes, limits):
    """At a limit position the dependent motion is infinitely fast, so G blows up (like the
    inverse square root of the distance); the equilibria are away from the limits and
    genuine roots."""
    ref = REFERENCES[name]
    p = _params(name, **changes)
    for mode in (+1, -1):
        for theta_b in limits(p):
            side = -1 if ref.assembles(p, theta_b - 1e-9) else +1
            mags = [abs(_g(ref, p, theta_b + side * d, mode)) for d in (1e-4, 1e-8, 1e-12)]
            assert mags[1] > 30 * mags[0] and mags[2] > 30 * mags[1]
        eqs = ref.equilibria(p, mode)
        assert eqs
        for x in eqs:
            assert min(abs(math.remainder(x - t, TWO_PI)) for t in limits(p)) > 1e-6
            assert ref.assembles(p, x - 1e-6) and ref.assembles(p, x + 1e-6)
            g = _g(ref, p, x, mode)
            assert abs(g) <= 1e-10 * _g_scale(ref, p, x, mode)
            assert _g(ref, p, x - 1e-8, mode) * _g(ref, p, x + 1e-8, mode) < 0


# --------------------------------------------------------------------------- known answers


@pytest.mark.parametrize("theta_0", [1.5707963267948966, 0.3, -2.0, 7.0])
def test_torsion_pendulum_without_loads_rests_at_its_free_angle(theta_0):
    ref = REFERENCES["torsion_pendulum"]
    p = _params("torsion_pendulum", g=0.0, F_x=0.0, theta_0=theta_0)
    assert ref.equilibria(p) == pytest.approx([theta_0], abs=1e-13)


def test_torsion_pendulum_range_ends():
    """Without the spring G = (m/2 + m_t) g l cos(theta): roots at the odd multiples of pi/2
    inside (theta_0 - pi, theta_0 + pi] -- the closed end counts, the open end does not."""
    ref = REFERENCES["torsion_pendulum"]
    half = math.pi / 2
    assert ref.equilibria(_params("torsion_pendulum", k_t=0.0)) == \
        pytest.approx([half, 3 * half], abs=1e-12)
    assert ref.equilibria(_params("torsion_pendulum", k_t=0.0, theta_0=0.0)) == \
        pytest.approx([-half, half], abs=1e-12)
    # The spring winds: theta_0 + 2 pi gives the same roots shifted by 2 pi.
    shifted = ref.equilibria(_params("torsion_pendulum", k_t=0.0, theta_0=TWO_PI))
    assert shifted == pytest.approx([TWO_PI - half, TWO_PI + half], abs=1e-12)


@pytest.mark.parametrize("name", ["slider_crank", "four_bar"])
def test_without_loads_G_vanishes_identically(name):
    ref = REFERENCES[name]
    zero = dict(k=0.0, g=0.0, T=0.0, **({"F": 0.0} if name == "slider_crank" else {}))
    p = _params(name, **zero)
    for mode in (+1, -1):
        for theta in _random_angles(ref, p, 5, salt=(8, mode + 2)):
            assert abs(_g(ref, p, theta, mode)) < 1e-25
        assert ref.equilibria(p, mode) == []
    # A constant torque alone: G = -T everywhere, never zero.
    p = _params(name, **dict(zero, T=0.25))
    for theta in _random_angles(ref, p, 3, salt=(9,)):
        assert abs(_g(ref, p, theta, +1) + mpmath.mpf(0.25)) < 1e-25
    assert ref.equilibria(p, +1) == [] and ref.equilibria(p, -1) == []


@pytest.mark.parametrize("name, changes", [
    ("slider_crank", dict(m_2=0.0, m_3=0.0, k=0.0, F=0.0, T=0.0)),
    ("slider_crank", dict(m_2=0.0, m_3=0.0, k=0.0, F=0.0, T=0.0, e=0.0)),
    ("four_bar", dict(m_3=0.0, m_4=0.0, k=0.0, T=0.0)),
    ("four_bar", dict(m_3=0.0, m_4=0.0, k=0.0, T=0.0, **NON_GRASHOF)),
    ("doughty", dict(k=0.0)),
], ids=["slider_crank", "slider_crank_e0", "four_bar", "four_bar_non_grashof", "doughty"])
def test_only_the_crank_is_heavy(name, changes):
    """With gravity acting on the crank alone (on the bar's weight and F for Doughty, both
    proportional to sin(theta)) the equilibria are the crank hanging and standing,
    theta = -+pi/2, wherever the mechanism assembles there."""
    ref = REFERENCES[name]
    p = _params(name, **changes)
    for mode in ref.MODES:
        expected = [t for t in (-math.pi / 2, math.pi / 2) if ref.assembles(p, t)]
        assert ref.equilibria(p, mode) == pytest.approx(expected, abs=1e-12)
    if name == "four_bar" and "a_3" in changes:
        assert expected == []  # |A - O4| = 0.5 > a_3 + a_4 at +-pi/2: no equilibrium at all


def test_slider_crank_force_alone_holds_at_the_dead_centres():
    """V = -F x_B is stationary where the rod lines up with the crank: B at R + l from O
    (extended) or l - R (folded), on the slide y = e."""
    ref = REFERENCES["slider_crank"]
    p = _params("slider_crank", g=0.0, k=0.0, T=0.0)
    e, R, l = p["e"], p["R"], p["l"]
    ext, fold = math.asin(e / (R + l)), math.asin(e / (l - R))
    expected = {+1: [ext, _wrap(fold + math.pi)], -1: [_wrap(math.pi - ext), -fold]}
    for mode in (+1, -1):
        assert _same_angles(ref.equilibria(p, mode), expected[mode], 1e-12)


def test_doughty_spring_through_zero_length_is_not_an_equilibrium():
    """With a = H the spring's end P passes through O' at theta = 0: r ~ (L - a)|theta|, so
    G jumps by 2 k l_ND (L - a) there and changes sign without a root. It must not be
    reported; the genuine equilibria still are."""
    ref = REFERENCES["doughty"]
    p = _params("doughty", a=0.18)
    assert ref.spring_length(p, 0.0) < 1e-25
    gl, gr = _g(ref, p, -1e-9), _g(ref, p, 1e-9)
    assert gl > 0 > gr  # the scan sees a sign change here...
    jump = 2 * p["k"] * p["l_ND"] * (p["L"] - p["a"])
    assert abs((gl - gr) - jump) < 1e-5 * jump
    eqs = ref.equilibria(p)
    assert eqs and min(abs(x) for x in eqs) > 0.1  # ...and rejects it
    for x in eqs:
        assert abs(_g(ref, p, x)) <= 1e-10 * _g_scale(ref, p, x)


def test_doughty_spring_alone_rests_where_it_is_free_or_extremal():
    """With g = F = 0, G = k (r - l_ND) dr/dtheta: every equilibrium has r = l_ND or r at an
    extremum (dr/dtheta = 0, e.g. theta = 0 and pi, where P is on the X axis)."""
    ref = REFERENCES["doughty"]
    p = _params("doughty", g=0.0, F=0.0)
    eqs = ref.equilibria(p)
    assert _same_angles([x for x in eqs if abs(math.remainder(x, math.pi)) < 1e-12],
                        [0.0, math.pi])
    for x in eqs:
        with mpmath.workdps(30):
            r = ref.spring_length(p, x)
            dr = (ref.spring_length(p, x + 1e-9) - ref.spring_length(p, x - 1e-9)) / 2e-9
        assert abs(r - p["l_ND"]) < 1e-12 or abs(dr) < 1e-12
