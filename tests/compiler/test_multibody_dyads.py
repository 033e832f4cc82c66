"""Dyads inside mechanisms with several coordinates: a four-bar carrying a pendulum (2 DOF,
tests/models/four_bar_pendulum.py) against an independent 40-digit computation written here,
and the refusals a user meets when a dyad's assembly mode is not declared.

The reference shares nothing with the compiler: B is the intersection of the circles about A
(radius a_3) and O4 (radius a_4) on the declared side of O4-A, V is typed in from the bodies,
G and K are mpmath derivatives of V, M comes from numerical Jacobians of the bodies' centres
and angles. Every equilibrium: G_psi = m_p g l_p cos(psi) vanishes at psi = +-pi/2 only, and
G_theta does not depend on psi, so the equilibria are the zeros of G_theta (a dense scan of
the crank's turn with bisection) times those two angles.
"""
from __future__ import annotations

import math
from pathlib import Path

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from codegen.compiler.derivation.multibody import derive_multibody
from codegen.compiler.model import ModelError, load as load_model

MODEL = Path(__file__).resolve().parents[1] / "models" / "four_bar_pendulum.py"
EXAMPLE = dict(d=0.4, a_2=0.12, a_3=0.35, a_4=0.3, m_2=0.4, m_3=1.0, m_4=0.8, l_p=0.25,
               m_p=0.5, k_c=2.0, alpha=1.0, c_c=0.05, c_p=0.01, g=9.81)


@pytest.fixture(scope="module")
def lib(tmp_path_factory):
    from codegen.user_model import library

    return library(MODEL, tmp_path_factory.mktemp("four_bar_pendulum"))


# ------------------------------------------------------------------------- the reference

def _joints(p, theta):
    """A, B (the declared mode: (A - O4) x (B - O4) > 0), or None where the loop cannot
    close."""
    A = (p["a_2"] * mpmath.cos(theta), p["a_2"] * mpmath.sin(theta))
    ux, uy = A[0] - p["d"], A[1]                  # O4 -> A
    r = mpmath.sqrt(ux**2 + uy**2)
    along = (p["a_4"]**2 - p["a_3"]**2 + r**2) / (2 * r)
    across2 = p["a_4"]**2 - along**2
    if across2 < 0:
        return None
    across = mpmath.sqrt(across2)
    for side in (1, -1):
        B = (p["d"] + (along * ux - side * across * uy) / r,
             (along * uy + side * across * ux) / r)
        if ux * B[1] - uy * (B[0] - p["d"]) > 0:
            return A, B
    return None


def _potential(p, q):
    theta, psi = q
    A, B = _joints(p, theta)
    heights = (p["m_2"] * A[1] / 2 + p["m_3"] * (A[1] + B[1]) / 2 + p["m_4"] * B[1] / 2
               + p["m_p"] * (B[1] + p["l_p"] * mpmath.sin(psi)))
    return p["k_c"] * (theta - p["alpha"])**2 / 2 + p["g"] * heights


def _G_theta(p, theta):
    return mpmath.diff(lambda t: _potential(p, (t, 0)), theta)


def _stiffness(p, q):
    f = lambda a, b: _potential(p, (a, b))  # noqa: E731
    return [[mpmath.diff(f, q, (2, 0)), mpmath.diff(f, q, (1, 1))],
            [mpmath.diff(f, q, (1, 1)), mpmath.diff(f, q, (0, 2))]]


