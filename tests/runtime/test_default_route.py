"""The default route keeps the isolation's contract (issue 29): only proven equilibria are
equilibria. A root of the polynomial that could not be proven, and the neighbourhood of every
extraneous root, are searched by the certified isolation of G itself (on the root's mode; on
every mode near an extraneous root), so what the polynomial route reports as an equilibrium is
proven, and a genuine root the branches misranked is found; so are the critical points of the
polynomial where it vanishes to rounding (a multiple root the root finder sees as a complex
pair). The reference is the isolation route, which shares only the enclosures of G with it.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from codegen import api
from codegen.runtime.analysis import analyze

EQUILIBRIUM_KINDS = ("equilibrium", "other assembly mode")


def _equilibria(result):
    return [(r.theta, r.kind) for r in result.roots if r.kind in EQUILIBRIUM_KINDS]


def _same_equilibria(auto, isolate):
    a, b = _equilibria(auto), _equilibria(isolate)
    return len(a) == len(b) and all(
        abs(x[0] - y[0]) <= 1e-9 and x[1] == y[1] for x, y in zip(a, b))


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(["doughty", "slider_crank"]), seed=st.integers(0, 2**32 - 1))
def test_every_equilibrium_of_the_default_route_is_proven_and_is_the_isolations(name, seed):
    library = api.load(name)
    rng = np.random.default_rng(seed)
    values = {p: v * math.exp(rng.uniform(-1.0, 1.0)) if v != 0 else 0.0
              for p, v in library.EXAMPLE.items()}
    try:
        params = library.Params(**values)
        auto, isolate = analyze(params, "auto"), analyze(params, "isolate")
    except ValueError:      # parameters the model refuses, refused by both routes alike
        return
    assert all(r.certified for r in auto.roots if r.kind in EQUILIBRIUM_KINDS)
    assert _same_equilibria(auto, isolate)


def test_equilibria_the_branches_misrank_at_extreme_scales_are_found():
    # L / a ~ 3e6: the stable equilibria near 0 and 180 deg sit 3e-4 rad from extraneous
    # roots, and the branches once called them extraneous (issue 29)
    library = api.load("doughty")
    params = library.Params(H=0.001289, L=585.6, a=0.0002057, m_A=0.2169, m_B=0.006405,
                            m_C=0.05767, k=10280, b=2.917, l_ND=0.001496, F=481.6, g=0.2443)
    auto, isolate = analyze(params, "auto"), analyze(params, "isolate")
    stable = [math.degrees(r.theta) for r in auto.roots
              if r.kind == "equilibrium" and r.stability == "stable"]
    assert stable == pytest.approx([0.0047, 179.9953], abs=1e-4)
    assert all(r.certified for r in auto.roots if r.kind == "equilibrium")
    assert _same_equilibria(auto, isolate)


def test_a_slider_crank_without_its_spring_and_force_keeps_its_equilibria():
    # k = F = 0 leaves no square root in G: every root of sigma is multiple, and rounding
    # turns them into complex pairs. The equilibria are where the crank torque T balances the
    # weights: cos(theta) = 2 T / ((m_1 + m_2) g R), in each assembly mode (issue 29).
    library = api.load("slider_crank")
    ex = library.EXAMPLE
    for torque in np.linspace(0.0, 0.9, 200):
        params = library.example_params(k=0.0, F=0.0, T=float(torque))
        auto = analyze(params, "auto")
        ratio = 2 * torque / ((ex["m_1"] + ex["m_2"]) * ex["g"] * ex["R"])
        expected = [] if ratio > 1 else sorted({-math.acos(ratio), math.acos(ratio)})
        for kind in EQUILIBRIUM_KINDS:
            found = sorted(r.theta for r in auto.roots if r.kind == kind)
            undecided = [(u.lo, u.hi) for u in auto.uncertain]
            # each expected equilibrium listed, or (at the fold) inside an uncertain interval
            for theta in expected:
                assert (any(abs(t - theta) < 1e-9 for t in found)
                        or any(lo - 1e-9 <= theta <= hi + 1e-9 for lo, hi in undecided)), (
                    torque, kind, theta, found, undecided)
            # and nothing listed elsewhere
            assert all(any(abs(t - theta) < 1e-9 for theta in expected) for t in found), (
                torque, kind, found, expected)
        assert all(r.certified for r in auto.roots if r.kind in EQUILIBRIUM_KINDS)
