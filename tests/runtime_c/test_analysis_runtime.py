"""Tests for the runtime's analysis and time response on their own
(runtime/codegen_analysis.c and codegen_simulation.c, copied to generated/runtime/), through
a codegen_model written by hand in drivers/analysis_driver.c: nothing generated.

Its mechanism: G(theta) = a cos(theta) + b sin(theta) + c with constant M = m and B = d. The
references are closed forms that share nothing with the runtime: the zeros of G from
R cos(theta - phi) = -c, K = G', omega_n = sqrt(K/m), zeta = d / (2 m omega_n), and for the
time response scipy's solve_ivp and a Runge-Kutta step written out here.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import solve_ivp

OK, NULL_POINTER, NONFINITE_PARAM, EVERY_ANGLE, CAPACITY, ERR_MASS = 0, 1, 4, 7, 9, 12
DEFAULT, ISOLATION = 0, 1
STABLE, MARGINAL, UNSTABLE = range(3)
UNDERDAMPED, CRITICAL, OVERDAMPED, UNDAMPED, NOT_OSCILLATORY = range(5)
FIELDS = ("theta", "lo", "hi", "certified", "genuine", "kind", "residual", "M", "B", "K",
          "omega_re", "omega_im", "zeta_re", "zeta_im", "eig_re0", "eig_im0", "eig_re1",
          "eig_im1", "stability", "damping")
INTEGERS = {"certified", "genuine", "kind", "stability", "damping"}
RUNTIME = ("codegen_analysis.c", "codegen_modes.c", "codegen_simulation.c", "codegen_interval.c",
           "codegen_roots.c", "codegen_ode.c")


def h(x: float) -> str:
    return float(x).hex()


@pytest.fixture(scope="module")
def driver(tmp_path_factory, runtime_driver):
    """The driver, built with the strict flags against the runtime's sources."""
    exe = runtime_driver.build(tmp_path_factory.mktemp("analysis") / "analysis_driver",
                               "analysis_driver.c", RUNTIME)
    return runtime_driver.program(exe)


def analyze(driver, a, b, c, m=1.0, d=0.5, centre=0.0, route=DEFAULT, capacity=4):
    words = driver([f"analyze {route} {capacity} " + " ".join(map(h, (a, b, c, m, d, centre)))])[0]
    status, n = int(words[0]), int(words[1])
    roots, at = [], 2
    for _ in range(n):
        values = words[at:at + len(FIELDS)]
        roots.append({k: int(v) if k in INTEGERS else float.fromhex(v)
                      for k, v in zip(FIELDS, values)})
        at += len(FIELDS)
    n_uncertain = int(words[at])
    uncertain = [(float.fromhex(words[at + 1 + 3 * i]), float.fromhex(words[at + 2 + 3 * i]),
                  int(words[at + 3 + 3 * i])) for i in range(n_uncertain)]
    sigma = [float.fromhex(w) for w in words[at + 1 + 3 * n_uncertain:]]
    return status, roots, uncertain, sigma


def reference_roots(a, b, c, centre=0.0):
    """The zeros of a cos + b sin + c in (centre - pi, centre + pi]: R cos(theta - phi) = -c."""
    r, phi = math.hypot(a, b), math.atan2(b, a)
    if r == 0 or abs(c) > r:
        return []
    half = math.acos(-c / r)
    found = set()
    for theta in (phi + half, phi - half):
        theta = centre + math.remainder(theta - centre, 2 * math.pi)
        # the range is (centre - pi, centre + pi]: its lower end (to rounding) is its upper one
        found.add(theta if theta > centre - math.pi + 1e-12 else theta + 2 * math.pi)
    return sorted(found)


def vibration(K, m, d):
    """omega_n and zeta as complex numbers, and the classification, from K, M, B."""
    omega = complex(math.sqrt(K / m)) if K >= 0 else 1j * math.sqrt(-K / m)
    zeta = d / (2 * m * omega) if omega != 0 else complex(math.inf if d > 0 else 0)
    stability = UNSTABLE if K < 0 else STABLE if K > 0 and d > 0 else MARGINAL
    damping = (NOT_OSCILLATORY if K <= 0 else UNDAMPED if d == 0 else
               UNDERDAMPED if zeta.real < 1 else OVERDAMPED)
    return omega, zeta, stability, damping