def _mass(p, q):
    """sum m J_c^T J_c + I J_a^T J_a with the Jacobians of each body's centre and angle."""
    def parts(theta, psi):
        A, B = _joints(p, theta)
        P = (B[0] + p["l_p"] * mpmath.cos(psi), B[1] + p["l_p"] * mpmath.sin(psi))
        phi_3 = mpmath.atan2(B[1] - A[1], B[0] - A[0])
        phi_4 = mpmath.atan2(B[1], B[0] - p["d"])
        return [(p["m_2"], A[0] / 2), (p["m_2"], A[1] / 2),
                (p["m_3"], (A[0] + B[0]) / 2), (p["m_3"], (A[1] + B[1]) / 2),
                (p["m_4"], (p["d"] + B[0]) / 2), (p["m_4"], B[1] / 2),
                (p["m_p"], P[0]), (p["m_p"], P[1]),
                (p["m_2"] * p["a_2"]**2 / 12, theta), (p["m_3"] * p["a_3"]**2 / 12, phi_3),
                (p["m_4"] * p["a_4"]**2 / 12, phi_4)]

    count = len(parts(*q))
    J = [[mpmath.diff(lambda a, b, k=k: parts(a, b)[k][1], q, (1, 0)),
          mpmath.diff(lambda a, b, k=k: parts(a, b)[k][1], q, (0, 1))] for k in range(count)]
    weights = [w for w, _ in parts(*q)]
    return [[sum(w * j[r] * j[c] for w, j in zip(weights, J)) for c in range(2)]
            for r in range(2)]


def reference_equilibria(params):
    """Every equilibrium (theta in (alpha - pi, alpha + pi], psi = +-pi/2), each with its
    stability and omega^2, at 40 digits."""
    with mpmath.workdps(40):
        p = {k: mpmath.mpf(v) for k, v in params.items()}
        grid = np.linspace(float(p["alpha"]) - math.pi, float(p["alpha"]) + math.pi, 1201)
        values = []
        for t in grid:
            values.append(None if _joints(p, mpmath.mpf(t)) is None
                          else _G_theta(p, mpmath.mpf(t)))
        roots = []
        for (a, ga), (b, gb) in zip(zip(grid, values), zip(grid[1:], values[1:])):
            if ga is None or gb is None or ga * gb > 0:
                continue
            lo, hi = mpmath.mpf(a), mpmath.mpf(b)
            for _ in range(120):
                mid = (lo + hi) / 2
                if _G_theta(p, mid) * _G_theta(p, lo) > 0:
                    lo = mid
                else:
                    hi = mid
            roots.append((lo + hi) / 2)
        found = []
        for theta in roots:
            for psi in (-mpmath.pi / 2, mpmath.pi / 2):
                K = np.array(_stiffness(p, (theta, psi)), dtype=float)
                M = np.array(_mass(p, (theta, psi)), dtype=float)
                w2 = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
                found.append({"q": [float(theta), float(psi)], "omega_squared": w2,
                              "stable": bool(np.all(np.linalg.eigvalsh(K) > 0))})
    return found


def _wrapped(q, params):
    """q with theta in (alpha - pi, alpha + pi] and psi in (-3 pi/2, pi/2]."""
    centre = (params["alpha"], -math.pi / 2)
    return [c + (x - c) - 2 * math.pi * round((x - c) / (2 * math.pi)) for x, c in zip(q, centre)]


def dead_points(params):
    """The crank angles where the loop just closes (coupler and rocker aligned), by bisection
    between angles where it closes and where it does not."""
    with mpmath.workdps(40):
        p = {k: mpmath.mpf(v) for k, v in params.items()}
        grid = np.linspace(-math.pi, math.pi, 721)
        closes = [_joints(p, mpmath.mpf(t)) is not None for t in grid]
        found = []
        for a, b, ca, cb in zip(grid, grid[1:], closes, closes[1:]):
            if ca != cb:
                lo, hi = mpmath.mpf(a), mpmath.mpf(b)
                for _ in range(100):
                    mid = (lo + hi) / 2
                    if (_joints(p, mid) is not None) == ca:
                        lo = mid
                    else:
                        hi = mid
                found.append(float(lo))
    return found


def check_against_reference(lib, params, dead=()):
    """The library's equilibria are the reference's; undecided boxes only at ``dead``
    (crank angles of a dead point, where G is not defined), each a singular one."""
    found = lib.analyze(params)
    expected = reference_equilibria(params)
    for u in found.uncertain:
        assert u.kind == "singular"
        centre = (u.lo[0] + u.hi[0]) / 2
        assert min(abs(math.remainder(centre - t, 2 * math.pi)) for t in dead) < 1e-6, u
    def order(q):   # the same crank angle twice (psi = +-pi/2): by psi, not by rounding
        return (round(q[0], 6), q[1])

    got = sorted(((_wrapped(e.theta, params), e) for e in found.equilibria),
                 key=lambda pair: order(pair[0]))
    want = sorted(((_wrapped(r["q"], params), r) for r in expected),
                  key=lambda pair: order(pair[0]))
    assert len(got) == len(want) > 0
    for (q, e), (r_q, r) in zip(got, want):
        assert q == pytest.approx(r_q, abs=1e-9)
        assert e.stable == r["stable"]
        assert np.sort(e.omega_squared) == pytest.approx(r["omega_squared"], rel=1e-7,
                                                         abs=1e-9)
    return found


