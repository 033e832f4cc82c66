"""Every shipped mechanism through the same checks (issue 8), none of them typed in.

For each mechanism of ``codegen.compiler.model.SHIPPED``:
(a) every compiled function equals its symbolic expression evaluated at 40 digits (sigma:
    exactly, in rationals), to 1e-12 relative or its rounding bound where it cancels;
(b) positions from ``dependent_state`` close the loops (f(q) = 0, A qdot = 0), and the
    potential energies they give equal the independent references' (tests/reference_
    mechanisms.py: a numerical position analysis that shares nothing with the derivation);
(c) G and K = dG/dtheta equal the references' derivative of the potential;
(d) the reduced equation equals Lagrange's equations with multipliers solved in full;
(e) without damping and loads, integrating the reduced equation conserves the energy;
(f) sigma is, exactly, (1+tau^2)^w times the product of the numerator of G over every
    branch of the square roots, divided by the denominator factors the derivation removed;
(g) the analysis finds exactly the references' equilibria of the declared assembly mode
    (genuine) and of the other mode, at the example values, at random sets, at limit
    positions (a slider-crank whose crank cannot turn, a non-Grashof four-bar).
Doughty's own suites (paper forms, Table 3, hypothesis runs) stay where they are.
"""
from __future__ import annotations

import functools
import math
import os
import sys
from dataclasses import dataclass

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from codegen.api import load
from codegen.compiler.derivation import derive
from codegen.compiler.derivation.equilibrium import common_numerator, on_branch
from codegen.compiler.emission.plan import build_plan, written_out
from codegen.compiler.model import SHIPPED
from codegen.compiler.model import load as load_model

try:
    import reference_mechanisms as rm
    import sampling
except ImportError:  # pytest's importlib mode: the tests folder is not on the path
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "support"))
    import reference_mechanisms as rm
    import sampling

U = 2.0**-53
SEED = 20_240_611


@dataclass(frozen=True)
class Spec:
    """What the tests need to know of a mechanism beyond its library."""

    damping: tuple[str, ...]             # parameters that dissipate
    loads: tuple[str, ...]               # applied forces and torques


SPECS = {
    "doughty": Spec(damping=("b",), loads=("F",)),
    "slider_crank": Spec(damping=("b",), loads=("F", "T")),
    "four_bar": Spec(damping=("b",), loads=("T",)),
    "torsion_pendulum": Spec(damping=("c",), loads=("F_x",)),
}
NAMES = list(SHIPPED)


def test_every_shipped_mechanism_is_covered():
    assert sorted(SPECS) == sorted(NAMES) == sorted(rm.REFERENCES)


@functools.lru_cache(maxsize=None)
def _library(name):
    return load(name)


@functools.lru_cache(maxsize=None)
def _derivation(name):
    return derive(load_model(name))


@functools.lru_cache(maxsize=None)
def _plan(name):
    return build_plan(_derivation(name))


def _symbols(name):
    return [sp.Symbol(n, real=True) for n in _library(name).PARAMETER_NAMES]


def _near_example(name, rng, sd=0.1):
    """The example with every parameter scaled by a factor around 1 (zeros drawn)."""
    lib = _library(name)
    return lib.Params(**sampling.near_example(lib, rng, sd))


def _random_sets(name, rng, count):
    """Sets near the example whose mechanism assembles at every angle (dependent_state OK)."""
    lib, sets = _library(name), []
    grid = np.linspace(-math.pi, math.pi, 73)
    while len(sets) < count:
        p = _near_example(name, rng)
        _, status = lib.dependent_state.batch(lib.params_array([p] * grid.size), grid,
                                              np.zeros_like(grid), raise_on_error=False)
        if np.all(status == 0):
            sets.append(p)
    return sets


def _as_dict(p):
    return {n: float(getattr(p, n)) for n in type(p)._fields} if hasattr(type(p), "_fields") \
        else {n: float(getattr(p, n)) for n in p.__dataclass_fields__}


