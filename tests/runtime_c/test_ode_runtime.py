"""Tests for the runtime's integrator, runtime/codegen_ode.h/.c (copied verbatim to
generated/runtime/): Dormand-Prince 5(4) with dense output, and one RK4 step.

Self-contained: drivers/ode_driver.c is compiled here with the project's strict flags against
runtime/codegen_ode.c and fed commands on stdin; doubles travel as hex floats both ways.
Nothing of the project is imported but the flags (runtime/cflags.txt). The references are
exact solutions: a damped harmonic oscillator (under-, critically, over- and undamped),
exponential decay and growth, a time-dependent right-hand side, a rotating and decaying 3-D
linear system, and y' = y^2, which is infinite at a known time.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np
import pytest

OK, BAD_INPUT, BUDGET, STEP_UNDERFLOW, NONFINITE = range(5)   # codegen_ode_status
INF = math.inf


def h(x: float) -> str:
    return float(x).hex()


@dataclass
class Solution:
    status: int
    reached: int
    steps: int
    rejected: int
    evaluations: int
    t: float           # the time the integrator reached
    h: float           # its next step size
    y: np.ndarray      # (reached, n)


class Driver:
    """tests/support/c/ode_driver.c: the commands as methods, the answers parsed."""

    def __init__(self, program):
        self.program = program     # conftest's DriverProgram

    def raw(self, lines) -> str:
        return self.program.raw(lines, timeout=300)

    def lines(self, lines) -> list[list[str]]:
        return self.program(lines, timeout=300)

    def solve(self, problem, a, b, y0, times, rtol=1e-10, atol=1e-12, h_max=INF,
              max_steps=10**6, split=None) -> Solution:
        words = self.lines([solve_line(problem, a, b, y0, times, rtol, atol, h_max, max_steps,
                                       split)])[0]
        status, reached, steps, rejected, evaluations = map(int, words[:5])
        values = np.array([float.fromhex(w) for w in words[7:]]).reshape(-1, len(y0))
        return Solution(status, reached, steps, rejected, evaluations, float.fromhex(words[5]),
                        float.fromhex(words[6]), values)

    def rk4(self, problem, a, b, t, step, y) -> tuple[int, np.ndarray]:
        words = self.lines([f"rk4 {problem} {h(a)} {h(b)} {h(t)} {h(step)} {len(y)} "
                            + " ".join(h(v) for v in y)])[0]
        return int(words[0]), np.array([float.fromhex(w) for w in words[1:]])


def solve_line(problem, a, b, y0, times, rtol=1e-10, atol=1e-12, h_max=INF, max_steps=10**6,
               split=None) -> str:
    head = "solve" if split is None else f"split {split}"
    return (f"{head} {problem} {h(a)} {h(b)} {h(rtol)} {h(atol)} {h(h_max)} {max_steps} "
            f"{len(y0)} " + " ".join(h(v) for v in y0) + f" {len(times)} "
            + " ".join(h(t) for t in times))


def _build(compiler, tmp, name, flags=None):
    return compiler.build(tmp / name, "ode_driver.c", "codegen_ode.c", flags)


@pytest.fixture(scope="module")
def drv(tmp_path_factory, runtime_driver):
    """The driver, compiled with -O2 and the strict flags (a warning is an error)."""
    return Driver(runtime_driver.program(_build(runtime_driver, tmp_path_factory.mktemp("ode"),
                                                "ode_driver")))


# ---------------------------------------------------------------------------- exact solutions

def oscillator(zeta: float, omega: float, x0: float, v0: float, t: np.ndarray) -> np.ndarray:
    """x'' + 2 zeta omega x' + omega^2 x = 0: (x, x') at t, in closed form for every zeta."""
    a = -zeta * omega                                   # e^(a t) times cos/cosh/1 and sin/sinh/t
    q = omega * omega * (1.0 - zeta * zeta)             # the squared damped frequency (< 0: real)
    if q > 0:
        w = math.sqrt(q)
        c, s, ds = np.cos(w * t), np.sin(w * t) / w, np.cos(w * t)
        dc = -w * np.sin(w * t)
    elif q < 0:
        m = math.sqrt(-q)
        c, s, ds = np.cosh(m * t), np.sinh(m * t) / m, np.cosh(m * t)
        dc = m * np.sinh(m * t)
    else:
        c, s, ds, dc = np.ones_like(t), t, np.ones_like(t), np.zeros_like(t)
    e = np.exp(a * t)
    x = e * (x0 * c + (v0 - a * x0) * s)
    v = a * x + e * (x0 * dc + (v0 - a * x0) * ds)
    return np.column_stack([x, v])


def rotation(a: float, b: float, y0, t: np.ndarray) -> np.ndarray:
    u0, v0, w0 = y0
    e = np.exp(a * t)
    return np.column_stack([e * (u0 * np.cos(b * t) - v0 * np.sin(b * t)),
                            e * (u0 * np.sin(b * t) + v0 * np.cos(b * t)),
                            w0 * np.exp(-b * t)])


def max_error(y: np.ndarray, exact: np.ndarray) -> float:
    """The largest error relative to the largest magnitude of each component."""
    return float(np.max(np.abs(y - exact) / np.max(np.abs(exact), axis=0)))


# ---------------------------------------------------------------------------- 1. accuracy

OSCILLATORS = [(0.05, 10.0), (0.3, 2.0), (1.0, 5.0), (3.0, 4.0), (0.0, 7.0)]


@pytest.mark.parametrize("zeta, omega", OSCILLATORS)
def test_damped_oscillator_matches_its_exact_solution(drv, zeta, omega):
    """At 2001 output times over about five periods (interpolated between steps), every
    damping: the global error stays within 30 rtol (it is 0.1-3 rtol), falls about as fast as
    rtol, and row 0 is the initial state."""
    times = np.linspace(0.0, 5 * 2 * math.pi / omega, 2001)
    exact = oscillator(zeta, omega, 1.0, -0.5, times)
    errors = {}
    for rtol in (1e-6, 1e-8, 1e-10):
        s = drv.solve("oscillator", zeta, omega, [1.0, -0.5], times, rtol=rtol, atol=rtol * 1e-3)
        assert s.status == OK and s.reached == len(times)
        assert s.y[0].tolist() == [1.0, -0.5]
        errors[rtol] = max_error(s.y, exact)
        assert errors[rtol] < 30 * rtol, (rtol, errors[rtol])
    assert errors[1e-6] > 1000 * errors[1e-10]          # it converges


def test_every_output_time_is_accurate_not_only_the_steps(drv):
    """Outputs far denser than the steps (order-4 continuous extension): as accurate at the
    10 001 interpolated times as at the steps' own ends."""
    zeta, omega = 0.1, 3.0
    dense = np.linspace(0.0, 10.0, 10001)
    s = drv.solve("oscillator", zeta, omega, [0.0, 1.0], dense, rtol=1e-9, atol=1e-12)
    assert s.status == OK and s.steps < 2000                     # far fewer steps than outputs
    assert max_error(s.y, oscillator(zeta, omega, 0.0, 1.0, dense)) < 4e-9   # 4e-10 here


