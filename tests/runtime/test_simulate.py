"""The time response (templates/simulate.c.j2 -> PREFIX_simulate.c, codegen.runtime.simulation) of
every shipped mechanism, against references independent of the C: the symbolic derivation
(codegen.compiler.derivation: thetaddot, the damping coefficient e2 and the applied forces'
generalised force, lambdified) integrated by scipy's solve_ivp (DOP853, rtol 1e-12); the energy balance
dE/dt = Q_theta thetadot - e2 thetadot^2 along trajectories, by Gauss-Legendre quadrature; and
small motions about every stable equilibrium against what the linearisation's eigenvalues
say. Then the C entry points' statuses and untouched outputs, resumption bit for bit, the
RK4 step's order, and the Python API's errors.
"""
from __future__ import annotations

import functools
import math
import pickle
from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from codegen.runtime import simulation
from codegen.api import load
from codegen.compiler.derivation import derive
from codegen.errors import LibraryError
from codegen.compiler.model import SHIPPED
from codegen.compiler.model import load as load_model

NAMES = list(SHIPPED)
#: Loads switched on where the example has none, so that the applied forces do work.
LOADS = {"torsion_pendulum": {"F_x": 3.0}, "four_bar": {"T": 0.5}}
SENTINEL = 12345.678


@dataclass(frozen=True)
class Symbolic:
    """Lambdified from the derivation, each f(theta[, theta_d], *parameters)."""

    thetaddot: object      # (36) solved for thetaddot [rad/s^2]
    damping: object        # e2 of (36): the dampers' torque is e2 thetadot [N m s]
    applied: object        # Q_theta = S^T Q_nc: the applied loads' generalised force [N m]


@functools.lru_cache(maxsize=None)
def _symbolic(name: str) -> Symbolic:
    d = derive(load_model(name))
    red = d.reduction
    parameters = [sp.Symbol(n, real=True) for n in load(name).PARAMETER_NAMES]
    on_motion = dict(zip(d.state.coords, red.positions))
    # virtual work: Q_theta = sum_i Q_i dq_i/dtheta, the loads' forces projected on the motion
    q_theta = (red.positions.diff(red.theta).T
               * d.frozen(d.dynamics.applied_forces).subs(on_motion, simultaneous=True))[0]
    return Symbolic(
        thetaddot=sp.lambdify([red.theta, red.theta_d, *parameters], red.angular_acceleration,
                              "math", cse=True),
        damping=sp.lambdify([red.theta, *parameters], red.e[2], "numpy", cse=True),
        applied=sp.lambdify([red.theta, *parameters], q_theta, "numpy", cse=True))


def _params(name: str):
    return load(name).example_params(**LOADS.get(name, {}))


def _values(params) -> list[float]:
    library = type(params).library
    return [getattr(params, n) for n in library.PARAMETER_NAMES]


def _start(params) -> tuple[float, float, float]:
    """(theta0 [rad], theta_d0 [rad/s], duration [s]): 0.3 rad from the least damped stable
    equilibrium, moving at 0.3 omega_n, for about four of its periods."""
    stable = [e for e in params.library.analyze(params).equilibria if simulation.is_stable(e)]
    e = min(stable, key=lambda e: e.zeta.real)
    omega = e.omega_n.real
    return e.theta + 0.3, 0.3 * omega, 25.0 / omega


# --------------------------------------------------------------------------- references

@pytest.mark.parametrize("name", NAMES)
def test_trajectories_agree_with_scipy_on_the_symbolic_equation(name):
    """DOP853 at rtol 1e-12 on the lambdified derivation against simulate at rtol 1e-9 and
    1e-11: both within 100 rtol (of the largest |theta| or |thetadot|), and closer at the
    tighter tolerance."""
    params = _params(name)
    theta0, theta_d0, duration = _start(params)
    times = np.linspace(0.0, duration, 1001)
    f, values = _symbolic(name).thetaddot, _values(params)
    ref = solve_ivp(lambda t, y: [y[1], f(y[0], y[1], *values)], (0.0, duration),
                    [theta0, theta_d0], method="DOP853", rtol=1e-12, atol=1e-12, t_eval=times)
    assert ref.success
    errors = {}
    for rtol in (1e-9, 1e-11):
        tr = params.library.simulate(params, theta0, theta_d0, times, rtol=rtol,
                                     atol=rtol * 1e-3)
        errors[rtol] = max(np.max(np.abs(tr.theta - ref.y[0])) / np.max(np.abs(ref.y[0])),
                           np.max(np.abs(tr.theta_d - ref.y[1])) / np.max(np.abs(ref.y[1])))
        assert errors[rtol] < 100 * rtol, (rtol, errors[rtol])
    assert errors[1e-11] < errors[1e-9] / 10


