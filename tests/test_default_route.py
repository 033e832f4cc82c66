"""The default route keeps the isolation's contract (issue 29): only proven equilibria are
equilibria. A root of the polynomial that could not be proven, and the neighbourhood of every
extraneous root, are searched by the certified isolation of G itself (on the root's mode; on
every mode near an extraneous root), so what the polynomial route reports as an equilibrium is
proven, and a genuine root the branches misranked is found. The reference is the isolation
route, which shares only the enclosures of G with it.
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


@pytest.mark.xfail(strict=True, reason="issue 29, open: with k = F = 0 every root of sigma is "
                   "double and the root finder returns them as complex pairs; the isolation "
                   "route finds them")
def test_a_slider_crank_without_its_spring_and_force_keeps_its_equilibria():
    library = api.load("slider_crank")
    params = library.example_params(k=0.0, F=0.0, T=0.1)
    assert _same_equilibria(analyze(params, "auto"), analyze(params, "isolate"))
