"""Properties that catch hidden absolute thresholds and non-reentrant code."""
from __future__ import annotations

import math
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, assume, given, settings, strategies as st

from codegen.api import load

api = load("doughty")
from codegen.runtime.analysis import analyze, analyze_batch

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))   # whatever pytest's import mode
from .test_equilibria import min_spring_length  # noqa: E402  (closed form of min r, (34))
import reference_mechanisms  # noqa: E402  (independent of our derivation)

REFERENCE = reference_mechanisms.REFERENCES["doughty"]

LENGTHS = ("H", "L", "a", "l_ND")


@st.composite
def parameter_sets(draw):
    L = draw(st.floats(0.1, 3.0))
    return api.Params(
        H=draw(st.floats(-2.0, 2.0)), L=L, a=draw(st.floats(0.0, 1.0)) * L,
        m_A=draw(st.floats(0.01, 20.0)), m_B=draw(st.floats(0.01, 20.0)),
        m_C=draw(st.floats(0.0, 20.0)), k=draw(st.floats(1.0, 1e5)),
        b=draw(st.floats(0.0, 1e4)), l_ND=draw(st.floats(0.0, 2.0)),
        F=draw(st.floats(-300.0, 300.0)), g=draw(st.floats(0.0, 20.0)))


def _generic(p):
    """Set aside (nearly) degenerate families: a = L puts r = 0 on a root; l_ND = 0, k = 0 or
    F = g = 0 with H = 0 or a = 0 stack factors into roots of multiplicity 4, whose being real
    at all is decided by the last bit; within 1e-6 of those, by the last few bits
    (test_validation covers the exact families directly)."""
    margin = 1e-6 * p.L
    assume(margin < p.a < p.L - margin and p.l_ND > margin and abs(p.H) > margin)
    assume(p.k > 0 and (p.F != 0 or p.g != 0))


def _scaled(p, **factors):
    return api.Params(**{n: getattr(p, n) * factors.get(n, 1.0) for n in api.PARAMETER_NAMES})


def _nearly_collapsing(p) -> bool:
    """Whether the spring length r gets below 1e-6 L somewhere: near r = 0, G changes over an
    angle ~ r_min/L and its terms grow like 1/r, so roots there are as ill-posed as at r = 0."""
    return min_spring_length(p) < 1e-6 * p.L


def _analysis(p):
    """analyze(p), with parameter sets where a root puts r = 0 (|H| = a, or a = L) set
    aside: the library reports those as DOUGHTY_ERR_SINGULAR_STATE (tested elsewhere)..."""
    try:
        return analyze(p)
    except api.LibraryError as error:
        # ... and neutral sets (H = 0, a = L/2 with F = g = 0: G vanishes identically)
        assume(error.code not in ("ERR_SINGULAR_STATE", "ERR_EVERY_ANGLE"))
        raise


def _genuine_angles(p):
    return [(r.theta, r.genuine) for r in _analysis(p).roots]


def _well_separated(roots, gap=1e-6):
    thetas = sorted(t for t, _ in roots)
    return all(b - a > gap for a, b in zip(thetas, thetas[1:]))


def _same_roots(a, b, tol=1e-8):
    if [g for _, g in a] != [g for _, g in b] or len(a) != len(b):
        return False
    return all(abs(math.remainder(x - y, 2 * math.pi)) < tol for (x, _), (y, _) in zip(a, b))


@settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(parameter_sets(), st.floats(0.01, 100.0))
def test_angles_and_kinds_do_not_change_with_length_scale(p, s):
    _generic(p)
    base = _genuine_angles(p)
    assume(_well_separated(base))  # a pair closer than this may legitimately merge
    factors = {n: s for n in LENGTHS} | {"k": 1.0 / s}
    assert _same_roots(base, _genuine_angles(_scaled(p, **factors)))


@settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(parameter_sets(), st.floats(1e-3, 1e3))
def test_angles_and_kinds_do_not_change_when_k_F_g_scale_together(p, c):
    _generic(p)
    base = _genuine_angles(p)
    assume(_well_separated(base))
    assert _same_roots(base, _genuine_angles(_scaled(p, k=c, F=c, g=c)))


@settings(max_examples=1000, deadline=None)
@given(parameter_sets())
def test_genuine_roots_satisfy_43_and_extraneous_ones_fail_it(p):
    assume(not _nearly_collapsing(p))
    for r in _analysis(p).roots:
        genuine, extraneous = api.equilibrium_branches(p, r.theta)
        if r.genuine:
            assert (r.relative_residual <= 1e-12
                    or abs(r.residual) <= 1e-12 * _data_sensitivity(p, r.theta)), r
        else:
            # (43) fails, relative to the size of its own terms, far beyond rounding (an
            # extraneous root 2e-6 rad from a genuine one fails it by ~1e-6); the other
            # branch holds
            assert r.relative_residual >= 1e-9, r
            assert abs(extraneous) < abs(genuine), r


def _data_sensitivity(p, theta, step=1e-8):
    """sum over the data of |x dG/dx| at theta (the reference, 30 digits): what G moves by
    when each datum moves by its own size. Where G's terms are small differences of large
    ones (k (r - l_ND) with r ~ l_ND, e.g. g ~ 0 beside a flat triple root), rounding leaves
    a residual of this size times epsilon, however small the terms' own sum."""
    values = {n: getattr(p, n) for n in api.PARAMETER_NAMES}

    def g(name, factor):
        return REFERENCE.generalized_force({**values, name: values[name] * factor}, theta)

    return float(sum(abs(g(n, 1 + step) - g(n, 1 - step)) / (2 * step)
                     for n in api.PARAMETER_NAMES if values[n] != 0))


def _random_table(n, seed=7):
    rng = np.random.default_rng(seed)
    table = api.params_array([api.example_params()] * n)
    for name in api.PARAMETER_NAMES:
        table[name] *= rng.uniform(0.5, 1.5, n)
    table["a"] = np.minimum(table["a"], table["L"])
    return table


def test_batch_analysis_is_bit_identical_to_single_calls_in_any_order_and_thread():
    table = _random_table(400)
    batch, statuses = analyze_batch(table, api)
    assert (statuses == 0).all()
    singles = [analyze(api.Params(**{n: float(row[n]) for n in api.PARAMETER_NAMES}))
               for row in table]
    assert [a.to_dict() for a in batch] == [a.to_dict() for a in singles]
    order = np.random.default_rng(1).permutation(len(table))
    shuffled, _ = analyze_batch(table[order], api)
    assert [shuffled[i].to_dict() for i in np.argsort(order)] == [a.to_dict() for a in batch]
    chunks = np.array_split(np.arange(len(table)), 8)
    with ThreadPoolExecutor(4) as pool:
        parts = list(pool.map(lambda idx: analyze_batch(table[idx], api)[0], chunks))
    threaded = [a for part in parts for a in part]
    assert [a.to_dict() for a in threaded] == [a.to_dict() for a in batch]


def test_function_batches_are_bit_identical_to_single_calls_across_threads():
    table = _random_table(300, seed=3)
    theta = np.linspace(-3.1, 3.1, len(table))
    for name in ("linearisation", "reduced_coefficients", "sigma", "equilibrium_residual"):
        fn = getattr(api, name)
        args = () if name == "sigma" else (theta,)
        batch = fn(table, *args)
        with ThreadPoolExecutor(4) as pool:
            singles = list(pool.map(
                lambda i: fn(api.Params(**{n: float(table[n][i]) for n in api.PARAMETER_NAMES}),
                             *(a[i] for a in args)), range(len(table))))
        stacked = np.array([np.array(s, dtype=float).ravel() for s in singles])
        flat = np.column_stack([np.asarray(x, dtype=float).reshape(len(table), -1)
                                for x in (batch if isinstance(batch, tuple) else (batch,))])
        assert np.array_equal(stacked, flat), name