def _gauss_times(duration: float, pieces: int, order: int = 8):
    """Output times: the ends of `pieces` equal intervals and `order` Gauss-Legendre nodes in
    each; the indices of the ends and of the nodes, and the weights (times half-widths)."""
    ends = np.linspace(0.0, duration, pieces + 1)
    x, w = np.polynomial.legendre.leggauss(order)
    half = np.diff(ends) / 2
    nodes = (ends[:-1] + half)[:, None] + half[:, None] * x[None, :]
    times = np.sort(np.concatenate([ends, nodes.ravel()]))
    return (times, np.searchsorted(times, ends), np.searchsorted(times, nodes.ravel()),
            half[:, None] * w[None, :])


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("rtol", [1e-8, 1e-11])
def test_energy_balance_along_trajectories(name, rtol):
    """E = T + V_G + V_E (the library's energies at the library's dependent state) changes
    by the applied loads' work minus what the dampers dissipate, the integrals of
    Q_theta thetadot and e2 thetadot^2 (from the derivation), to within 100 rtol of the
    energies' size; without the loads' work or the dissipation the balance fails by far."""
    params = _params(name)
    library, symbolic, values = params.library, _symbolic(name), _values(params)
    theta0, theta_d0, duration = _start(params)
    times, ends, nodes, weights = _gauss_times(duration, 200)
    tr = library.simulate(params, theta0, theta_d0, times, rtol=rtol, atol=rtol * 1e-3)
    table = library.params_array([params] * len(times))
    coords, rates = library.dependent_state(table, tr.theta, tr.theta_d)
    energy = library.energies(table, coords, rates)
    total = energy.T + energy.V_G + energy.V_E
    scale = max(np.max(np.abs(x)) for x in (energy.T, energy.V_G, energy.V_E))
    theta, rate = tr.theta[nodes], tr.theta_d[nodes]
    work = np.cumsum(np.sum(weights * (symbolic.applied(theta, *values) * rate)
                            .reshape(weights.shape), axis=1))
    dissipated = np.cumsum(np.sum(weights * (symbolic.damping(theta, *values) * rate**2)
                                  .reshape(weights.shape), axis=1))
    change = total[ends[1:]] - total[ends[0]]
    assert np.max(np.abs(change - work + dissipated)) < 100 * rtol * scale
    assert np.max(np.abs(dissipated)) > 1e-3 * scale        # the dampers take energy out
    assert np.max(np.abs(work)) > 1e-3 * scale               # the loads do work


def _stable_equilibria():
    return [(name, i) for name in NAMES
            for i, e in enumerate(load(name).analyze(_params(name)).equilibria)
            if simulation.is_stable(e)]


def _small_motion(name: str, index: int, delta: float):
    """A motion from delta [rad] off a stable equilibrium, at rest, for about three periods
    (or time constants): the equilibrium, the times and x(t) = theta - theta_E."""
    params = _params(name)
    e = params.library.analyze(params).equilibria[index]
    duration = 20.0 / e.omega_n.real
    times = np.linspace(0.0, duration, 4001)
    tr = params.library.simulate(params, e.theta + delta, 0.0, times, rtol=1e-12,
                                 atol=1e-16)
    return e, times, tr.theta - e.theta


@pytest.mark.parametrize("name, index", _stable_equilibria())
def test_small_motions_follow_the_linearisation(name, index):
    """From 1e-3 and 5e-4 rad off each stable equilibrium: x(t) differs from the linear
    response (closed form, M, B, K of the analysis) by O(delta^2), a quarter when delta
    halves (so what remains is the nonlinearity), and by under 1 % of delta."""
    differences = []
    for delta in (1e-3, 5e-4):
        e, times, x = _small_motion(name, index, delta)
        linear, _ = simulation.linear_response(e.M, e.B, e.K, delta, 0.0, times)
        differences.append(np.max(np.abs(x - linear)))
        assert differences[-1] < 1e-2 * delta
    assert 3.0 < differences[0] / differences[1] < 5.0