def _theta_index(name):
    """Which coordinate is theta (dependent_state returns it as given)."""
    lib = _library(name)
    coords, _ = lib.dependent_state(lib.example_params(), 0.4321, 0.0)
    (index,) = np.flatnonzero(np.asarray(coords) == 0.4321)
    return int(index)


def _angles(name, rng, count):
    lo, hi = rm.REFERENCES[name].theta_range(_as_dict(_library(name).example_params()))
    return rng.uniform(lo, hi, count)


# --------------------------------------------------------------------------- (a)


def _plan_cases():
    """From the compiled libraries (cheap at collection; the plan is derived in the test,
    and test_plan_and_library_agree ties the two together)."""
    return [(n, f) for n in NAMES for f in sorted(_library(n).FUNCTIONS)]


@pytest.mark.parametrize("name", NAMES)
def test_plan_and_library_agree(name):
    assert sorted(f.name for f in _plan(name).functions) == sorted(_library(name).FUNCTIONS)


def _states(name, rng, table):
    """(theta, theta_d, coords, rates, accels, multipliers): half on the mechanism, half
    with coordinates and rates perturbed off it."""
    lib = _library(name)
    n = len(table)
    theta = _angles(name, rng, n)
    theta_d = rng.normal(0.0, 3.0, n)
    coords, rates = (np.array(a).reshape(n, -1) for a in lib.dependent_state(table, theta,
                                                                             theta_d))
    off = np.arange(n) >= n // 2
    coords[off] *= 1 + 0.2 * rng.standard_normal(coords[off].shape)
    rates[off] += rng.normal(0.0, 2.0, rates[off].shape)
    size = coords.shape[1]
    multipliers = len(_derivation(name).state.multipliers)
    return dict(theta=theta, theta_d=theta_d, coords=coords, rates=rates,
                accels=rng.normal(0.0, 30.0, (n, size)),
                multipliers=rng.normal(0.0, 100.0, (n, multipliers)))


def _exact_program(function, param_values):
    """A function with a straight-line program (sigma), evaluated exactly in rationals."""
    values = {sp.Symbol(n, real=True): sp.Rational(v) for n, v in param_values.items()}
    for symbol, definition in function.definitions:
        values[symbol] = definition.xreplace(values)
    return [sp.Rational(e.xreplace(values)) for out in function.outputs for e in out.exprs]


@functools.lru_cache(maxsize=None)
def _rounding_bound(bound_class, symbols: tuple, definitions: tuple, outputs: tuple):
    """The rounding bound of outputs written out in the inputs, once per program: sigma and
    sigma_fast share one, which takes minutes to write out for the four-bar."""
    return bound_class(symbols, written_out(definitions, outputs))


@pytest.mark.parametrize("name, function_name", _plan_cases(),
                         ids=[f"{n}-{f}" for n, f in _plan_cases()])
