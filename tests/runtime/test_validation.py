"""Bad input: every status code, from C, Python and the command line; valid edge cases."""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from codegen.api import load

api = load("doughty")
ffi, lib = api.ffi, api.lib
from codegen.runtime.analysis import analyze

SENTINEL = 12345.678

# One violation per requirement code: (overrides, code, parameter named in the error)
VIOLATIONS = [
    ({"L": 0.0}, "ERR_L_NOT_POSITIVE", "L"),
    ({"L": -0.9}, "ERR_L_NOT_POSITIVE", "L"),
    ({"a": -0.01}, "ERR_A_OUT_OF_RANGE", "a"),
    ({"a": 0.95}, "ERR_A_OUT_OF_RANGE", "a"),
    ({"l_ND": -0.1}, "ERR_L_ND_NEGATIVE", "l_ND"),
    ({"m_B": -1.0}, "ERR_MASS_NEGATIVE", "m_B"),
    ({"k": -1.0}, "ERR_K_NEGATIVE", "k"),
    ({"b": -875.0}, "ERR_B_NEGATIVE", "b"),
]


def _c_params(**overrides):
    return api._c_params(api.example_params(**overrides))


def test_every_status_has_a_distinct_message():
    messages = {ffi.string(lib.doughty_status_message(v)).decode() for v in api.STATUS.values()}
    assert len(messages) == len(api.STATUS)
    assert ffi.string(lib.doughty_status_message(999)).decode() == "unknown status code"


@pytest.mark.parametrize("overrides, code, name", VIOLATIONS)
def test_requirement_codes_from_c_python_and_cli(overrides, code, name):
    assert lib.doughty_check_params(_c_params(**overrides)) == api.STATUS[code]
    out = ffi.new("double[13]", [SENTINEL] * 13)
    assert lib.doughty_sigma(_c_params(**overrides), out) == api.STATUS[code]
    assert list(out) == [SENTINEL] * 13  # outputs untouched on failure
    with pytest.raises(ValueError, match=name) as error:
        api.sigma(api.example_params(**overrides))
    assert error.value.code == code
    _cli_fails([f"--set={k}={v}" for k, v in overrides.items()], name)


@pytest.mark.parametrize("name", api.PARAMETER_NAMES)
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_nonfinite_parameter_is_named(name, value):
    assert lib.doughty_check_params(_c_params(**{name: value})) == api.STATUS["ERR_NONFINITE_PARAM"]
    with pytest.raises(ValueError, match=rf"^{name}: .*NaN or infinite"):
        analyze(api.example_params(**{name: value}))


def _cli_fails(args, name):
    result = subprocess.run([sys.executable, "-m", "codegen", "analyze", *args],
                            capture_output=True, text=True)
    assert result.returncode != 0
    assert len(result.stderr.strip().splitlines()) == 1 and name in result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""


def test_cli_nonfinite_parameter():
    _cli_fails(["--set", "g=inf"], "g")


def test_nonfinite_state_and_null_pointers():
    p = _c_params()
    out, scale = ffi.new("double *", SENTINEL), ffi.new("double *", SENTINEL)
    residual = lib.doughty_equilibrium_residual
    assert residual(p, math.nan, out, scale) == api.STATUS["ERR_NONFINITE"]
    assert out[0] == SENTINEL and scale[0] == SENTINEL
    assert residual(ffi.NULL, 0.1, out, scale) == api.STATUS["ERR_NULL_POINTER"]
    assert residual(p, 0.1, ffi.NULL, scale) == api.STATUS["ERR_NULL_POINTER"]
    assert residual(p, 0.1, out, ffi.NULL) == api.STATUS["ERR_NULL_POINTER"]
    assert lib.doughty_analyze(p, ffi.NULL) == api.STATUS["ERR_NULL_POINTER"]
    coords = np.array([0.9, 0.0, math.inf, 0.0, 0.0])
    with pytest.raises(ValueError, match="NaN or infinite"):
        api.position_constraints(api.example_params(), coords)


def test_zero_spring_length_is_reported_not_nan():
    # H = a puts P on O' at theta = 0: r = 0 and the spring's direction is undefined.
    p = api.example_params(H=0.135)
    with pytest.raises(ValueError, match="spring length r is zero") as error:
        api.reduced_coefficients(p, 0.0)
    assert error.value.code == "ERR_SINGULAR_STATE"
    out = ffi.new("double[5]", [SENTINEL] * 5)
    assert lib.doughty_reduced_coefficients(api._c_params(p), 0.0, out) == \
        api.STATUS["ERR_SINGULAR_STATE"]
    assert list(out) == [SENTINEL] * 5