@pytest.mark.parametrize("rate", [-50.0, -1.0, 1.0])
def test_exponential_decay_and_growth(drv, rate):
    times = np.linspace(0.0, 3.0, 31)
    s = drv.solve("decay", rate, 0.0, [2.0], times, rtol=1e-10, atol=0.0)   # purely relative
    assert s.status == OK
    exact = 2.0 * np.exp(rate * times)
    assert np.max(np.abs(s.y[:, 0] - exact) / exact) < 1e-8


def test_the_right_hand_side_sees_the_time(drv):
    """y' = cos(a t) from t0 = 1 (not 0): y = y0 + (sin(a t) - sin(a t0)) / a."""
    a, times = 3.0, np.linspace(1.0, 6.0, 51)
    s = drv.solve("clock", a, 0.0, [0.25], times)
    assert s.status == OK
    exact = 0.25 + (np.sin(a * times) - math.sin(a)) / a
    assert np.max(np.abs(s.y[:, 0] - exact)) < 1e-9


def test_a_three_dimensional_system(drv):
    a, b, y0 = -0.2, 4.0, [1.0, -2.0, 0.5]
    times = np.linspace(0.0, 4.0, 401)
    s = drv.solve("rotation", a, b, y0, times)
    assert s.status == OK
    assert max_error(s.y, rotation(a, b, y0, times)) < 1e-8


def test_step_budget_is_the_tried_steps_and_fsal_costs_six_evaluations_a_step(drv):
    """Evaluations: one at the start, one for the first step size, then six per tried step
    (accepted or rejected): the last stage of a step is the next one's first."""
    times = np.linspace(0.0, 20.0, 5)
    s = drv.solve("oscillator", 0.02, 6.0, [1.0, 0.0], times, rtol=1e-7)
    assert s.status == OK and s.steps > 100
    assert s.evaluations == 2 + 6 * (s.steps + s.rejected)
    assert s.t >= times[-1]


def test_h_max_bounds_every_step(drv):
    times = [0.0, 10.0]
    free = drv.solve("decay", -0.01, 0.0, [1.0], times, rtol=1e-6)
    bounded = drv.solve("decay", -0.01, 0.0, [1.0], times, rtol=1e-6, h_max=0.01)
    assert free.steps < 50 and bounded.steps >= 1000
    assert bounded.h <= 0.01 * 10   # the next step may be proposed longer, never taken so