def check_against_reference(roots, a, b, c, m, d, centre):
    expected = reference_roots(a, b, c, centre)
    assert len(roots) == len(expected), (roots, expected)
    scale = abs(a) + abs(b) + abs(c)
    for root, theta in zip(roots, expected):
        K = b * math.cos(theta) - a * math.sin(theta)
        slope = max(abs(K), 1e-300)
        assert root["certified"] == 1 and root["genuine"] == 1 and root["kind"] == 0
        assert root["lo"] <= theta <= root["hi"] or abs(root["theta"] - theta) < 1e-15 * scale / slope
        assert abs(root["theta"] - theta) <= 1e-13 * max(1.0, scale / slope)
        assert root["M"] == m and root["B"] == d
        assert root["K"] == pytest.approx(K, abs=1e-12 * scale)
        omega, zeta, stability, damping = vibration(root["K"], m, d)
        assert complex(root["omega_re"], root["omega_im"]) == pytest.approx(omega, rel=1e-14)
        assert complex(root["zeta_re"], root["zeta_im"]) == pytest.approx(zeta, rel=1e-14)
        assert root["stability"] == stability and root["damping"] == damping
        # the eigenvalues solve m s^2 + d s + K = 0
        for re, im in ((root["eig_re0"], root["eig_im0"]), (root["eig_re1"], root["eig_im1"])):
            s = complex(re, im)
            assert abs(m * s * s + d * s + root["K"]) <= 1e-12 * (m * abs(s) ** 2 + d * abs(s) + abs(K))


@pytest.mark.parametrize("route", [DEFAULT, ISOLATION])
def test_two_equilibria_as_the_closed_form_says(driver, route):
    a, b, c, m, d = 1.0, 0.5, 0.25, 1.0, 0.125
    status, roots, uncertain, sigma = analyze(driver, a, b, c, m, d, route=route)
    assert status == OK and not uncertain
    check_against_reference(roots, a, b, c, m, d, 0.0)
    assert [r["stability"] for r in roots] == [STABLE, UNSTABLE]
    # the polynomial in tan(theta/2), and none after the isolation
    assert sigma == ([a + c, 2 * b, c - a] if route == DEFAULT else [0.0, 0.0, 0.0])


@settings(max_examples=60, deadline=None)
@given(a=st.floats(-10, 10), b=st.floats(-10, 10), c=st.floats(-10, 10),
       m=st.floats(0.1, 10), d=st.floats(0, 5), centre=st.floats(-4, 4),
       route=st.sampled_from([DEFAULT, ISOLATION]))
def test_every_zero_of_g_is_found_and_proven(driver, a, b, c, m, d, centre, route):
    r = math.hypot(a, b)
    if r < 1e-3 or abs(abs(c) - r) < 1e-6 * r:
        return      # a double root or no G to speak of: decided by the tests below
    if route == DEFAULT and (abs(c - a) < 1e-6 * r or centre != 0.0):
        centre = 0.0  # the polynomial route covers (-pi, pi]; a root near pi: tau -> infinity
    status, roots, uncertain, _ = analyze(driver, a, b, c, m, d, centre, route)
    assert status == OK and not uncertain
    check_against_reference(roots, a, b, c, m, d, centre)


def test_a_range_centred_elsewhere_reports_its_angles_there(driver):
    status, roots, _, _ = analyze(driver, 1.0, 0.0, 0.5, centre=3.0, route=ISOLATION)
    assert status == OK
    assert all(3.0 - math.pi < r["theta"] <= 3.0 + math.pi for r in roots)
    check_against_reference(roots, 1.0, 0.0, 0.5, 1.0, 0.5, 3.0)