def test_compiled_equals_symbolic(name, function_name, mp_compile, rounding_bound):
    lib, function = _library(name), _plan(name).function(function_name)
    rng = np.random.default_rng([SEED, NAMES.index(name), len(function_name)])
    count = 8 if function.definitions else 40
    params = [lib.example_params()] + _random_sets(name, rng, count - 1)
    table = lib.params_array(params)
    states = _states(name, rng, table)
    arrays = [states[a.name] for a in function.inputs]
    result, status = lib.FUNCTIONS[function_name].batch(table, *arrays, raise_on_error=False)
    assert np.all(status == 0), status
    parts = result if isinstance(result, tuple) else (result,)
    compiled = np.hstack([np.asarray(p).reshape(count, -1) for p in parts])

    symbols = list(_symbols(name))
    columns = [table[n] for n in lib.PARAMETER_NAMES]
    for arg, array in zip(function.inputs, arrays):
        cols = array.reshape(count, -1).T
        assert len(cols) == len(arg.symbols)
        symbols += list(arg.symbols)
        columns += list(cols)
    outputs = tuple(e for out in function.outputs for e in out.exprs)
    bound = _rounding_bound(rounding_bound, tuple(symbols), function.definitions, outputs)
    assert compiled.shape == (count, len(outputs))
    _, bounds = bound(*columns)
    exact_fn = None if function.definitions else mp_compile(symbols, list(outputs), dps=40)

    failures = []
    for i in range(count):
        if function.definitions:
            exact = _exact_program(function, {n: table[n][i] for n in lib.PARAMETER_NAMES})
            exact = [mpmath.mpf(x.p) / x.q for x in exact]
        else:
            exact = exact_fn(*(float(c[i]) for c in columns))
        for j, x in enumerate(exact):
            error = float(abs(mpmath.mpf(compiled[i, j]) - x))
            tol = 1e-12 * float(abs(x)) + 4.0 * bounds[j, i]
            if function.arithmetic == "double-double":  # whatever the cancellation: ~1 ulp
                tol = 4 * U * float(abs(x))
            if not error <= tol:
                failures.append((i, j, compiled[i, j], float(x), error, tol))
    assert not failures, f"{len(failures)} mismatches, first {failures[0]}"


# --------------------------------------------------------------------------- (b), (c)


@pytest.mark.parametrize("name", [n for n in NAMES
                                  if _library(n).SPEC["sizes"]["N_CONSTRAINTS"]])
def test_dependent_state_closes_the_loops(name, rounding_bound):
    lib, d = _library(name), _derivation(name)
    rng = np.random.default_rng([SEED, 2, NAMES.index(name)])
    params = _random_sets(name, rng, 8)
    table = lib.params_array([p for p in params for _ in range(8)])
    theta = _angles(name, rng, len(table))
    theta_d = rng.normal(0.0, 3.0, len(table))
    coords, rates = lib.dependent_state(table, theta, theta_d)
    f = lib.position_constraints(table, coords)
    A = lib.constraint_jacobian(table, coords).reshape(len(table), -1, coords.shape[1])
    A_qdot = np.einsum("nij,nj->ni", A, rates)
    symbols = list(d.state.coords) + list(d.state.rates) + _symbols(name)
    columns = list(coords.T) + list(rates.T) + [table[n] for n in lib.PARAMETER_NAMES]
    f_scale = _scale(rounding_bound, d.frozen(d.kinematics.constraints), symbols, columns)
    v_scale = _scale(rounding_bound, d.frozen(d.kinematics.velocity_constraints), symbols,
                     columns)
    assert np.all(np.abs(f) <= 1e-13 * f_scale), np.max(np.abs(f) / f_scale)
    assert np.all(np.abs(A_qdot) <= 1e-13 * v_scale), np.max(np.abs(A_qdot) / v_scale)
    # not vacuous: a coordinate 1 % off leaves a residual far above the tolerance
    off = coords.copy()
    off[:, _theta_index(name)] *= 1.01
    assert np.max(np.abs(lib.position_constraints(table, off)) / f_scale) > 1e-6


def _scale(rounding_bound, matrix, symbols, columns):
    _, bound = rounding_bound(symbols, list(matrix))(*columns, input_rel=U)
    return bound.T / U


@pytest.mark.parametrize("name", NAMES)
def test_potential_energies_equal_the_reference(name):
    """V_G and V_E at the compiled positions against the reference's own position analysis."""
    lib, ref = _library(name), rm.REFERENCES[name]
    rng = np.random.default_rng([SEED, 3, NAMES.index(name)])
    for p in [lib.example_params()] + _random_sets(name, rng, 5):
        for theta in _angles(name, rng, 6):
            coords, rates = lib.dependent_state(p, theta, 0.0)
            e = lib.energies(p, coords, rates)
            terms = ref.potential_terms(_as_dict(p), theta)
            scale = float(sum(abs(v) for v in terms.values()))
            assert abs(e.V_G - float(terms["gravity"])) <= 1e-12 * scale, (theta, e, terms)
            assert abs(e.V_E - float(terms["spring"])) <= 1e-12 * scale, (theta, e, terms)
            assert e.T == 0.0