@pytest.mark.parametrize("name, index", _stable_equilibria())
def test_small_motions_decay_and_oscillate_as_the_eigenvalues_say(name, index):
    """Measured on the simulated motion alone: an underdamped equilibrium's zero crossings
    are pi / Im(s) apart and its swings shrink by exp(Re(s) pi / Im(s)) each; an overdamped
    one's motion decays at the slower real eigenvalue's rate. To 0.2 %."""
    e, times, x = _small_motion(name, index, 1e-4)
    s = max(e.eigenvalues, key=lambda z: (z.real, z.imag))   # the slowest, Im >= 0
    if e.damping == "underdamped":
        down = np.flatnonzero((x[:-1] > 0) & (x[1:] <= 0))
        crossings = times[down] - x[down] * (times[down + 1] - times[down]) / (x[down + 1] - x[down])
        period = np.diff(crossings)
        assert len(period) >= 2
        assert np.allclose(period, 2 * math.pi / s.imag, rtol=2e-3, atol=0)
        peaks = [np.max(np.abs(x[(times >= a) & (times < b)]))
                 for a, b in zip(crossings[:-1], crossings[1:])]
        ratios = np.array(peaks[1:]) / np.array(peaks[:-1])
        assert np.allclose(ratios, math.exp(s.real * 2 * math.pi / s.imag), rtol=2e-3, atol=0)
    else:
        late = times > times[-1] / 2
        slope = np.polyfit(times[late], np.log(np.abs(x[late])), 1)[0]
        assert slope == pytest.approx(s.real, rel=2e-3)


def test_the_linear_response_is_the_solution_of_its_equation():
    """linear_response against solve_ivp on M x'' + B x' + K x = 0, for every damping."""
    times = np.linspace(0.0, 3.0, 301)
    for M, B, K in [(2.0, 0.5, 30.0), (2.0, 2 * math.sqrt(60.0), 30.0), (2.0, 40.0, 30.0),
                    (1.0, 0.0, 4.0), (1.0, 400.0, 1.0)]:
        x, v = simulation.linear_response(M, B, K, 0.1, -0.3, times)
        ref = solve_ivp(lambda t, y: [y[1], -(B * y[1] + K * y[0]) / M], (0.0, 3.0),
                        [0.1, -0.3], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=times)
        assert np.allclose(x, ref.y[0], rtol=0, atol=1e-9), (M, B, K)
        assert np.allclose(v, ref.y[1], rtol=0, atol=1e-8), (M, B, K)


# --------------------------------------------------------------------------- the C API

def _c(name: str = "doughty"):
    library = load(name)
    return library, library.ffi, library.lib, library.PREFIX


def _simulate_c(name, theta0=2.8, theta_d0=0.0, times=(0.0, 0.5, 1.0), options=None,
                params=None, null=None):
    """PREFIX_simulate on sentinel-filled outputs: (status, reached, theta, theta_d)."""
    library, ffi, lib, P = _c(name)
    c_params = library._c_params(params or library.example_params())
    times = np.array(times, dtype=np.float64)
    theta, theta_d = np.full(len(times), SENTINEL), np.full(len(times), SENTINEL)
    reached = ffi.new("size_t *", 99)
    arguments = [c_params, theta0, theta_d0, ffi.from_buffer("double[]", times), len(times),
                 options if options is not None else ffi.NULL,
                 ffi.from_buffer("double[]", theta, require_writable=True),
                 ffi.from_buffer("double[]", theta_d, require_writable=True), reached]
    if null is not None:
        arguments[null] = ffi.NULL
    status = getattr(lib, f"{P}_simulate")(*arguments)
    return status, reached[0], theta, theta_d


def _options(name, **change):
    library, ffi, lib, _ = _c(name)
    options = ffi.new("codegen_ode_options *", lib.codegen_ode_defaults())
    for key, value in change.items():
        setattr(options, key, value)
    return options