# ---------------------------------------------------------------------------- 2. resuming

@pytest.mark.parametrize("split", [1, 2, 137, 500, 1000])
def test_advancing_in_pieces_is_the_same_integration_bit_for_bit(drv, split):
    """Outputs are interpolated and never shorten a step, so how the output times are split
    between calls changes nothing: the same numbers, steps and evaluations."""
    times = np.linspace(0.0, 7.0, 1001)
    whole = drv.solve("oscillator", 0.1, 5.0, [1.0, 0.0], times, rtol=1e-9)
    pieces = drv.solve("oscillator", 0.1, 5.0, [1.0, 0.0], times, rtol=1e-9, split=split)
    assert whole.status == pieces.status == OK
    assert np.array_equal(whole.y, pieces.y)
    assert (whole.steps, whole.rejected, whole.evaluations) == (
        pieces.steps, pieces.rejected, pieces.evaluations)


def test_repeated_output_times_repeat_the_row(drv):
    times = [0.0, 0.5, 0.5, 0.5, 1.0, 1.0]
    s = drv.solve("oscillator", 0.1, 5.0, [1.0, 0.0], times)
    assert s.status == OK and s.reached == 6
    assert np.array_equal(s.y[1], s.y[2]) and np.array_equal(s.y[2], s.y[3])
    assert np.array_equal(s.y[4], s.y[5])


# ---------------------------------------------------------------------------- 3. statuses

@pytest.mark.parametrize("change", [
    {"rtol": 0.0}, {"rtol": 1e-15}, {"rtol": 2.0}, {"rtol": math.nan}, {"atol": -1e-12},
    {"atol": math.nan}, {"atol": INF}, {"h_max": 0.0}, {"h_max": -1.0}, {"h_max": math.nan},
    {"max_steps": 0}, {"y0": [math.nan, 0.0]}, {"y0": [INF, 0.0]},
    {"times": [0.0, math.nan]}, {"times": [0.0, INF]}, {"times": [0.0, 1.0, 0.5]},
    {"times": [math.nan, 1.0]}, {"times": []}])
def test_bad_input_is_refused_before_anything_is_written(drv, change):
    arguments = dict(problem="oscillator", a=0.1, b=5.0, y0=[1.0, 0.0], times=[0.0, 1.0, 2.0])
    arguments |= change
    s = drv.solve(**arguments)
    assert (s.status, s.reached, s.evaluations) == (BAD_INPUT, 0, 0)


def test_the_step_budget_runs_out(drv):
    times = np.linspace(0.0, 50.0, 101)
    s = drv.solve("oscillator", 0.01, 10.0, [1.0, 0.0], times, rtol=1e-10, max_steps=300)
    assert s.status == BUDGET
    assert s.steps + s.rejected == 300
    assert 0 < s.reached < len(times) and times[s.reached - 1] <= s.t < times[s.reached]
    exact = oscillator(0.01, 10.0, 1.0, 0.0, times[:s.reached])
    assert np.max(np.abs(s.y - exact)) < 1e-7        # the rows written are the right ones


def test_a_solution_that_goes_to_infinity_underflows_the_step(drv):
    """y' = y^2 from y(0) = 1 is 1/(1 - t): the steps shrink towards t = 1 until they are lost
    in the rounding of t; the rows before are exact to the tolerance."""
    times = np.linspace(0.0, 2.0, 21)
    s = drv.solve("blowup", 1.0, 0.0, [1.0], times, rtol=1e-10)
    assert s.status == STEP_UNDERFLOW
    assert s.reached == 10 and 1.0 - 1e-6 < s.t < 1.0      # t = 0, 0.1, .., 0.9 written
    exact = 1.0 / (1.0 - times[:10])
    assert np.max(np.abs(s.y[:, 0] - exact) / exact) < 1e-8


def test_a_wall_where_the_right_hand_side_is_undefined(drv):
    """f is NaN beyond y = 0.45 (y = t): the trial steps into the wall are rejected and shrunk
    until the step underflows next to it: NONFINITE, the rows before it written."""
    times = np.linspace(0.0, 1.0, 11)
    s = drv.solve("wall", 0.45, 0.0, [0.0], times)
    assert s.status == NONFINITE
    assert s.reached == 5 and 0.45 - 1e-9 < s.t <= 0.45
    assert np.allclose(s.y[:, 0], times[:5], rtol=0, atol=1e-14)
    s = drv.solve("nan", 0.0, 0.0, [0.0], times)                  # not finite at the start
    assert (s.status, s.reached, s.evaluations) == (NONFINITE, 0, 1)