@pytest.mark.parametrize("name", NAMES)
def test_static_force_and_stiffness_are_the_references_derivatives(name):
    """G(theta) = dV/dtheta and K = dG/dtheta, against the reference potential at 30 digits."""
    lib, ref = _library(name), rm.REFERENCES[name]
    rng = np.random.default_rng([SEED, 4, NAMES.index(name)])
    h = mpmath.mpf("1e-12")
    for p in [lib.example_params()] + _random_sets(name, rng, 4):
        pd = _as_dict(p)
        for theta in _angles(name, rng, 5):
            g, scale = lib.equilibrium_residual(p, theta)
            reference = ref.generalized_force(pd, theta)
            assert abs(g - float(reference)) <= 1e-12 * scale, (theta, g, reference)
            _, _, k = lib.linearisation(p, theta)
            with mpmath.workdps(40):
                dg = (ref.generalized_force(pd, mpmath.mpf(theta) + h)
                      - ref.generalized_force(pd, mpmath.mpf(theta) - h)) / (2 * h)
            assert abs(k - float(dg)) <= 1e-9 * (abs(float(dg)) + scale), (theta, k, dg)


# --------------------------------------------------------------------------- (d)


def _affine_columns(evaluate, args, slot, size, step=2.0**10):
    """F(x) affine in args[slot]: F(0) and the columns of its linear part."""
    args = list(args)
    args[slot] = np.zeros(size)
    f0 = np.asarray(evaluate(*args), dtype=float)
    cols = []
    for j in range(size):
        args[slot] = np.eye(size)[j] * step
        cols.append((np.asarray(evaluate(*args), dtype=float) - f0) / step)
    return f0, np.column_stack(cols) if cols else np.zeros((f0.size, 0))


def _lagrange_solution(name, p, theta, theta_d):
    """Solve Lagrange's equations with multipliers and the acceleration constraints."""
    lib = _library(name)
    coords, rates = lib.dependent_state(p, theta, theta_d)
    n, m = coords.size, len(_derivation(name).state.multipliers)

    def residual(accels, multipliers):
        extra = (multipliers,) if m else ()
        return lib.lagrange_terms(p, coords, rates, accels, *extra).residual

    c0, M = _affine_columns(residual, [np.zeros(n), np.zeros(m)], 0, n)
    blocks, rhs = [M], [c0]
    if m:
        _, At = _affine_columns(residual, [np.zeros(n), np.zeros(m)], 1, m)
        a0, A = _affine_columns(lambda a: lib.acceleration_constraints(p, coords, rates, a),
                                [np.zeros(n)], 0, n)
        system = np.block([[M, At], [A, np.zeros((m, m))]])
        rhs = -np.concatenate([c0, a0])
    else:
        system, rhs = M, -c0
    rows = 1.0 / np.max(np.abs(system), axis=1)
    system, rhs = system * rows[:, None], rhs * rows
    cols = 1.0 / np.max(np.abs(system), axis=0)
    return np.linalg.solve(system * cols[None, :], rhs) * cols


