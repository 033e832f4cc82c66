"""Property (issue 30): for random chains of two dyads (tests/support/random_chains.py: RRR, RRP,
RPR or PRR each, random dimensions, driving point, springs, loads, and either assembly mode
of each dyad declared), the emission plan's positions (dependent_state) satisfy the model's constraints,
and its G, e0 and e2 (the expressions printed to C) equal the independent reference's G, M
and B, at random angles in every quadrant where the chain assembles in its declared modes.

Hypothesis draws the seed of each chain (the project's profile is derandomized); each
derivation takes a few seconds to half a minute, so the property is marked slow.
"""
from __future__ import annotations

import sys
from pathlib import Path

import mpmath
import pytest
import sympy as sp
from hypothesis import given, settings

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))   # whatever pytest's import mode
from gallery import example  # noqa: E402
from random_chains import PAIRS, random_chain  # noqa: E402
from .test_random_mechanisms import SEEDS, SETTINGS, plan_matches_reference  # noqa: E402

from codegen.compiler.derivation import derive  # noqa: E402
from codegen.compiler.emission.plan import build_plan  # noqa: E402

#: |constraint| allowed at the plan's positions, relative to the chain's size
CONSTRAINT_TOLERANCE = 1e-20


def constraint_residuals(mechanism, params: dict, thetas) -> list[float]:
    """max |constraint| / size at each angle, the constraints evaluated at the coordinates
    the plan's dependent_state computes (30 digits)."""
    d = derive(mechanism)
    plan = build_plan(d)
    state = plan.function("dependent_state")
    theta, theta_d = (i.symbols[0] for i in state.inputs)
    coords = state.explicit(state.outputs[0].exprs)
    freezer = mechanism.freezer()
    q = list(freezer.values())
    frozen = [sp.sympify(e).subs(freezer) for e in mechanism.constraints]
    positions = sp.lambdify([theta, theta_d, *mechanism.symbols], coords, modules="mpmath")
    constraints = sp.lambdify([*q, *mechanism.symbols], frozen, modules="mpmath")
    values = [mpmath.mpf(params[p.symbol.name]) for p in mechanism.parameters]
    size = max(abs(v) for v in params.values())
    out = []
    with mpmath.workdps(30):
        for t in thetas:
            at = positions(mpmath.mpf(t), 0, *values)
            out.append(float(max(abs(c) for c in constraints(*at, *values)) / size))
    return out


def check_chain(mechanism, seed: int, drawn: bool = True) -> None:
    """The plan against the reference (test_random_mechanisms), and its positions closing
    the loops at the same angles."""
    thetas = plan_matches_reference(mechanism, seed, drawn)
    residuals = constraint_residuals(mechanism, example(mechanism), thetas)
    assert max(residuals) < CONSTRAINT_TOLERANCE, (mechanism.title, residuals)


@pytest.mark.slow
@settings(max_examples=3, **SETTINGS)
@given(SEEDS)
def test_random_dyad_chains_plan_equals_the_reference(seed):
    check_chain(random_chain(seed), seed)


#: A seed whose chain assembles at the test's angles, for each pair of kinds
PAIR_SEEDS = {pair: 1 for pair in PAIRS}


@pytest.mark.slow
@pytest.mark.parametrize("kinds", list(PAIR_SEEDS), ids=["-".join(k) for k in PAIR_SEEDS])
def test_each_pair_of_dyad_kinds_in_a_chain(kinds):
    """Every pair of kinds at least once, whatever hypothesis draws."""
    check_chain(random_chain(PAIR_SEEDS[kinds], kinds), PAIR_SEEDS[kinds], drawn=False)