@pytest.mark.parametrize("name", NAMES)
def test_c_statuses_leave_the_outputs_untouched(name):
    library = load(name)
    S = library.STATUS
    cases = [({"null": 0}, "ERR_NULL_POINTER"), ({"null": 3}, "ERR_NULL_POINTER"),
             ({"null": 6}, "ERR_NULL_POINTER"), ({"null": 7}, "ERR_NULL_POINTER"),
             ({"theta0": math.nan}, "ERR_NONFINITE"), ({"theta_d0": math.inf}, "ERR_NONFINITE"),
             ({"times": (0.0, math.nan)}, "ERR_NONFINITE"),
             ({"times": (0.0, 1.0, 0.5)}, "ERR_ARGUMENT"), ({"times": ()}, "ERR_ARGUMENT"),
             ({"options": _options(name, rtol=0.0)}, "ERR_ARGUMENT"),
             ({"options": _options(name, atol=-1.0)}, "ERR_ARGUMENT"),
             ({"options": _options(name, max_steps=0)}, "ERR_ARGUMENT"),
             ({"options": _options(name, h_max=0.0)}, "ERR_ARGUMENT"),
             ({"params": library.example_params(**{library.PARAMETER_NAMES[0]: math.nan})},
              "ERR_NONFINITE_PARAM")]
    theta0 = _start(_params(name))[0]
    for change, expected in cases:
        status, reached, theta, theta_d = _simulate_c(name, **{"theta0": theta0, **change})
        assert status == S[expected], (change, status)
        assert reached == 0 and np.all(theta == SENTINEL) and np.all(theta_d == SENTINEL)


def test_c_budget_writes_the_rows_before_it_and_says_how_many():
    times = np.linspace(0.0, 2.0, 101)
    status, reached, theta, _ = _simulate_c("doughty", times=times,
                                            options=_options("doughty", max_steps=40))
    assert status == load("doughty").STATUS["ERR_STEP_BUDGET"]
    assert 1 < reached < len(times)
    assert np.all(theta[reached:] == SENTINEL) and np.all(theta[:reached] != SENTINEL)
    full = load("doughty").simulate(None, 2.8, 0.0, times)
    assert np.array_equal(theta[:reached], full.theta[:reached])   # the same integration


def test_a_singular_start_is_the_librarys_singular_state():
    library = load("doughty")
    massless = library.example_params(m_A=0.0, m_B=0.0, m_C=0.0)   # no inertia: e0 = 0
    status, *_ = _simulate_c("doughty", params=massless)
    assert status == library.STATUS["ERR_SINGULAR_STATE"]
    with pytest.raises(LibraryError, match="^m_A, m_B, m_C: ") as error:   # the example's work
        library.simulate(massless, 2.8, 0.0, [0.0, 1.0])
    assert error.value.code == "ERR_SINGULAR_STATE"


@pytest.mark.parametrize("name", NAMES)
def test_resuming_and_progress_change_no_number(name):
    """Output in pieces (start once, advance per hundredth, with a progress callback) is the
    one-call integration bit for bit; progress goes up to the total."""
    params = _params(name)
    theta0, theta_d0, duration = _start(params)
    times = np.linspace(0.0, duration, 1234)
    whole = params.library.simulate(params, theta0, theta_d0, times)
    calls = []
    pieces = params.library.simulate(params, theta0, theta_d0, times,
                                     progress=lambda done, total: calls.append((done, total)))
    assert np.array_equal(whole.theta, pieces.theta)
    assert np.array_equal(whole.theta_d, pieces.theta_d)
    assert (whole.steps, whole.evaluations) == (pieces.steps, pieces.evaluations)
    assert 50 <= len(calls) <= simulation.PROGRESS_STEPS and calls[-1] == (1234, 1234)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    assert whole.theta[0] == theta0 and whole.theta_d[0] == theta_d0


@pytest.mark.parametrize("name", NAMES)
def test_rk4_step_has_order_four(name):
    """Repeated RK4 steps over a span against simulate at rtol 1e-12: the error falls by
    2^4 = 16 (within 14-18) per halving of the step."""
    params = _params(name)
    theta0, theta_d0, duration = _start(params)
    span = duration / 10
    reference = params.library.simulate(params, theta0, theta_d0, [0.0, span], rtol=1e-12,
                                        atol=1e-15)
    errors = []
    for count in (40, 80, 160):
        state = (theta0, theta_d0)
        for _ in range(count):
            state = params.library.rk4_step(params, *state, span / count)
        errors.append(abs(state[0] - reference.theta[-1]))
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(14.0 < r < 18.0 for r in ratios), ratios


def test_rk4_step_errors_name_the_input_and_leave_outputs_untouched():
    library, ffi, lib, P = _c()
    with pytest.raises(LibraryError, match=r"^h: .*\(h=nan\)"):
        library.rk4_step(None, 1.0, 0.0, math.nan)
    with pytest.raises(LibraryError, match=r"^k: .*k=-1"):
        library.rk4_step({**library.EXAMPLE, "k": -1.0}, 1.0, 0.0, 1e-3)
    out = ffi.new("double[2]", [SENTINEL, SENTINEL])
    massless = library._c_params(library.example_params(m_A=0.0, m_B=0.0, m_C=0.0))
    assert getattr(lib, f"{P}_rk4_step")(massless, 1e-3, 1.0, 0.0, out, out + 1) == \
        library.STATUS["ERR_SINGULAR_STATE"]
    assert list(out) == [SENTINEL, SENTINEL]
    assert getattr(lib, f"{P}_rk4_step")(massless, 1e-3, 1.0, 0.0, ffi.NULL, out) == \
        library.STATUS["ERR_NULL_POINTER"]