def test_null_pointers_a_zero_dimension_and_a_final_failure(drv):
    """start: NULL f, n = 0, NULL y0, options, state, work; solve with no output time; a
    good start; advance with NULL times; a failure (f not finite at y0), then an advance
    after it returns the same failure; RK4 with NULL work. Then the last reached count."""
    statuses = drv.lines(["misuse"])[0]
    assert statuses == ["1"] * 7 + ["0", "1", "4", "4", "1", "0"]


# ---------------------------------------------------------------------------- 4. one RK4 step

def test_rk4_step_is_simpsons_rule_on_a_quadrature(drv):
    """For y' = f(t), RK4 is Simpson's rule: y + h/6 (f(t) + 4 f(t + h/2) + f(t + h))."""
    a, t, step, y = 2.0, 0.3, 0.25, 1.5
    status, y_next = drv.rk4("clock", a, 0.0, t, step, [y])
    simpson = y + step / 6 * (math.cos(a * t) + 4 * math.cos(a * (t + step / 2))
                              + math.cos(a * (t + step)))
    assert status == OK and y_next[0] == pytest.approx(simpson, rel=4e-16, abs=0)


def test_rk4_converges_with_order_four(drv):
    """Repeated steps over a fixed span: the global error falls 2^4 = 16 times per halving."""
    zeta, omega, span = 0.2, 3.0, 2.0
    exact = oscillator(zeta, omega, 1.0, 0.0, np.array([span]))[0]
    errors = []
    for count in (50, 100, 200):
        y, step = [1.0, 0.0], span / count
        for i in range(count):
            status, y = drv.rk4("oscillator", zeta, omega, i * step, step, list(y))
            assert status == OK
        errors.append(float(np.max(np.abs(y - exact))))
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(14.0 < r < 18.0 for r in ratios), ratios


def test_rk4_refuses_bad_input_and_reports_a_nonfinite_result(drv):
    assert drv.rk4("decay", -1.0, 0.0, 0.0, math.nan, [1.0])[0] == BAD_INPUT
    assert drv.rk4("decay", -1.0, 0.0, INF, 0.1, [1.0])[0] == BAD_INPUT
    assert drv.rk4("decay", -1.0, 0.0, 0.0, 0.1, [math.nan])[0] == BAD_INPUT
    status, y = drv.rk4("wall", 0.5, 0.0, 0.0, 1.0, [0.0])   # stages beyond the wall
    assert status == NONFINITE and y.tolist() == [0.0]       # y_next (= y) untouched
    assert drv.rk4("decay", 1.0, 0.0, 0.0, 1.0, [1e308])[0] == NONFINITE   # overflow


# ---------------------------------------------------------------------------- 5. sanitizers

def _sanitizer_script() -> list[str]:
    lines = ["misuse"]
    for zeta, omega in OSCILLATORS:
        times = np.linspace(0.0, 3.0, 301)
        lines.append(solve_line("oscillator", zeta, omega, [1.0, -0.5], times, rtol=1e-8))
        lines.append(solve_line("oscillator", zeta, omega, [1.0, -0.5], times, rtol=1e-8,
                                split=77))
    lines += [solve_line("rotation", -0.2, 4.0, [1.0, -2.0, 0.5], np.linspace(0, 4, 41)),
              solve_line("blowup", 1.0, 0.0, [1.0], np.linspace(0, 2, 21)),
              solve_line("wall", 0.45, 0.0, [0.0], np.linspace(0, 1, 11)),
              solve_line("nan", 0.0, 0.0, [0.0], [0.0, 1.0]),
              solve_line("decay", 1.0, 0.0, [1.0], [0.0, 1000.0]),     # overflows
              solve_line("decay", -1.0, 0.0, [0.0], [0.0, 1.0], atol=0.0),
              solve_line("oscillator", 0.01, 10.0, [1.0, 0.0], [0.0, 50.0], max_steps=7),
              f"rk4 oscillator {h(0.2)} {h(3.0)} 0x0p+0 {h(0.1)} 2 {h(1.0)} 0x0p+0",
              f"rk4 wall {h(0.5)} 0x0p+0 0x0p+0 {h(1.0)} 1 0x0p+0"]
    return lines


def test_sanitized_driver(tmp_path, drv, sanitizer, runtime_driver):
    """Every kind of integration and failure under AddressSanitizer + UBSan (work and outputs
    exactly CODEGEN_ODE_WORK(n) doubles on the heap): clean, and the same output bit for bit."""
    exe = _build(runtime_driver, tmp_path, "ode_driver_san",
                 [*sanitizer.flags, *runtime_driver.warnings])
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0", UBSAN_OPTIONS="print_stacktrace=1")
    lines = _sanitizer_script()
    assert runtime_driver.program(exe, env).raw(lines) == drv.raw(lines)
