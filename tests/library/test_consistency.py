"""The compiled functions agree with each other the way the mechanics says they must.

(a) states from ``dependent_state`` satisfy f(q) = 0 and A qdot = 0, and the acceleration
    constraints vanish for qddot built from the reduced angular acceleration;
(b) the reduced equation of motion equals Lagrange's equations with multipliers solved
    for the accelerations and multipliers;
(c) the sigma polynomial equals (1+tau^2)^6 times the product of the two branches;
(d) G(theta) = e3 sin(theta) + e4 cos(theta) with the paper's e3, e4 (typed in below);
(e) without damping, integrating the reduced equation conserves the energy.

Nothing here compares a function with its own expression: each check ties two different
derivations together (and (a) uses the paper's closed-form q(theta), typed in below).
"""
from __future__ import annotations

import math
from dataclasses import asdict

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from codegen.api import load

api = load("doughty")

U = 2.0**-53
HYPOTHESIS = settings(max_examples=50, deadline=None, database=None, derandomize=True)
seeds = st.integers(min_value=0, max_value=2**32 - 1)
angles = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)
ANGLES_PER_EXAMPLE = 16
THETA = 3  # index of theta among the coordinates p, q, r, theta, phi


def _angles(seed: int, theta0: float) -> np.ndarray:
    """theta0 (from hypothesis) and a spread of other angles from the same seed."""
    extra = np.random.default_rng(seed).uniform(-math.pi, math.pi, ANGLES_PER_EXAMPLE - 1)
    return np.concatenate([[theta0], extra])


def _rates(seed: int, count: int) -> np.ndarray:
    rng = np.random.default_rng([seed, 1])
    return rng.normal(0.0, 4.0, count) * np.exp(rng.uniform(-2.0, 1.0, count))


# ------------------------------------------------------------------- paper's q(theta)

_sym = {n: sp.Symbol(n, real=True) for n in api.PARAMETER_NAMES}
_theta = sp.Symbol("theta", real=True)


def _paper_positions():
    """(30), (31), (34) and phi from f1, f4: tan(phi) = (L - a) sin / (H - a cos)."""
    H, L, a = _sym["H"], _sym["L"], _sym["a"]
    th = _theta
    X, Y = H - a * sp.cos(th), (L - a) * sp.sin(th)
    return sp.Matrix([L * sp.cos(th), L * sp.sin(th), sp.sqrt(X**2 + Y**2), th, sp.atan2(Y, X)])


_Q = _paper_positions()
_S = _Q.diff(_theta)
_S2 = _S.diff(_theta)
_ARGS = [_sym["H"], _sym["L"], _sym["a"], _theta]
_S_NUM = sp.lambdify(_ARGS, list(_S), modules="mpmath")
_S2_NUM = sp.lambdify(_ARGS, list(_S2), modules="mpmath")


def _exact_accels(p, theta, theta_d, theta_dd):
    """qddot = S(theta) thetaddot + S'(theta) thetadot^2, at 30 digits, rounded once."""
    with mpmath.workdps(30):
        args = [mpmath.mpf(v) for v in (p.H, p.L, p.a, theta)]
        s, s2 = _S_NUM(*args), _S2_NUM(*args)
        td, tdd = mpmath.mpf(theta_d), mpmath.mpf(theta_dd)
        return np.array([float(x * tdd + y * td**2) for x, y in zip(s, s2)])


# ------------------------------------------------------------------- (a) constraints


def _term_scale(bound_class, exprs, symbols, columns):
    """Magnitude of the terms an expression sums, and of its sensitivity to a relative
    change u of each input: its rounding bound (inputs off by u) divided by u."""
    _, bound = bound_class(symbols, exprs)(*columns, input_rel=U)
    return bound / U