def test_a_double_root_is_uncertain_never_an_equilibrium(driver):
    # G = cos(theta) + 1 touches zero at pi without crossing it
    status, roots, uncertain, _ = analyze(driver, 1.0, 0.0, 1.0, route=ISOLATION)
    assert status == OK and roots == []
    lo, hi, _ = uncertain[0]
    assert len(uncertain) == 1 and any(lo <= math.pi + k * 2 * math.pi <= hi for k in (-1, 0))


@pytest.mark.parametrize("route", [DEFAULT, ISOLATION])
def test_no_zero_no_equilibrium(driver, route):
    status, roots, uncertain, _ = analyze(driver, 1.0, 1.0, 2.0, route=route)
    assert (status, roots, uncertain) == (OK, [], [])


@pytest.mark.parametrize("route", [DEFAULT, ISOLATION])
def test_g_identically_zero_is_every_angle(driver, route):
    assert analyze(driver, 0.0, 0.0, 0.0, route=route)[0] == EVERY_ANGLE


def test_more_equilibria_than_the_result_holds_is_a_capacity_error(driver):
    assert analyze(driver, 1.0, 0.0, 0.5, route=ISOLATION, capacity=1)[0] == CAPACITY
    assert analyze(driver, 1.0, 0.0, 0.5, route=ISOLATION, capacity=2)[0] == OK


def test_the_models_parameter_check_and_null_pointers(driver):
    assert analyze(driver, 1.0, 0.0, 0.5, m=0.0)[0] == ERR_MASS
    assert analyze(driver, math.nan, 0.0, 0.5)[0] == NONFINITE_PARAM
    assert driver(["null"])[0] == [str(NULL_POINTER)] * 5


def test_the_time_response_is_the_equation_of_motions(driver):
    a, b, c, m, d = 1.0, 0.5, 0.25, 2.0, 0.3
    times = np.linspace(0.0, 5.0, 11)
    words = driver([f"simulate {h(a)} {h(b)} {h(c)} {h(m)} {h(d)} {h(0.3)} {h(0.0)} "
                    f"{len(times)} " + " ".join(map(h, times))])[0]
    assert int(words[0]) == OK and int(words[1]) == len(times)
    got = np.array([float.fromhex(w) for w in words[2:]]).reshape(-1, 2)

    def rate(_, y):
        return [y[1], -(a * math.cos(y[0]) + b * math.sin(y[0]) + c + d * y[1]) / m]

    reference = solve_ivp(rate, (0.0, 5.0), [0.3, 0.0], t_eval=times, method="DOP853",
                          rtol=1e-12, atol=1e-14).y.T
    assert np.max(np.abs(got - reference)) < 1e-7


MODE_UNDECIDED_STATUS = 12


@pytest.mark.parametrize("w", [1.0, -1.0, 0.0])
def test_a_motion_is_on_the_sign_choice_its_conditions_declare(driver, w):
    """The two-mode model's condition is w on sign choice 0 and -w on choice 1: the motion
    integrates b's sign where the condition holds (b negated for w < 0), and a start where
    the condition decides nothing is refused (the mode undecided), never run on choice 0."""
    a, b, c, m, d = 1.0, 0.5, 0.25, 2.0, 0.3
    times = np.linspace(0.0, 5.0, 11)
    words = driver([f"simulate_modes {h(a)} {h(b)} {h(c)} {h(m)} {h(d)} {h(w)} {h(0.3)} "
                    f"{h(0.0)} {len(times)} " + " ".join(map(h, times))])[0]
    if w == 0:
        assert words == [str(MODE_UNDECIDED_STATUS), "0"]
        return
    assert int(words[0]) == OK and int(words[1]) == len(times)
    got = np.array([float.fromhex(x) for x in words[2:]]).reshape(-1, 2)
    b_declared = b if w > 0 else -b

    def rate(_, y):
        return [y[1], -(a * math.cos(y[0]) + b_declared * math.sin(y[0]) + c + d * y[1]) / m]

    reference = solve_ivp(rate, (0.0, 5.0), [0.3, 0.0], t_eval=times, method="DOP853",
                          rtol=1e-12, atol=1e-14).y.T
    assert np.max(np.abs(got - reference)) < 1e-7