@pytest.mark.parametrize("name", NAMES)
def test_reduced_equation_matches_lagrange_with_multipliers(name):
    lib = _library(name)
    rng = np.random.default_rng([SEED, 5, NAMES.index(name)])
    index = _theta_index(name)
    for p in [lib.example_params()] + _random_sets(name, rng, 4):
        for theta, theta_d in zip(_angles(name, rng, 4), rng.normal(0.0, 3.0, 4)):
            full = _lagrange_solution(name, p, theta, theta_d)[index]
            reduced = lib.angular_acceleration(p, theta, theta_d)
            e = lib.reduced_coefficients(p, theta)
            size = (abs(e[1]) * theta_d**2 + abs(e[2] * theta_d)
                    + lib.equilibrium_residual(p, theta).scale) / e[0]
            assert abs(full - reduced) <= 1e-9 * size, (theta, theta_d, full, reduced)
    # not vacuous: a different load changes theta_ddot
    p = lib.example_params()
    load = SPECS[name].loads[0]
    q = lib.example_params(**{load: getattr(p, load) + 1.0})
    assert abs(lib.angular_acceleration(p, 0.3, 0.2) - lib.angular_acceleration(q, 0.3, 0.2)) > 1e-6


# --------------------------------------------------------------------------- (e)


@pytest.mark.parametrize("name", NAMES)
def test_energy_is_conserved_without_damping_and_loads(name):
    lib = _library(name)
    rng = np.random.default_rng([SEED, 6, NAMES.index(name)])
    zero = {n: 0.0 for n in SPECS[name].damping + SPECS[name].loads}
    sets = [lib.Params(**{**_as_dict(p), **zero})
            for p in [lib.example_params()] + _random_sets(name, rng, 5)]
    table = lib.params_array(sets)
    count = len(sets)
    theta = _angles(name, rng, count)
    theta_d = rng.normal(0.0, 2.0, count)

    def energy(th, thd):
        e = lib.energies(table, *lib.dependent_state(table, th, thd))
        return e.T + e.V_G + e.V_E, np.abs(e.T) + np.abs(e.V_G) + np.abs(e.V_E), e.T

    grid = np.linspace(-math.pi, math.pi, 91)
    M, _, K = lib.linearisation(np.repeat(table, grid.size), np.tile(grid, count))
    rate = np.sqrt(np.max(np.abs(K / M).reshape(count, -1), axis=1)) + 4 * np.abs(theta_d)
    dt = 0.01 / rate
    energies, kinetic = [], []
    E, scale, T = energy(theta, theta_d)
    for step in range(1500):
        def f(th, thd):
            return thd, lib.angular_acceleration(table, th, thd)
        k1 = f(theta, theta_d)
        k2 = f(theta + dt / 2 * k1[0], theta_d + dt / 2 * k1[1])
        k3 = f(theta + dt / 2 * k2[0], theta_d + dt / 2 * k2[1])
        k4 = f(theta + dt * k3[0], theta_d + dt * k3[1])
        theta = theta + dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        theta_d = theta_d + dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        if step % 100 == 99:
            E_now, s, T_now = energy(theta, theta_d)
            energies.append(E_now)
            kinetic.append(T_now)
            scale = np.maximum(scale, s)
    drift = np.max(np.abs(np.array(energies) - E), axis=0) / scale
    assert np.all(drift < 1e-8), drift
    swing = (np.max(kinetic, axis=0) - np.min(kinetic, axis=0)) / scale
    assert np.median(swing) > 1e-2, swing   # energy did move between its forms


def test_energy_check_detects_damping():
    lib = _library("slider_crank")
    p = lib.example_params(F=0.0, T=0.0)
    coords, rates = lib.dependent_state(p, 0.3, 4.0)
    # the damper's power -b v^2 is negative: d/dt(T + V) < 0 along any motion with v != 0
    e0 = lib.energies(p, coords, rates)
    th, thd, dt = 0.3, 4.0, 1e-5
    thd2 = thd + dt * lib.angular_acceleration(p, th, thd)
    e1 = lib.energies(p, *lib.dependent_state(p, th + dt * thd, thd2))
    assert (e1.T + e1.V_G + e1.V_E) < (e0.T + e0.V_G + e0.V_E)


# --------------------------------------------------------------------------- (f)