@HYPOTHESIS
@given(seed=seeds, theta0=angles)
def test_dependent_state_satisfies_constraints(seed, theta0, params_for_seed, derivation,
                                               rounding_bound):
    p = params_for_seed(seed)
    theta = _angles(seed, theta0)
    theta_d = _rates(seed, theta.size)
    table = api.params_array([p] * theta.size)
    coords, rates = api.dependent_state(table, theta, theta_d)
    np.testing.assert_array_equal(coords[:, THETA], theta)
    np.testing.assert_array_equal(rates[:, THETA], theta_d)

    f = api.position_constraints(table, coords)
    f_d = api.velocity_constraints(table, coords, rates)
    A = api.constraint_jacobian(table, coords).reshape(-1, 4, 5)
    A_qdot = np.einsum("nij,nj->ni", A, rates)

    # Each must vanish to ~1e-13 of the size of its terms and of its sensitivity to the
    # inputs' own rounding (term scale with inputs perturbed by u: phi = pi is not exact,
    # and sin(phi) = 1.2e-16 there). A wrong r, phi or rate leaves O(1) of that scale.
    state = derivation.state
    lengths = [_sym["H"], _sym["L"], _sym["a"]]
    len_cols = [np.full(theta.size, v) for v in (p.H, p.L, p.a)]
    kin = derivation.kinematics
    f_scale = _term_scale(rounding_bound, list(derivation.frozen(kin.constraints)),
                          list(state.coords) + lengths, list(coords.T) + len_cols).T
    assert np.all(np.abs(f) <= 1e-13 * f_scale), np.max(np.abs(f) / f_scale)
    fd_scale = _term_scale(rounding_bound, list(derivation.frozen(kin.velocity_constraints)),
                           list(state.coords) + list(state.rates) + lengths,
                           list(coords.T) + list(rates.T) + len_cols).T
    assert np.all(np.abs(f_d) <= 1e-13 * fd_scale), np.max(np.abs(f_d) / fd_scale)
    assert np.all(np.abs(A_qdot) <= 1e-13 * fd_scale), np.max(np.abs(A_qdot) / fd_scale)

    # Acceleration level: qddot from the compiled reduced equation and the paper's q(theta).
    theta_dd = api.angular_acceleration(table, theta, theta_d)
    accels = np.array([_exact_accels(p, t, td, tdd)
                       for t, td, tdd in zip(theta, theta_d, theta_dd)])
    f_dd = api.acceleration_constraints(table, coords, rates, accels)
    symbols = list(state.coords) + list(state.rates) + list(state.accels) + [
        _sym["H"], _sym["L"], _sym["a"]]
    columns = list(coords.T) + list(rates.T) + list(accels.T) + [
        np.full(theta.size, p.H), np.full(theta.size, p.L), np.full(theta.size, p.a)]
    exprs = list(derivation.frozen(derivation.kinematics.acceleration_constraints))
    scale = _term_scale(rounding_bound, exprs, symbols, columns).T
    assert np.all(np.abs(f_dd) <= 1e-13 * scale), np.max(np.abs(f_dd) / scale)


def test_constraint_check_is_not_vacuous():
    """A state off the mechanism (r 1% long) is caught by the same tolerances."""
    p = api.example_params()
    coords, rates = api.dependent_state(p, 0.7, 1.3)
    bad = coords.copy()
    bad[2] *= 1.01
    assert np.max(np.abs(api.position_constraints(p, bad))) > 1e-4
    rates_bad = rates.copy()
    rates_bad[2] *= 1.01
    assert np.max(np.abs(api.velocity_constraints(p, coords, rates_bad))) > 1e-4


# ------------------------------------------------------------------- (b) Lagrange


def _affine_columns(evaluate, base_args, slot, size, step=2.0**20):
    """Columns of the linear part of an affine function of argument ``slot``.

    evaluate(*args) is affine in args[slot]; the column j is (F(s e_j) - F(0)) / s. A
    large power-of-two s keeps the subtraction from eating the column when F(0) is large.
    """
    args = list(base_args)
    args[slot] = np.zeros(size)
    f0 = np.asarray(evaluate(*args))
    cols = []
    for j in range(size):
        e = np.zeros(size)
        e[j] = step
        args[slot] = e
        cols.append((np.asarray(evaluate(*args)) - f0) / step)
    return f0, np.column_stack(cols)