# ------------------------------------------------------------------------------ tests

def test_the_example_matches_the_reference(lib):
    found = check_against_reference(lib, EXAMPLE)
    assert len(found.equilibria) == 2


def test_a_weak_crank_spring_gives_more_equilibria_all_found(lib):
    found = check_against_reference(lib, {**EXAMPLE, "k_c": 0.05, "m_p": 2.0})
    assert len(found.equilibria) >= 4


@pytest.mark.slow
@settings(max_examples=5, deadline=None, phases=(Phase.explicit, Phase.generate),
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(k_c=st.floats(0.05, 20), alpha=st.floats(-3, 3), m_p=st.floats(0.05, 3),
       l_p=st.floats(0.05, 1), m_3=st.floats(0.1, 3))
def test_drawn_parameter_sets_match_the_reference(lib, k_c, alpha, m_p, l_p, m_3):
    check_against_reference(lib, {**EXAMPLE, "k_c": k_c, "alpha": alpha, "m_p": m_p,
                                  "l_p": l_p, "m_3": m_3})


def test_a_crank_that_cannot_turn_fully_is_analysed_where_it_assembles(lib):
    """A crank too long for the loop to close at every angle (not a Grashof crank): the
    boxes where it cannot be assembled hold nothing, the equilibria where it can are the
    reference's, and the dead points (where the coupler and rocker align, G is undefined and
    the linkage can lock) are undecided boxes, never equilibria."""
    params = {**EXAMPLE, "a_2": 0.2, "a_3": 0.25, "alpha": 0.3, "k_c": 1.0}
    dead = dead_points(params)
    assert len(dead) == 2
    found = check_against_reference(lib, params, dead)
    assert {round(u.lo[0], 6) for u in found.uncertain} == {round(t, 6) for t in dead}


def _long_crank_model(tmp_path) -> Path:
    """four_bar_pendulum.py with a crank too long to turn fully (a_2 = 0.3 at its example:
    the loop opens for crank angles near pi), renamed."""
    text = MODEL.read_text()
    for old, new in (('"crank length", "0.12"', '"crank length", "0.3"'),
                     ('name="four_bar_pendulum"', 'name="long_crank_pendulum"')):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "long_crank_pendulum.py"
    path.write_text(text)
    return path


def test_the_check_at_generation_draws_other_points_where_the_loop_is_open(tmp_path):
    """Each parameter set is checked at POINTS points where the loop closes, drawn again
    where it does not (not fewer points for a crank that cannot turn fully)."""
    from codegen.compiler.emission.multibody import build_multibody_plan
    from codegen.compiler.verification import SETS
    from codegen.compiler.verification_multibody import POINTS, verify_multibody

    d = derive_multibody(load_model(str(_long_crank_model(tmp_path))))
    n = 2   # per point: G and h (n each), K, M and B (n^2 each)
    assert verify_multibody(d, build_multibody_plan(d)) == SETS * POINTS * (2 * n + 3 * n * n)


def test_a_model_whose_crank_cannot_turn_fully_at_its_example_is_generated(tmp_path):
    """Issue 48: the crank made too long for the loop to close over its whole turn at the
    model's own example (a_2 = 0.3: the loop opens for crank angles near pi). The checks at
    generation skip the points where the loop does not close (they crashed on mpmath's
    complex positions), and the library's equilibria are the brute-force reference's: the
    boxes where the loop is open hold nothing, its dead points are undecided boxes."""
    from codegen.user_model import library

    long_crank = library(_long_crank_model(tmp_path), tmp_path / "build")
    params = {**EXAMPLE, "a_2": 0.3}
    dead = dead_points(params)
    assert len(dead) == 2
    found = check_against_reference(long_crank, params, dead)
    for t in dead:   # each dead point undecided (once per psi = +-pi/2)
        assert any(abs(math.remainder(u.lo[0] - t, 2 * math.pi)) < 1e-6 for u in found.uncertain)
    closed = [_joints({k: mpmath.mpf(v) for k, v in params.items()}, mpmath.mpf(e.theta[0]))
              for e in found.equilibria]
    assert all(c is not None for c in closed)


def test_positions_close_the_loop_in_the_declared_mode(lib):
    rng = np.random.default_rng(3)
    for theta in rng.uniform(-math.pi, math.pi, 20):
        coords = lib.positions(EXAMPLE, [theta, 0.3])
        with mpmath.workdps(30):
            A, B = _joints({k: mpmath.mpf(v) for k, v in EXAMPLE.items()}, mpmath.mpf(theta))
        phi_3, phi_4 = coords[2], coords[3]
        assert math.atan2(float(B[1] - A[1]), float(B[0] - A[0])) == pytest.approx(phi_3,
                                                                                  abs=1e-12)
        assert math.atan2(float(B[1]), float(B[0]) - EXAMPLE["d"]) == pytest.approx(phi_4,
                                                                                   abs=1e-12)


def test_the_time_response_of_the_undamped_linkage_keeps_its_energy(lib):
    params = {**EXAMPLE, "c_c": 0.0, "c_p": 0.0}
    e = next(e for e in lib.analyze(params).equilibria if e.stable)
    trajectory = lib.simulate(params, e.theta + np.array([0.3, 0.4]), [0.0, 0.0],
                              np.linspace(0, 2, 41), rtol=1e-11, atol=1e-13)
    energy = np.array([sum(lib.energies(params, q, v))
                       for q, v in zip(trajectory.theta, trajectory.theta_d)])
    assert np.ptp(energy) < 1e-7 * abs(lib.energies(params, e.theta, [0, 0])[1] - energy[0])


def _variant(tmp_path, old: str, new: str) -> Path:
    text = MODEL.read_text()
    assert old in text
    path = tmp_path / "variant.py"
    path.write_text(text.replace(old, new))
    return path


def test_a_dyad_without_a_declared_assembly_mode_is_refused(tmp_path):

    path = _variant(tmp_path, "        assembly_modes=(", "        assembly_modes=() and (")
    with pytest.raises(ModelError, match=r"phi_3 is fixed by a dyad.*declare assembly_modes"):
        derive_multibody(load_model(str(path)))


def test_an_assembly_mode_that_does_not_tell_the_modes_apart_is_refused(tmp_path):

    path = _variant(tmp_path, "assembly_modes=((A[0] - d) * (B[1] - 0) - (A[1] - 0) * (B[0] - d),)",
                    "assembly_modes=(d,)")
    with pytest.raises(ModelError, match="do not tell the assembly modes of phi_3 apart"):
        derive_multibody(load_model(str(path)))


@pytest.mark.slow
def test_a_users_model_with_a_dyad_goes_into_an_fmu(lib, tmp_path):
    """The user's build (not a shipped library) as an FMU: validated by fmpy, its
    Co-Simulation the library's motion."""
    fmpy = pytest.importorskip("fmpy")
    from fmpy.validation import validate_fmu

    from codegen.fmu import write_fmu

    path = write_fmu(lib, tmp_path / "four_bar_pendulum.fmu")
    assert validate_fmu(str(path)) == []
    times = np.linspace(0.0, 0.5, 6)
    start = {"theta": 0.3, "psi": -1.2}
    result = fmpy.simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=0.5,
                               output_interval=0.1, start_values=start, output=["theta", "psi"],
                               relative_tolerance=1e-12)
    expected = lib.simulate(EXAMPLE, [0.3, -1.2], [0.0, 0.0], times, rtol=1e-12, atol=1e-15)
    assert np.allclose(result["theta"], expected.theta[:, 0], rtol=1e-8, atol=1e-9)
    assert np.allclose(result["psi"], expected.theta[:, 1], rtol=1e-8, atol=1e-9)