@functools.lru_cache(maxsize=None)
def _branch_product(name):
    """(1+tau^2)^w prod_b N_b / prod D^k as an mpmath function of (params..., theta)."""
    d = _derivation(name)
    eq = d.equilibrium
    numerator, _ = common_numerator(d.reduction.static_terms)
    product = sp.S.One
    for branch in eq.branches:
        product *= on_branch(numerator, eq.roots, branch.signs)
    for factor, power in eq.polynomial.divided:
        product /= factor**power
    theta = d.reduction.theta
    product *= (2 / (1 + sp.cos(theta)))**eq.polynomial.weight  # 1 + tau^2
    return sp.lambdify(_symbols(name) + [theta], product, modules="mpmath")


@pytest.mark.parametrize("name", [n for n in NAMES if _library(n).has_polynomial])
def test_sigma_is_the_product_of_the_branches(name):
    lib = _library(name)
    plan_sigma = _plan(name).function("sigma")
    rng = np.random.default_rng([SEED, 7, NAMES.index(name)])
    product = _branch_product(name)
    for p in [lib.example_params()] + _random_sets(name, rng, 2):
        values = _as_dict(p)
        sigma = _exact_program(plan_sigma, values)
        ratios = []
        for theta in rng.uniform(-3.0, 3.0, 5):
            with mpmath.workdps(60):
                tau = mpmath.tan(mpmath.mpf(theta) / 2)
                poly = mpmath.fsum(mpmath.mpf(s.p) / s.q * tau**i for i, s in enumerate(sigma))
                ratios.append(poly / product(*(mpmath.mpf(v) for v in values.values()),
                                             mpmath.mpf(theta)))
        # the same constant at every angle: +-1, or a positive scale if the
        # derivation normalised it
        for r in ratios[1:]:
            assert abs(r / ratios[0] - 1) < mpmath.mpf(10) ** -40, ratios
        assert abs(abs(ratios[0]) - 1) < mpmath.mpf(10) ** -40, ratios[0]


# --------------------------------------------------------------------------- (g)


def _reported(analysis):
    by_kind = {}
    for r in analysis.roots:
        by_kind.setdefault(r.kind, []).append(r.theta)
    return by_kind


def _assert_same_angles(found, expected, what, tol=1e-8):
    found, expected = sorted(found), sorted(expected)
    assert len(found) == len(expected), (what, np.degrees(found), np.degrees(expected))
    for a, b in zip(found, expected):
        assert abs(math.remainder(a - b, 2 * math.pi)) <= tol, (what, np.degrees(found),
                                                               np.degrees(expected))


def _check_equilibria(name, p):
    lib, ref = _library(name), rm.REFERENCES[name]
    values = _as_dict(p)
    analysis = lib.analyze(p)
    reported = _reported(analysis)
    _assert_same_angles(reported.get("equilibrium", []), ref.equilibria(values, +1),
                        "declared mode")
    if -1 in ref.MODES:
        _assert_same_angles(reported.get("other assembly mode", []),
                            ref.equilibria(values, -1), "other mode")
    # Each vibrates as its own mode: K is the slope of that mode's G.
    h = mpmath.mpf("1e-15")
    for root in analysis.roots:
        mode = {"equilibrium": +1, "other assembly mode": -1}.get(root.kind)
        if mode is None:
            continue
        with mpmath.workdps(50):
            t = mpmath.mpf(root.theta)
            slope = (ref.generalized_force(values, t + h, mode)
                     - ref.generalized_force(values, t - h, mode)) / (2 * h)
        assert abs(root.K - float(slope)) <= 1e-7 * abs(float(slope)) + 1e-9, (
            root.kind, math.degrees(root.theta), root.K, slope)
        assert root.M > 0 and (root.stability == "unstable") == (root.K < 0)
    return analysis


ALGEBRAIC = [n for n in NAMES if _library(n).has_polynomial]


@pytest.mark.parametrize("name", ALGEBRAIC)
def test_example_equilibria_match_the_reference(name):
    analysis = _check_equilibria(name, _library(name).example_params())
    assert not analysis.singular and not analysis.unassembled