def _lagrange_solution(p, theta, theta_d):
    """Solve residual(qddot, lambda) = 0 and f_dd(qddot) = 0 at the state (theta, theta_d)."""
    coords, rates = api.dependent_state(p, theta, theta_d)

    def residual(accels, multipliers):
        return api.lagrange_terms(p, coords, rates, accels, multipliers).residual

    def f_dd(accels):
        return api.acceleration_constraints(p, coords, rates, accels)

    c0, M = _affine_columns(residual, [np.zeros(5), np.zeros(4)], 0, 5)
    _, At = _affine_columns(residual, [np.zeros(5), np.zeros(4)], 1, 4)
    a0, A = _affine_columns(f_dd, [np.zeros(5)], 0, 5)
    system = np.block([[M, At], [A, np.zeros((4, 4))]])
    rhs = -np.concatenate([c0, a0])
    # Equilibrate rows and columns: masses, stiffnesses and lengths span decades.
    rows = 1.0 / np.max(np.abs(system), axis=1)
    system, rhs = system * rows[:, None], rhs * rows
    cols = 1.0 / np.max(np.abs(system), axis=0)
    x = np.linalg.solve(system * cols[None, :], rhs) * cols
    return x[:5], x[5:], coords, rates


@HYPOTHESIS
@given(seed=seeds, theta0=angles)
def test_reduced_equation_matches_lagrange_with_multipliers(seed, theta0, params_for_seed):
    p = params_for_seed(seed)
    for theta, theta_d in zip(_angles(seed, theta0)[:4], _rates(seed, 4)):
        qdd, lam, coords, rates = _lagrange_solution(p, theta, theta_d)
        reduced = api.angular_acceleration(p, theta, theta_d)
        e = api.reduced_coefficients(p, theta)
        # theta_dd is a sum of terms (e1 thetadot^2, e2 thetadot, G's contributions) / e0;
        # where they cancel, compare with their magnitude instead.
        static_scale = api.equilibrium_residual(p, theta).scale
        terms = (abs(e[1]) * theta_d**2 + abs(e[2] * theta_d) + static_scale) / e[0]
        assert abs(qdd[THETA] - reduced) <= 1e-9 * max(abs(reduced), terms), (
            qdd[THETA], reduced, terms)
        # The full solution is a motion of the mechanism: the other accelerations follow.
        expected = _exact_accels(p, theta, theta_d, reduced)
        scale = (np.abs(_exact_accels(p, theta, 0.0, terms))
                 + np.abs(_exact_accels(p, theta, theta_d, 0.0)))
        # (a floor for a coordinate that does not move, e.g. phi when a = L)
        scale = scale + 1e-6 * scale.max()
        assert np.all(np.abs(qdd - expected) <= 1e-9 * scale), (qdd, expected)
        # and the multipliers balance the equations exactly (residual of the solution)
        res = api.lagrange_terms(p, coords, rates, qdd, lam)
        A = api.constraint_jacobian(p, coords).reshape(4, 5)
        forces = (np.abs(res.dt_dL_dqdot) + np.abs(res.dL_dq) + np.abs(A).T @ np.abs(lam)
                  + np.abs(res.dissipative_forces) + np.abs(res.applied_forces))
        assert np.all(np.abs(res.residual) <= 1e-9 * forces + 1e-300)


def test_lagrange_solution_detects_a_wrong_force():
    """Changing F changes the full solution's thetaddot: the check above can fail."""
    p = api.example_params()
    qdd, *_ = _lagrange_solution(p, 0.4, 0.2)
    q2, *_ = _lagrange_solution(api.example_params(F=111.0), 0.4, 0.2)
    assert abs(qdd[THETA] - q2[THETA]) > 1e-6 * abs(qdd[THETA])


# ------------------------------------------------------------------- (c) sigma


@pytest.fixture(scope="module")
def squared_mp(derivation, mp_compile):
    """r^2 G(+r) G(-r) = (alpha + beta r)(beta r - alpha), from the derivation's branches."""
    eq = derivation.equilibrium
    symbols = [_sym[n] for n in api.PARAMETER_NAMES] + [derivation.reduction.theta]
    plus, minus = (b.residual for b in eq.branches)
    return mp_compile(symbols, eq.radicands[0] * plus * minus, dps=50), eq.polynomial.weight