def test_zero_polynomial_is_reported():
    theta = ffi.new("double[12]", [SENTINEL] * 12)
    n = ffi.new("int *", -1)
    status = lib.doughty_poly_real_roots(ffi.new("double[13]"), theta, n)
    assert status == api.STATUS["ERR_ZERO_POLYNOMIAL"] and n[0] == -1


def test_batch_reports_the_failing_item():
    table = api.params_array([api.example_params(), api.example_params(b=-1.0)])
    with pytest.raises(ValueError, match=r"b: .*batch item 1"):
        api.sigma(table)
    values, statuses = api.FUNCTIONS["sigma"].batch(table, raise_on_error=False)
    assert list(statuses) == [0, api.STATUS["ERR_B_NEGATIVE"]]


@pytest.mark.parametrize("method", ["polynomial", "isolate"])
@pytest.mark.parametrize("masses", [dict(m_C=0.0, m_A=0.0), dict(m_C=0.0, m_B=0.0),
                                    dict(m_A=0.0, m_B=0.0, m_C=0.0)], ids=str)
def test_statics_need_no_inertia(masses, method):
    """Issue 9: m_C = 0 with m_A = 0 or m_B = 0 was refused (ERR_MASS_SINGULAR), though the
    equilibria do not depend on the masses. Now they are found, the same as with inertia, and
    omega_n, zeta are NaN exactly where M = 0."""
    with_inertia = analyze(api.example_params(g=0.0), method)
    without = analyze(api.example_params(g=0.0, **masses), method)
    assert [r.theta for r in without.equilibria] == pytest.approx(
        [r.theta for r in with_inertia.equilibria], abs=1e-12)
    for r in without.equilibria:
        assert math.isnan(r.omega_n.real) == (r.M == 0.0)
        assert math.isnan(r.zeta.real) == (r.M == 0.0)
        assert r.stability == ("unstable" if r.K < 0 else "stable" if r.K > 0 and r.B > 0
                               else r.stability)


@pytest.mark.parametrize("overrides", [
    {"k": 0.0}, {"b": 0.0}, {"F": 0.0}, {"g": 0.0}, {"H": 0.0}, {"H": -0.3}, {"m_C": 0.0},
    {"a": 0.0}, {"a": 0.9}, {"l_ND": 0.0}, {"F": (0.143 + 9.124 / 2) * 9.81},
])
def test_valid_edge_cases_work_without_nan(overrides):
    result = analyze(api.example_params(**overrides))
    assert result.roots, "every listed case has equilibria"
    for r in result.roots:
        values = [r.theta, r.M, r.B, r.K, r.residual, r.relative_residual,
                  *(abs(z) for z in (r.omega_n, *r.eigenvalues))]
        assert all(math.isfinite(v) for v in values), r
        assert not math.isnan(r.zeta.real) and not math.isnan(r.zeta.imag)
    assert result.equilibria


def test_overflow_is_reported_not_inf():
    out = ffi.new("double[13]", [SENTINEL] * 13)
    status = lib.doughty_sigma(_c_params(k=1e300), out)
    assert status == api.STATUS["ERR_OVERFLOW"] and list(out) == [SENTINEL] * 13
    with pytest.raises(ValueError, match="too large"):
        analyze(api.example_params(H=1e200))
    _cli_fails(["--set", "H=1e200"], "too large")


def test_a_stiffness_of_1e300_is_answered_where_its_results_fit():
    """k = 1e300 N/m: K ~ 5e299 N m fits a double. sigma (~ k^2) does not, so the analysis
    takes the isolation's route, in units where the forces are near 1 (it overflowed)."""
    result = analyze(api.example_params(k=1e300))
    assert len(result.equilibria) == 6 and all(e.certified for e in result.equilibria)
    assert all(math.isfinite(e.K) and abs(e.K) > 1e299 for e in result.equilibria)


def test_neutral_mechanism_says_every_angle_is_an_equilibrium():
    # H = 0, a = L/2: r = L/2 at every angle and P = 0, so with no load G vanishes identically
    p = api.example_params(H=0.0, a=0.45, F=0.0, g=0.0)
    with pytest.raises(ValueError, match="every angle is an equilibrium") as error:
        analyze(p)
    assert error.value.code == "ERR_EVERY_ANGLE"
    _cli_fails(["--set", "H=0", "--set", "a=0.45", "--set", "F=0", "--set", "g=0"],
               "every angle")