@pytest.mark.parametrize("name", [n for n in ALGEBRAIC if n != "doughty"])
@settings(max_examples=12, deadline=None, database=None, derandomize=True)
@given(seed=st.integers(0, 2**32 - 1))
def test_random_sets_match_the_reference(name, seed):
    (p,) = [_near_example(name, np.random.default_rng([SEED, 8, seed]), sd=0.25)]
    _check_equilibria(name, p)


#: (mechanism, changes from the example): limited mechanisms, where both modes meet
LIMITS = [
    # l < R + |e|: the crank cannot turn
    ("slider_crank", dict(l=0.1)), ("slider_crank", dict(l=0.09, e=0.03, F=10.0)),
    ("slider_crank", dict(l=0.11, x_S=0.2)),
    # s + l > p + q: non-Grashof, the crank rocks between limit positions
    ("four_bar", dict(a_2=0.3)), ("four_bar", dict(a_2=0.28, a_3=0.3, T=2.0)),
    ("four_bar", dict(d=0.5, a_2=0.25)),
]


@pytest.mark.parametrize("name, changes", LIMITS, ids=[f"{n}-{i}" for i, (n, _) in
                                                       enumerate(LIMITS)])
def test_limit_positions_match_the_reference(name, changes):
    lib, ref = _library(name), rm.REFERENCES[name]
    p = lib.example_params(**changes)
    grid = np.linspace(-math.pi, math.pi, 721)
    assert not all(ref.assembles(_as_dict(p), t) for t in grid)   # a limited mechanism
    _check_equilibria(name, p)


def test_torsion_pendulum_has_no_polynomial_but_its_vibration():
    """Its G holds theta itself: no polynomial (issue 9 isolates its roots), but M, B, K and
    theta_ddot at any angle are compiled and checked above."""
    lib = _library("torsion_pendulum")
    assert _derivation("torsion_pendulum").equilibrium.polynomial is None
    assert not lib.has_polynomial
    ref = rm.REFERENCES["torsion_pendulum"]
    for theta in ref.equilibria(None):
        m, b, k = lib.linearisation(lib.example_params(), theta)
        assert abs(lib.equilibrium_residual(lib.example_params(), theta).residual) < 1e-12
        assert m > 0 and b == lib.example_params().c


@pytest.mark.parametrize("name, changes", [
    ("slider_crank", dict(R=1e-308, m_2=1e308, m_3=0.0)),   # M = 0 at every root
    ("doughty", dict(m_A=1e308, b=1e308)),                  # B^2 and M K overflow
], ids=["no-inertia", "overflow"])
def test_extreme_accepted_parameters_never_give_nan_behind_ok(name, changes):
    """Found by the sanitizer driver over random seeds: the analysis returned OK with NaN in
    zeta or the eigenvalues (the eigenvalues are now computed from B/M and K/M). NaN only
    where documented: a root without inertia (M = 0; statics need none) has no natural
    frequency, damping ratio or eigenvalues, and its stability comes from K and B."""
    lib = _library(name)
    try:
        analysis = lib.analyze(lib.example_params(**changes))
    except ValueError:  # a status naming the problem is an acceptable answer
        return
    for r in analysis.roots:
        assert not any(math.isnan(v) for v in (r.M, r.B, r.K)) and r.M >= 0, r
        vibration = [r.omega_n.real, r.omega_n.imag, r.zeta.real, r.zeta.imag,
                     *(z.real for z in r.eigenvalues), *(z.imag for z in r.eigenvalues)]
        if r.M == 0:
            assert all(math.isnan(v) for v in vibration) and r.damping == "none", r
            assert r.stability == ("unstable" if r.K < 0 else
                                   "stable" if r.K > 0 and r.B > 0 else "marginal"), r
        else:
            assert not any(math.isnan(v) for v in vibration), r