# --------------------------------------------------------------------------- Python errors

@pytest.mark.parametrize("options, match", [
    ({"rtol": 0.0}, "^rtol"), ({"rtol": 1e-20}, "^rtol"), ({"rtol": math.nan}, "^rtol"),
    ({"atol": -1.0}, "^atol"), ({"atol": math.inf}, "^atol"), ({"max_steps": 0}, "^max_steps"),
    ({"max_steps": 1.5}, "^max_steps"), ({"h_max": 0.0}, "^h_max"),
    ({"t": [0.0, 1.0, 0.5]}, "^t: the times must not decrease"), ({"t": []}, "^t must be"),
    ({"t": [[0.0, 1.0]]}, "^t must be"), ({"t": [0.0, math.inf]}, "^t: every time")])
def test_bad_options_and_times_are_value_errors_naming_them(options, match):
    library = load("doughty")
    arguments = {"t": [0.0, 1.0], **options}
    with pytest.raises(ValueError, match=match):
        library.simulate(None, 2.8, 0.0, **arguments)


def test_any_array_of_times_and_the_trajectory_owns_a_copy():
    library = load("doughty")
    times = np.linspace(0.0, 1.0, 21)
    times.flags.writeable = False
    strided = library.simulate(None, 2.8, 0.0, times[::4])
    assert np.array_equal(strided.t, times[::4]) and not np.shares_memory(strided.t, times)
    whole = library.simulate(None, 2.8, 0.0, list(times))
    assert np.array_equal(whole.theta[::4], strided.theta)   # the same steps, interpolated


def test_failures_are_library_errors_with_their_cause():
    library = load("doughty")
    with pytest.raises(LibraryError, match=r"^theta0: .*theta0=nan"):
        library.simulate(None, math.nan, 0.0, [0.0, 1.0])
    with pytest.raises(LibraryError, match=r"^b: b must not be negative"):
        library.simulate({**library.EXAMPLE, "b": -1.0}, 2.8, 0.0, [0.0, 1.0])
    with pytest.raises(LibraryError, match=r"step budget .*\(t=.*, max_steps=30\)") as error:
        library.simulate(None, 2.8, 0.0, [0.0, 2.0], max_steps=30)
    assert error.value.code == "ERR_STEP_BUDGET" and 0 < error.value.values["t"] < 2.0
    with pytest.raises(TypeError, match="Params of a library"):
        simulation.simulate({"k": 1.0}, 2.8, 0.0, [0.0, 1.0])


def test_a_failed_integration_keeps_the_outputs_before_the_failure():
    """The step budget runs out part way: the error's trajectory is the prefix of the full
    one (bit for bit: the same steps), ending before the time the failure happened."""
    library = load("doughty")
    times = np.linspace(0.0, 2.0, 401)
    full = library.simulate(None, 2.8, 0.0, times)
    with pytest.raises(simulation.IntegrationError) as error:
        library.simulate(None, 2.8, 0.0, times, max_steps=full.steps // 2, progress=lambda *_: None)
    partial = error.value.trajectory
    n = len(partial.t)
    assert 1 < n < len(times) and partial.t[-1] <= error.value.values["t"] < times[n]
    assert np.array_equal(partial.theta, full.theta[:n])
    assert np.array_equal(partial.theta_d, full.theta_d[:n])
    again = pickle.loads(pickle.dumps(error.value))
    assert again.code == "ERR_STEP_BUDGET" and np.array_equal(again.trajectory.theta, partial.theta)
    assert str(again) == str(error.value)


def test_nearest_stable_equilibrium_moves_by_whole_turns_on_a_periodic_coordinate():
    library = load("doughty")
    params = library.example_params()
    underdamped = next(e for e in library.analyze(params).equilibria if e.damping == "underdamped")
    e, theta_e = simulation.nearest_stable(params, underdamped.theta - 4 * math.pi + 0.01)
    assert e.theta == underdamped.theta and theta_e == pytest.approx(e.theta - 4 * math.pi)