@HYPOTHESIS
@given(seed=seeds, theta0=angles)
def test_sigma_polynomial_is_product_of_branches(seed, theta0, params_for_seed, squared_mp):
    p = params_for_seed(seed)
    squared, weight = squared_mp
    assert weight == 6
    sigma = api.sigma(p)
    assert sigma.shape == (13,)
    theta = _angles(seed, theta0)
    table = api.params_array([p] * theta.size)
    coords, _ = api.dependent_state(table, theta, np.zeros_like(theta))
    # (alpha + beta r, beta r - alpha) = r (G(+r), G(-r))
    genuine, extraneous = (coords[:, 2] * b for b in api.equilibrium_branches(table, theta).T)
    residual = api.equilibrium_residual(table, theta).residual
    values = [getattr(p, n) for n in api.PARAMETER_NAMES]
    for i, th in enumerate(theta):
        tau = math.tan(th / 2)
        with mpmath.workdps(50):
            t = mpmath.mpf(tau)
            th_exact = 2 * mpmath.atan(t)          # the angle whose half-tangent is tau
            lift = (1 + t**2) ** weight
            exact = lift * squared(*values, th_exact)
            powers = [t**j for j in range(13)]
            poly = mpmath.fsum(mpmath.mpf(s) * w for s, w in zip(sigma, powers))
            poly_scale = mpmath.fsum(abs(mpmath.mpf(s) * w) for s, w in zip(sigma, powers))
            product = lift * mpmath.mpf(genuine[i]) * mpmath.mpf(extraneous[i])
            # (alpha + beta r)(beta r - alpha) from branches whose terms are alpha, beta r:
            branch_scale = lift * (abs(mpmath.mpf(genuine[i])) + abs(mpmath.mpf(extraneous[i])))**2
        # compiled coefficients, each to ~1e-13 of its terms, against the exact polynomial
        assert abs(poly - exact) <= 1e-12 * poly_scale, (th, float(poly), float(exact))
        # the compiled branches against the same exact value (theta vs 2 atan(tau):
        # a relative difference of ~u, amplified at most by the branch scale)
        assert abs(product - exact) <= 1e-12 * branch_scale, (th, float(product), float(exact))
        # genuine = r * G (43), with r from dependent_state
        r = coords[i, 2]
        g_scale = abs(genuine[i]) + abs(extraneous[i])
        assert abs(genuine[i] - r * residual[i]) <= 1e-13 * g_scale


def test_sigma_check_is_not_vacuous(squared_mp):
    """Perturbing one coefficient by 1e-9 of its size breaks the identity."""
    p = api.example_params()
    squared, weight = squared_mp
    sigma = api.sigma(p)
    sigma[6] *= 1 + 1e-9
    tau = 0.37
    with mpmath.workdps(50):
        t = mpmath.mpf(tau)
        exact = (1 + t**2) ** weight * squared(*(getattr(p, n) for n in api.PARAMETER_NAMES),
                                               2 * mpmath.atan(t))
        poly = sum(mpmath.mpf(s) * t**j for j, s in enumerate(sigma))
        scale = sum(abs(mpmath.mpf(s)) * t**j for j, s in enumerate(sigma))
    assert abs(poly - exact) > 1e-12 * scale


# ------------------------------------------------------------------- (d) G = e3 sin + e4 cos


@HYPOTHESIS
@given(seed=seeds, theta0=angles)
def test_static_force_is_split_into_e3_and_e4(seed, theta0, params_for_seed):
    """The derived G equals the paper's e3 sin + e4 cos, (40)-(42), typed in here."""
    p = params_for_seed(seed)
    theta = _angles(seed, theta0)
    table = api.params_array([p] * theta.size)
    G = api.equilibrium_residual(table, theta).residual
    e = api.reduced_coefficients(table, theta)
    r = np.hypot(p.H - p.a * np.cos(theta), (p.L - p.a) * np.sin(theta))
    e3 = p.k * (r - p.l_ND) * (p.H * p.a + (p.L**2 - 2 * p.L * p.a) * np.cos(theta)) / r
    e4 = (-p.F + (p.m_B + p.m_C / 2) * p.g) * p.L
    elastic, load = e3 * np.sin(theta), e4 * np.cos(theta)
    assert np.all(np.abs(G - (elastic + load)) <= 1e-13 * (np.abs(elastic) + np.abs(load)))
    # at rest, thetaddot = -G / e0
    theta_dd = api.angular_acceleration(table, theta, np.zeros_like(theta))
    assert np.all(np.abs(theta_dd * e[:, 0] + G) <= 1e-13 * (np.abs(elastic) + np.abs(load)))


# ------------------------------------------------------------------- (e) energy


