"""The answer does not depend on the units (issue 48): each one-coordinate mechanism, its
lengths, masses and times given in units 10^k apart (every parameter multiplied by its unit's
powers of 10^k_L, 10^k_M, 10^k_T), gets the same equilibria, kinds, proofs and uncertain
intervals, and K, M, B, omega_n and sigma in the new units. The analysis divides the units
out (codegen_analysis.c, emission/scaling.py); before it did, lengths x 1e-9 gave "every
angle is an equilibrium", x 1e-8 roots where no square root vanishes, and x 1e8 an overflow.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from codegen.api import load
from codegen.compiler.emission.scaling import _dimension_of, _power_of_two, unit_scaling
from codegen.compiler.model.units import dimension
from codegen.runtime.analysis import analyze
from libraries import generated_libraries
from pathlib import Path

GENERATED = Path(__file__).resolve().parents[2] / "generated"
MECHANISMS = generated_libraries(GENERATED, several=False)


def in_units(api, params, k_length, k_mass, k_time):
    """params with every parameter in units 10^k of its own (a change of units)."""
    values = {}
    for name in api.PARAMETER_NAMES:
        unit = api.UNITS[name]
        a, b, c = dimension(unit)
        values[name] = getattr(params, name) * 10.0 ** (a * k_length + b * k_mass + c * k_time)
    return api.example_params(**values)


def same_answer(api, one, other, k):
    """other is one in units 10^k (k: length, mass, time): the same equilibria (of every
    mode) and uncertain intervals, the angles to rounding, each quantity in its units. An
    extraneous root (of the squared polynomial, no equilibrium) is listed only where sigma
    fits a double in the user's units: where it would overflow the answer is the isolation's,
    which has none, so the other units' extraneous roots are among the first's."""
    a, b = analyze(one), analyze(other)
    real = [r for r in a.roots if r.kind != "extraneous"], [r for r in b.roots if r.kind != "extraneous"]
    assert [(r.kind, r.certified) for r in real[0]] == [(r.kind, r.certified) for r in real[1]]
    for s in (r for r in b.roots if r.kind == "extraneous"):
        assert any(math.isclose(r.theta, s.theta, rel_tol=1e-9, abs_tol=1e-9)
                   for r in a.roots if r.kind == "extraneous")
    assert [(u.kind, u.mode) for u in a.uncertain] == [(u.kind, u.mode) for u in b.uncertain]
    force = 10.0 ** (2 * k[0] + k[1] - 2 * k[2])
    stiffest = max([abs(r.K) for r in a.roots if r.kind != "extraneous"], default=0.0)
    for r, s in zip(*real):
        assert math.isclose(r.theta, s.theta, rel_tol=1e-9, abs_tol=1e-9)
        assert math.isclose(s.K, r.K * force, rel_tol=1e-6, abs_tol=1e-9 * stiffest * force)
        assert math.isclose(s.M, r.M * force * 10.0 ** (2 * k[2]), rel_tol=1e-6)
        assert np.allclose(np.array(s.omega_n, dtype=complex),
                           np.array(r.omega_n, dtype=complex) * 10.0 ** -k[2], rtol=1e-6)
    for u, v in zip(a.uncertain, b.uncertain):
        assert abs(u.lo - v.lo) < 1e-6 and abs(u.hi - v.hi) < 1e-6


@pytest.mark.parametrize("name", MECHANISMS)
@settings(max_examples=12, deadline=None)
@given(k_length=st.integers(-12, 12), k_mass=st.integers(-12, 12), k_time=st.integers(-4, 4))
def test_the_analysis_does_not_depend_on_the_units(name, k_length, k_mass, k_time):
    api = load(name)
    example = api.example_params()
    same_answer(api, example, in_units(api, example, k_length, k_mass, k_time),
                (k_length, k_mass, k_time))


# Issue 48's reproducers.
FOUR_BAR_LENGTHS = ("d", "a_2", "a_3", "a_4", "l_0", "x_S", "y_S")


@pytest.mark.parametrize("scale", [1e-12, 1e-9, 1e-8, 1e8, 1e12])
def test_a_four_bar_in_other_length_units(scale):
    api = load("four_bar")
    at_one = api.example_params(g=0.0, T=0.0)
    scaled = api.example_params(g=0.0, T=0.0, **{n: getattr(at_one, n) * scale
                                                  for n in FOUR_BAR_LENGTHS})
    for method in ("polynomial", "isolate"):
        a, b = analyze(at_one, method), analyze(scaled, method)
        assert [(r.kind, r.certified) for r in a.roots if r.kind != "extraneous"] == \
               [(r.kind, r.certified) for r in b.roots if r.kind != "extraneous"]
        assert len([r for r in b.roots if r.kind == "equilibrium"]) == 4
        assert not b.uncertain and not b.singular


def test_doughty_with_a_vanishing_force_alone():
    """k = g = 0 and F = 1e-200: G ~ 1e-200; its square underflowed in sigma ("every
    angle"). The two equilibria at +-90 deg are proven."""
    a = analyze(load("doughty").example_params(k=0.0, g=0.0, F=1e-200))
    assert [round(math.degrees(r.theta), 9) for r in a.equilibria] == [-90.0, 90.0]
    assert all(r.certified for r in a.equilibria)


def test_the_generator_finds_each_quantitys_units():
    """G in N m and sigma's own units, found at 60 digits; a model whose units do not make
    it homogeneous keeps the user's units."""
    import sympy as sp
    from codegen.compiler.derivation import derive
    from codegen.compiler.model import doughty
    scaling = unit_scaling(derive(doughty.build()))
    assert scaling.force == (2, 1, -2)
    assert scaling.parameters[0] == (1, 0, 0) and scaling.parameters[6] == (0, 1, -2)
    x, y = sp.symbols("x y", positive=True)
    assert _dimension_of([x, y], (), [x * y, 2 * x * y], ((1, 0, 0), (0, 1, 0))) == (1, 1, 0)
    assert _dimension_of([x, y], (), [x + y], ((1, 0, 0), (0, 1, 0))) is None
    assert _power_of_two(3) is None and _power_of_two(0.125) == -3


@pytest.mark.parametrize("unit, expected", [
    ("m", (1, 0, 0)), ("N m s/rad", (2, 1, -1)), ("m/s^2", (1, 0, -2)), ("kg m**2", (2, 1, 0)),
    ("1", (0, 0, 0)), ("N/m", (0, 1, -2)), ("furlong", None), ("m/s/s", None)])
def test_units_are_read_as_model_files_write_them(unit, expected):
    assert dimension(unit) == expected