def test_one_rk4_step_is_the_classical_formula(driver):
    a, b, c, m, d, step, theta, theta_d = 1.0, 0.0, 0.0, 1.0, 0.0, 0.0625, 0.25, 0.0
    words = driver([f"rk4 {h(a)} {h(b)} {h(c)} {h(m)} {h(d)} {h(step)} {h(theta)} {h(theta_d)}"])[0]

    def f(y):
        return np.array([y[1], -(a * math.cos(y[0]) + b * math.sin(y[0]) + c + d * y[1]) / m])

    y = np.array([theta, theta_d])
    k1 = f(y)
    k2 = f(y + step / 2 * k1)
    k3 = f(y + step / 2 * k2)
    k4 = f(y + step * k3)
    expected = y + step / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    assert int(words[0]) == OK
    assert [float.fromhex(w) for w in words[1:]] == pytest.approx(list(expected), abs=1e-15)


EQUILIBRIUM, OTHER_ASSEMBLY, MODE_UNDECIDED = 0, 1, 3


def analyze_modes(driver, a, b, c, w, absent=0.0):
    """The isolation route on the driver's two-mode model (mode 1: b negated), whose
    assembly-mode condition is w on mode 0 and -w on mode 1 (``absent``: mode 0 exists
    nowhere): [(theta, kind, mode, genuine, certified)]."""
    words = driver([f"modes {h(a)} {h(b)} {h(c)} {h(1.0)} {h(0.5)} {h(w)} {h(absent)}"])[0]
    assert int(words[0]) == OK
    fields = words[2:]
    return [(float.fromhex(fields[i]), *map(int, fields[i + 1:i + 5]))
            for i in range(0, 5 * int(words[1]), 5)]


@pytest.mark.parametrize("w", [1.0, -1.0, 0.0])
def test_each_equilibrium_is_named_by_the_mode_its_conditions_declare(driver, w):
    """The runtime names a root's mode by the model's conditions at it, not by the sign
    choice it was found on: a condition that flips sign (a parameter set where the other
    sign is the declared mode) swaps the names; one that holds on neither leaves the mode
    undecided (never the declared mode's equilibrium), each root still proven."""
    a, b, c = 1.0, 0.5, 0.2
    found = analyze_modes(driver, a, b, c, w)
    on_mode_0, on_mode_1 = reference_roots(a, b, c), reference_roots(a, -b, c)
    assert len(found) == len(on_mode_0) + len(on_mode_1) == 4
    for theta, kind, mode, genuine, certified in found:
        sign_choice = 0 if any(abs(theta - t) < 1e-12 for t in on_mode_0) else 1
        assert any(abs(theta - t) < 1e-12 for t in (on_mode_0, on_mode_1)[sign_choice])
        assert certified == 1
        if w == 0:
            assert (kind, mode, genuine) == (MODE_UNDECIDED, 2, 0)
        else:
            declared = sign_choice if w > 0 else 1 - sign_choice
            assert (mode, kind, genuine) == (declared, (EQUILIBRIUM, OTHER_ASSEMBLY)[declared],
                                             int(declared == 0))


def test_a_mode_is_linearised_where_another_mode_does_not_exist(driver):
    """In a chain of dyads one mode may exist where another does not (its radicand below 0,
    its values NaN): each root of the mode that exists is still proven and linearised from
    that mode's own values (they were read with every other mode's, and the root listed as
    singular)."""
    a, b, c = 1.0, 0.5, 0.2
    found = analyze_modes(driver, a, b, c, w=-1.0, absent=1.0)
    on_mode_1 = reference_roots(a, -b, c)
    assert len(found) == len(on_mode_1) == 2
    for (theta, kind, mode, genuine, certified), expected in zip(found, sorted(on_mode_1)):
        assert abs(theta - expected) < 1e-12
        assert (kind, mode, genuine, certified) == (EQUILIBRIUM, 0, 1, 1)