def _energy(table, theta, theta_d, force):
    coords, rates = api.dependent_state(table, theta, theta_d)
    T, V_G, V_E, lagrangian = api.energies(table, coords, rates)
    np.testing.assert_allclose(lagrangian, T - V_G - V_E, rtol=1e-12,
                               atol=1e-12 * np.max(np.abs([T, V_G, V_E])))
    # F pushes slider 2 along +Y: its potential is -F q.
    V_F = -force * coords[:, 1]
    total = T + V_G + V_E + V_F
    scale = np.abs(T) + np.abs(V_G) + np.abs(V_E) + np.abs(V_F)
    return total, scale


def _rk4(table, theta, theta_d, dt, steps, every=50):
    """Classical RK4 on thetaddot = angular_acceleration; energies every ``every`` steps."""
    force = table["F"]
    E0, scale = _energy(table, theta, theta_d, force)
    energies, kinetic = [E0], [api.energies(table, *api.dependent_state(table, theta,
                                                                         theta_d)).T]

    def accel(th, thd):
        return api.angular_acceleration(table, th, thd)

    for step in range(steps):
        k1x, k1v = theta_d, accel(theta, theta_d)
        k2x, k2v = theta_d + dt / 2 * k1v, accel(theta + dt / 2 * k1x, theta_d + dt / 2 * k1v)
        k3x, k3v = theta_d + dt / 2 * k2v, accel(theta + dt / 2 * k2x, theta_d + dt / 2 * k2v)
        k4x, k4v = theta_d + dt * k3v, accel(theta + dt * k3x, theta_d + dt * k3v)
        theta = theta + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        theta_d = theta_d + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        if step % every == every - 1:
            E, s = _energy(table, theta, theta_d, force)
            energies.append(E)
            kinetic.append(api.energies(table, *api.dependent_state(table, theta, theta_d)).T)
            scale = np.maximum(scale, s)
    return np.array(energies), np.array(kinetic), scale


@pytest.mark.parametrize("with_force", [False, True], ids=["F=0", "F!=0"])
def test_energy_is_conserved_without_damping(with_force, random_params):
    rng = np.random.default_rng(20_240_613 + with_force)
    sets = [api.example_params()] + random_params(rng, 11)
    sets = [api.Params(**{**asdict(p), "b": 0.0, "F": p.F if with_force else 0.0})
            for p in sets]
    table = api.params_array(sets)
    n = len(sets)
    theta = rng.uniform(-math.pi, math.pi, n)
    theta_d = rng.normal(0.0, 2.0, n)

    # Time step from the fastest motion each system can have: the largest |K|/M over the
    # circle, and the largest speed its energy allows.
    grid = np.linspace(-math.pi, math.pi, 181)
    M, _, K = api.linearisation(np.repeat(table, grid.size), np.tile(grid, n))
    omega2 = np.max(np.abs(K / M).reshape(n, -1), axis=1)
    E0, _ = _energy(table, theta, theta_d, table["F"])
    V, _ = _energy(np.repeat(table, grid.size), np.tile(grid, n), np.zeros(n * grid.size),
                   np.repeat(table["F"], grid.size))
    speed2 = 2 * (E0 - np.min(V.reshape(n, -1), axis=1)) / np.min(M.reshape(n, -1), axis=1)
    dt = 0.005 / np.sqrt(omega2 + np.maximum(speed2, 0.0) + theta_d**2)

    energies, kinetic, scale = _rk4(table, theta, theta_d, dt, steps=2000, every=100)
    drift = np.max(np.abs(energies - energies[0]), axis=0) / scale
    assert np.all(drift < 1e-9), drift
    # The motion is not trivial: energy moved between kinetic and potential forms.
    swing = (kinetic.max(axis=0) - kinetic.min(axis=0)) / scale
    assert np.median(swing) > 1e-2, swing


def test_energy_check_detects_damping():
    """With the paper's damper the same integration loses energy far beyond tolerance."""
    table = api.params_array([api.example_params(F=0.0), api.example_params(F=0.0, b=1.0)])
    energies, _, scale = _rk4(table, np.array([0.5, 0.5]), np.array([3.0, 3.0]), 1e-4, 200)
    loss = (energies[0] - energies[-1]) / scale
    assert np.all(loss > 1e-6), loss
