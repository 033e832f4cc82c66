"""Mechanisms with n coordinates (issue 31): every equilibrium in the box of the ranges, each
proven, and its modes, against an independent 40-digit computation (multibody_reference.py:
its own kinematics and potential, numerical derivatives, its own search for the zeros)."""
from __future__ import annotations

import math
from pathlib import Path

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import multibody_reference as reference
from codegen.api import load
from codegen.compiler.derivation.multibody import derive_multibody
from codegen.compiler.emission.multibody import build_multibody_plan
from codegen.compiler.model import ModelError, load as load_model
from codegen.compiler.verification import VerificationError
from codegen.compiler.verification_multibody import verify_multibody

NAMES = ("double_pendulum", "flexible_doughty")
GUIDE = Path(__file__).resolve().parents[2] / "docs" / "multibody.md"


def triple_pendulum(folder: Path) -> Path:
    """The model file docs/multibody.md lists, written into folder."""
    text = GUIDE.read_text().split("## A model with three coordinates", 1)[1]
    path = folder / "triple_pendulum.py"
    path.write_text(text.split("```python\n", 1)[1].split("```", 1)[0])
    return path


def agree(library, name: str, params: dict, uncertain: bool = False) -> list[dict]:
    """The library's analysis matches the reference's equilibria one to one: coordinates,
    stability, natural frequencies and damped eigenvalues. With ``uncertain``, boxes the
    library could not decide are allowed: a reference equilibrium inside one is not missed,
    and no proven equilibrium may lie in none of the reference's. The reference's
    equilibria."""
    analysis = library.analyze(params)
    expected = reference.equilibria(name, params)
    assert uncertain or not analysis.uncertain, analysis.uncertain

    def undecided(q) -> bool:
        return any(np.all(u.lo - 1e-9 <= q) and np.all(q <= u.hi + 1e-9)
                   for u in analysis.uncertain)

    expected = [r for r in expected if not undecided(np.array(r["q"], dtype=float))]
    found = sorted(analysis.equilibria, key=lambda e: tuple(e.theta))
    assert len(found) == len(expected), ([e.theta for e in found], [e["q"] for e in expected])
    for e, r in zip(found, expected):
        assert np.allclose(e.theta, r["q"], rtol=0, atol=1e-9), (e.theta, r["q"])
        assert np.all(e.lo <= e.theta) and np.all(e.theta <= e.hi)
        assert e.stable == r["stable"]
        w2 = np.array([float(x) for x in r["omega_squared"]])
        assert np.allclose(e.omega_squared, w2, rtol=1e-7, atol=1e-7 * np.abs(w2).max())
        s = np.array([complex(x) for x in r["s"]])
        assert np.allclose(np.sort_complex(e.eigenvalues), np.sort_complex(s), rtol=1e-6,
                           atol=1e-6 * np.abs(s).max())
    return expected


@pytest.mark.parametrize("name", NAMES)
def test_the_examples_equilibria_and_modes_match_the_reference(name):
    lib = load(name)
    expected = agree(lib, name, lib.EXAMPLE)
    assert len(expected) == {"double_pendulum": 3, "flexible_doughty": 6}[name]


def test_the_double_pendulum_buckles_as_described():
    """The example's upright is unstable and it has two buckled stable equilibria; stiffer
    springs hold it upright alone."""
    lib = load("double_pendulum")
    stability = [e.stability for e in lib.analyze().equilibria]
    assert stability == ["stable", "unstable", "stable"]
    stiff = lib.analyze({**lib.EXAMPLE, "k_1": 60.0, "k_2": 40.0})
    assert len(stiff.equilibria) == 1 and stiff.equilibria[0].stable
    assert np.allclose(stiff.equilibria[0].theta, [math.pi / 2, 0], atol=1e-12)


SPRINGS = {"double_pendulum": ("k_1", "k_2"), "flexible_doughty": ("k", "k_t")}


@pytest.mark.parametrize("name", NAMES)
@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_drawn_parameter_sets_match_the_reference(name, data):
    lib = load(name)
    params = dict(lib.EXAMPLE)
    for key in params:
        if params[key] > 0 and key not in ("alpha_1",):
            params[key] *= data.draw(st.floats(0.7, 1.3), label=key)
    # With the spring's anchor exactly at reach of its attachment (H = a), its length vanishes
    # along a whole ridge through the box (to first order): the isolation runs out of boxes
    # there and says so (ERR_CAPACITY, docs/multibody.md), which is not what this test draws.
    assume(name != "flexible_doughty" or abs(params["H"] - params["a"]) > 1e-6 * params["a"])
    # where the spring's anchor can meet its attachment (H = a cos theta_1), its length
    # vanishes and G is not smooth: boxes there are undecided, never equilibria
    agree(lib, name, params, uncertain=True)


def test_where_the_spring_length_vanishes_the_boxes_are_undecided_not_equilibria():
    lib = load("flexible_doughty")
    params = {**lib.EXAMPLE, "H": 0.135, "a": 0.16875}
    analysis = lib.analyze(params)
    assert analysis.uncertain and {u.kind for u in analysis.uncertain} <= {"singular", "cluster"}
    theta_1 = math.acos(params["H"] / params["a"])   # a cos theta_1 = H: P can reach (H, 0)
    assert all(abs(abs((u.lo[0] + u.hi[0]) / 2) - theta_1) < 1e-6 for u in analysis.uncertain)
    agree(lib, "flexible_doughty", params, uncertain=True)


@pytest.mark.parametrize("scale", [0.1, 0.3])
def test_weak_springs_give_many_equilibria_all_found(scale):
    lib = load("double_pendulum")
    params = {**lib.EXAMPLE, "k_1": 30 * scale, "k_2": 15 * scale, "F_x": 0.7}
    assert len(agree(lib, "double_pendulum", params)) >= 3


def upright_threshold(params: dict) -> float:
    """k_1 at which the upright double pendulum (theta_1 = pi/2, delta = 0) loses stability:
    K there is K_0 + k_1 e_1 e_1^T, so det K = det K_0 + k_1 K_0[1, 1] vanishes at
    k_1 = -det K_0 / K_0[1, 1] (the reference's K, at k_1 = 0)."""
    K0 = reference.stiffness("double_pendulum", {**params, "k_1": 0.0}, [math.pi / 2, 0.0])
    return float(-mpmath.det(K0) / K0[1, 1])


@pytest.mark.parametrize("side", [-1, 1])
def test_either_side_of_the_buckling_threshold_the_count_changes_by_two(side):
    lib = load("double_pendulum")
    params = dict(lib.EXAMPLE)
    threshold = upright_threshold(params)
    assert 25 < threshold < 40  # "stable only for k_1 above about 31"
    near = {**params, "k_1": threshold * (1 + side * 1e-6)}
    analysis = lib.analyze(near)
    # the buckled pair is 1e-3 rad from the upright here: proven apart, or else reported as
    # a cluster there, never miscounted
    if analysis.uncertain:
        assert all(np.allclose((u.lo + u.hi) / 2, [math.pi / 2, 0], atol=1e-2)
                   for u in analysis.uncertain)
        assert not any(np.allclose(e.theta, [math.pi / 2, 0], atol=1e-2)
                       for e in analysis.equilibria)
        return
    assert len(analysis.equilibria) == (3 if side < 0 else 1)
    agree(lib, "double_pendulum", near)


def test_a_stiff_joint_gives_doughtys_equilibria_and_first_mode():
    """k_t = 1e6: the equilibria with theta_1 = theta_2 within 1e-4 rad of the paper's
    mechanism's, and the first mode's omega_n and zeta within 1e-3 of its own."""
    flexible = load("flexible_doughty").analyze({**load("flexible_doughty").EXAMPLE,
                                                 "k_t": 1e6})
    rigid = [e for e in load("doughty").analyze().roots if e.genuine]
    assert len(flexible.equilibria) == len(rigid)
    for e, r in zip(flexible.equilibria, sorted(rigid, key=lambda r: r.theta)):
        assert abs(e.theta[0] - r.theta) < 1e-4 and abs(e.theta[1]) < 1e-4
        assert e.stable == (r.stability == "stable")
        if e.stable:
            assert abs(e.frequencies[0] / r.omega_n.real - 1) < 1e-3
            assert abs(e.modal_damping[0] / r.zeta.real - 1) < 1e-3


def test_the_hanging_double_pendulum_has_the_textbook_frequencies():
    """No springs, no tip mass, hanging: the two frequencies of the closed form
    det(K - w^2 M) = 0 with M = [[(m1/3 + m2) l1^2, m2 l1 l2/2], [m2 l1 l2/2, m2 l2^2/3]],
    K = g diag((m1/2 + m2) l1, m2 l2/2) (absolute angles), and M-orthonormal shapes."""
    lib = load("double_pendulum")
    p = {**lib.EXAMPLE, "k_1": 0.0, "k_2": 0.0, "m_t": 0.0, "alpha_1": -math.pi / 2}
    l1, l2, m1, m2, g = (p[k] for k in ("l_1", "l_2", "m_1", "m_2", "g"))
    a, b, c = (m1 / 3 + m2) * l1**2, m2 * l1 * l2 / 2, m2 * l2**2 / 3
    k1, k2 = g * (m1 / 2 + m2) * l1, g * m2 * l2 / 2
    # det([[k1 - w2 a, -w2 b], [-w2 b, k2 - w2 c]]) = (ac - b^2) w2^2 - (k1 c + k2 a) w2 + k1 k2
    A, B, C = a * c - b * b, -(k1 * c + k2 * a), k1 * k2
    roots = sorted(((-B - s * math.sqrt(B * B - 4 * A * C)) / (2 * A)) for s in (1, -1))
    hanging = [e for e in lib.analyze(p).equilibria if e.stable]
    assert len(hanging) == 1
    e = hanging[0]
    assert np.allclose(e.theta, [-math.pi / 2, 0], atol=1e-12)
    assert np.allclose(e.omega_squared, roots, rtol=1e-12)
    M = np.reshape(lib.mass_matrix(p, e.theta), (2, 2))
    assert np.allclose(e.shapes.T @ M @ e.shapes, np.eye(2), atol=1e-12)


def test_the_receptance_is_the_inverse_dynamic_stiffness():
    lib = load("double_pendulum")
    e = lib.analyze().equilibria[0]
    p = lib.EXAMPLE
    M, B, K = (np.reshape(f(p, e.theta), (2, 2)) for f in
               (lib.mass_matrix, lib.damping_matrix, lib.stiffness_matrix))
    omega = np.array([0.0, 0.5, e.frequencies[1], 40.0])
    H = lib.receptance(p, e.theta, omega)
    for w, h in zip(omega, H):
        assert np.allclose(h, np.linalg.inv(K - w * w * M + 1j * w * B), rtol=1e-10)


def test_the_linearisation_is_symmetric_and_k_is_the_slope_of_g():
    lib = load("flexible_doughty")
    p, theta = lib.EXAMPLE, np.array([0.3, -0.02])
    K = np.reshape(lib.stiffness_matrix(p, theta), (2, 2))
    assert np.allclose(K, K.T, rtol=1e-12)
    h = 1e-6
    slope = np.column_stack([(np.array(lib.generalised_force(p, theta + h * d))
                              - np.array(lib.generalised_force(p, theta - h * d))) / (2 * h)
                             for d in np.eye(2)])
    assert np.allclose(slope, K, rtol=1e-6)


def test_the_energy_functions_agree_with_the_mass_matrix():
    lib = load("double_pendulum")
    p, theta, rates = lib.EXAMPLE, np.array([1.0, 0.4]), np.array([0.3, -1.1])
    T, V = lib.energies(p, theta, rates)
    M = np.reshape(lib.mass_matrix(p, theta), (2, 2))
    assert T == pytest.approx(rates @ M @ rates / 2, rel=1e-13)
    assert V == pytest.approx(float(reference.potential("double_pendulum", p, theta))
                              - float(reference.potential("double_pendulum", p, [0.0, 0.0]))
                              + float(lib.energies(p, [0.0, 0.0], [0.0, 0.0])[1]), rel=1e-12)


def test_a_derivation_that_disagrees_with_the_model_is_refused():
    d = derive_multibody(load_model("double_pendulum"))
    wrong = type(d)(**{**d.__dict__, "mass": d.mass.applyfunc(lambda e: e * 1.001)})
    with pytest.raises(VerificationError, match="M disagrees"):
        verify_multibody(wrong, build_multibody_plan(wrong))
    sign = type(d)(**{**d.__dict__, "generalised_force": -d.generalised_force})
    with pytest.raises(VerificationError, match="G disagrees"):
        verify_multibody(sign, build_multibody_plan(sign))


def test_a_dependent_coordinate_no_constraint_solves_is_refused(tmp_path):
    source = triple_pendulum(tmp_path).read_text()
    bad = source.replace("theta_2 - theta_1 - delta_2", "theta_2**2 - theta_1 - delta_2")
    path = tmp_path / "bad.py"
    path.write_text(bad)
    with pytest.raises(ModelError, match="theta_2, theta_3 cannot be solved"):
        derive_multibody(load_model(str(path)))


@pytest.mark.slow   # a whole generation and build: 8 s
def test_a_users_three_coordinate_model_through_the_command_line(tmp_path):
    """A triple pendulum written in a model file of its own, generated, built and analysed by
    `mechvib analyze --model`, with springs weak enough to buckle it, against the reference."""
    import json
    import subprocess
    import sys

    weak = {"k_1": 4.0, "k_2": 2.5, "k_3": 1.2}
    command = [sys.executable, "-m", "codegen", "analyze", "--model",
               str(triple_pendulum(tmp_path)),
               "--out", str(tmp_path / "build"), "--json"]
    for name, value in weak.items():
        command += ["--set", f"{name}={value}"]
    out = subprocess.run(command, capture_output=True, text=True, check=True)
    found = json.loads(out.stdout)
    params = {**reference.EXAMPLES["triple_pendulum"], **weak}
    expected = reference.equilibria("triple_pendulum", params)
    assert not found["uncertain"] and found["method"] == "isolate"
    keys = [c["key"] for c in found["coordinates"]]
    assert keys == ["theta_1_deg", "delta_2_deg", "delta_3_deg"]
    assert len(found["roots"]) == len(expected) >= 3

    def theta(e):   # the JSON's angles are in degrees
        return np.radians([e[k] for k in keys])

    for e, r in zip(sorted(found["roots"], key=lambda e: tuple(theta(e))), expected):
        assert np.allclose(theta(e), r["q"], atol=1e-9)
        assert (e["stability"] == "stable") == r["stable"]
        assert np.allclose(e["omega_squared"], [float(x) for x in r["omega_squared"]],
                           rtol=1e-7, atol=1e-9)


@pytest.mark.parametrize("name", NAMES)
def test_the_undamped_time_response_keeps_its_energy(name):
    lib = load(name)
    params = {**lib.EXAMPLE, **{k: 0.0 for k in ("c_1", "c_2", "b", "c_t") if k in lib.EXAMPLE}}
    start = lib.analyze(params).equilibria[-1].theta + np.array([0.05, 0.01])
    trajectory = lib.simulate(params, start, [0.0, 0.0], np.linspace(0, 2, 41))
    energy = np.array([sum(lib.energies(params, q, v))
                       for q, v in zip(trajectory.theta, trajectory.theta_d)])
    swing = max(abs(lib.energies(params, q, v)[0])
                for q, v in zip(trajectory.theta, trajectory.theta_d))
    assert swing > 0 and np.ptp(energy) < 1e-6 * swing


def test_the_damped_time_response_loses_energy_to_its_dampers():
    lib = load("double_pendulum")
    trajectory = lib.simulate(None, [1.2, 0.3], [0.0, 0.0], np.linspace(0, 4, 81))
    energy = np.array([sum(lib.energies(lib.EXAMPLE, q, v))
                       for q, v in zip(trajectory.theta, trajectory.theta_d)])
    assert np.all(np.diff(energy) <= 1e-9 * abs(energy).max())


def test_a_failed_integration_keeps_the_motion_before_the_failure():
    """The step budget runs out part way: IntegrationError names the time and the budget and
    holds the prefix of the full motion, bit for bit (the same steps)."""
    from codegen.runtime.simulation import IntegrationError

    lib = load("double_pendulum")
    times = np.linspace(0.0, 2.0, 201)
    full = lib.simulate(None, [1.2, 0.3], [0.0, 0.0], times)
    with pytest.raises(IntegrationError) as error:
        lib.simulate(None, [1.2, 0.3], [0.0, 0.0], times, max_steps=20)
    partial = error.value.trajectory
    n = len(partial.t)
    assert error.value.code == "ERR_STEP_BUDGET" and error.value.values["max_steps"] == 20
    assert 1 < n < len(times) and partial.t[-1] == error.value.values["t"]
    assert np.array_equal(partial.theta, full.theta[:n])
    assert np.array_equal(partial.theta_d, full.theta_d[:n])


@pytest.mark.parametrize("name", NAMES)
def test_a_small_motion_about_a_stable_equilibrium_follows_its_linearisation(name):
    """theta(t) - theta_E against expm(A t) x0, A = [[0, I], [-M^-1 K, -M^-1 B]] (scipy), for a
    1e-6 rad start: the difference is second order in the amplitude."""
    from scipy.linalg import expm

    lib = load(name)
    e = next(e for e in lib.analyze().equilibria if e.stable)
    p = lib.EXAMPLE
    M, B, K = (np.reshape(f(p, e.theta), (2, 2)) for f in
               (lib.mass_matrix, lib.damping_matrix, lib.stiffness_matrix))
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, B)]])
    assert np.allclose(np.sort_complex(np.linalg.eigvals(A)), np.sort_complex(e.eigenvalues),
                       rtol=1e-8)
    amplitude = 1e-6
    x0 = np.array([amplitude, -amplitude, 0.0, 0.0])
    times = np.linspace(0, 4 / np.abs(e.eigenvalues).min(), 21)
    trajectory = lib.simulate(p, e.theta + x0[:2], x0[2:], times, rtol=1e-12, atol=1e-16)
    for t, q in zip(times, trajectory.theta):
        linear = (expm(A * t) @ x0)[:2]
        assert np.allclose(q - e.theta, linear, atol=1e-3 * amplitude)


def test_the_time_response_through_the_command_line(tmp_path):
    """`mechvib simulate` with several coordinates: one initial value per coordinate (degrees),
    a column per coordinate and rate equal to the Python call's, and --linearised beside it
    equal to scipy's expm of the library's state matrix."""
    import csv
    import io
    import json
    import subprocess
    import sys

    from scipy.linalg import expm

    run = [sys.executable, "-m", "codegen", "simulate", "--mechanism", "double_pendulum",
           "--theta0", "70", "-5", "--thetadot0", "0", "20", "--to", "0.5", "--points", "6"]
    table = list(csv.DictReader(io.StringIO(
        subprocess.run(run, capture_output=True, text=True, check=True).stdout)))
    lib = load("double_pendulum")
    start = np.radians([70.0, -5.0]), np.radians([0.0, 20.0])
    expected = lib.simulate(None, *start, np.linspace(0, 0.5, 6))
    assert [list(row) for row in table[:1]] == [
        ["t_s", "theta_1_deg", "delta_deg", "theta_1dot_deg_s", "deltadot_deg_s"]]
    for row, q, v in zip(table, expected.theta, expected.theta_d):
        assert [float(row[c]) for c in ("theta_1_deg", "delta_deg")] == pytest.approx(
            np.degrees(q), rel=1e-15)
        assert [float(row[c]) for c in ("theta_1dot_deg_s", "deltadot_deg_s")] == pytest.approx(
            np.degrees(v), rel=1e-15)
    out = subprocess.run(run + ["--linearised", "--out", str(tmp_path / "m.json"), "--plot",
                                str(tmp_path / "m.png")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "Linearised about the stable equilibrium" in " ".join(out.stdout.split())
    document = json.loads((tmp_path / "m.json").read_text())
    linear = document["linearised"]
    e = min((e for e in lib.analyze().equilibria if e.stable),
            key=lambda e: np.linalg.norm(e.theta - start[0]))
    assert linear["equilibrium"] == pytest.approx(e.theta, abs=1e-12)
    p = lib.EXAMPLE
    M, B, K = (np.reshape(f(p, e.theta), (2, 2)) for f in
               (lib.mass_matrix, lib.damping_matrix, lib.stiffness_matrix))
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, B)]])
    x0 = np.concatenate([start[0] - e.theta, start[1]])
    for k, t in enumerate(document["t_s"]):
        x = expm(A * t) @ x0
        assert [linear["theta_1_deg"][k], linear["delta_deg"][k]] == pytest.approx(
            np.degrees(e.theta + x[:2]), rel=1e-10, abs=1e-10)
        assert [linear["theta_1dot_deg_s"][k], linear["deltadot_deg_s"][k]] == pytest.approx(
            np.degrees(x[2:]), rel=1e-10, abs=1e-9)
    assert (tmp_path / "m.png").stat().st_size > 10_000


def test_the_command_lines_time_response_checks_the_state_and_keeps_what_a_failure_leaves(
        tmp_path):
    import subprocess
    import sys

    base = [sys.executable, "-m", "codegen", "simulate", "--mechanism", "double_pendulum",
            "--to", "1"]
    out = subprocess.run(base + ["--theta0", "70"], capture_output=True, text=True)
    assert out.returncode != 0 and "one value per coordinate" in out.stderr
    assert "theta_1, delta" in out.stderr and "Traceback" not in out.stderr
    out = subprocess.run(base + ["--theta0", "70", "0", "--max-steps", "5", "--out",
                                 str(tmp_path / "m.csv")], capture_output=True, text=True)
    assert out.returncode != 0 and "Traceback" not in out.stderr
    assert "points before it written to" in out.stderr
    rows = (tmp_path / "m.csv").read_text().splitlines()
    assert 2 <= len(rows) < 1002 and rows[1].split(",")[1] == "70"


@pytest.mark.parametrize("seed", range(40))
def test_the_state_transition_is_scipys_expm(seed):
    """multibody_motion.expm against scipy's on random, badly scaled and defective (a Jordan
    block: critical damping) matrices."""
    from scipy.linalg import expm as reference_expm

    from codegen.runtime.multibody_motion import expm

    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 7))
    A = rng.normal(size=(n, n)) * 10.0 ** rng.uniform(-3, 1.5)
    if seed % 4 == 0:   # defective: a repeated eigenvalue with one eigenvector
        J = np.diag(np.full(n, rng.normal())) + np.diag(np.ones(n - 1), 1)
        V = rng.normal(size=(n, n))
        A = V @ J @ np.linalg.inv(V)
    expected = reference_expm(A)
    assert np.allclose(expm(A), expected, rtol=1e-11, atol=1e-13 * np.abs(expected).max())


def test_the_frequency_response_through_the_command_line(tmp_path):
    """`mechvib frf` with several coordinates: each coordinate's amplitude and phase per unit
    force on the driven one, equal to the inverse dynamic stiffness built from the library's
    M, B, K; a JSON table and a figure."""
    import csv
    import io
    import json
    import subprocess
    import sys

    run = [sys.executable, "-m", "codegen", "frf", "--mechanism", "double_pendulum",
           "--drive", "delta", "--points", "7"]
    table = list(csv.DictReader(io.StringIO(
        subprocess.run(run, capture_output=True, text=True, check=True).stdout)))
    lib = load("double_pendulum")
    e = next(e for e in lib.analyze().equilibria if e.stable)
    p = lib.EXAMPLE
    M, B, K = (np.reshape(f(p, e.theta), (2, 2)) for f in
               (lib.mass_matrix, lib.damping_matrix, lib.stiffness_matrix))
    assert len(table) == 7 and float(table[-1]["omega"]) == pytest.approx(
        3 * e.frequencies.max())
    for row in table:
        w = float(row["omega"])
        column = np.linalg.inv(K - w * w * M + 1j * w * B)[:, 1]
        for i, name in enumerate(("theta_1", "delta")):
            assert float(row[f"amplitude_{name}"]) == pytest.approx(abs(column[i]), rel=1e-10)
            assert float(row[f"phase_deg_{name}"]) == pytest.approx(
                math.degrees(np.angle(column[i])), abs=1e-8)
    out = subprocess.run(run + ["--out", str(tmp_path / "frf.json"), "--plot",
                                str(tmp_path / "frf.png")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    document = json.loads((tmp_path / "frf.json").read_text())
    assert document["drive"] == "delta"
    assert document["natural_frequencies_hz"] == pytest.approx(e.frequencies / (2 * math.pi))
    assert (tmp_path / "frf.png").stat().st_size > 10_000


def test_a_sweep_has_a_row_per_equilibrium_as_the_analysis_finds_them():
    from codegen.runtime import sweep

    lib = load("double_pendulum")
    sets = sweep.grid(lib, {"k_1": np.linspace(5, 40, 6), "F_x": [0.0, 1.5]})
    rows = sweep.sweep(lib, sets, chunk=5, workers=2)
    assert set(rows["set"]) == set(range(len(sets)))
    for s, values in enumerate(sets):
        analysis = lib.analyze({name: float(values[name]) for name in lib.PARAMETER_NAMES})
        mine = rows[rows["set"] == s]
        assert len(mine) == len(analysis.equilibria) and np.all(mine["uncertain"] == 0)
        for row, e in zip(mine, analysis.equilibria):
            assert (row["theta_1"], row["delta"]) == tuple(e.theta)
            assert sweep.LABELS["stability"][row["stability"]] == e.stability
            assert np.array_equal([row["omega_n_1"], row["omega_n_2"]], e.frequencies,
                                  equal_nan=True)
            assert np.array_equal([row["zeta_1"], row["zeta_2"]], e.modal_damping,
                                  equal_nan=True)


def test_a_sweep_over_dask_gives_the_same_rows():
    """A dask array of sets, and the chunks on a local cluster's worker processes (which load
    the library again by its origin): the bytes of the local sweep."""
    da = pytest.importorskip("dask.array")
    distributed = pytest.importorskip("distributed")
    from codegen.runtime import sweep

    lib = load("flexible_doughty")
    sets = sweep.sample(lib, 12, {"k": (3000, 4000), "k_t": (500, 5000)}, seed=3)
    local = sweep.sweep(lib, sets)
    assert sweep.sweep(lib, da.from_array(sets, chunks=5)).tobytes() == local.tobytes()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = sweep.sweep(lib, sets, client=client, chunk=4)
    assert remote.tobytes() == local.tobytes()


def test_a_root_whose_tightest_box_rounding_hides_is_still_reported_at_its_zero():
    """Found by the benchmark: here the enclosures' rounding near a buckled equilibrium
    exceeds G's change across a box a few ulps wide, so that box could not be proven; the
    root used to be reported at the middle of its wide proven box, 4e-3 rad off. Wider
    boxes around the Newton point are tried now, and the point reported is Newton's."""
    lib = load("double_pendulum")
    params = {"l_1": 0.9551513472513712, "l_2": 0.7809556700228129, "m_1": 1.0132977388176365,
              "m_2": 0.7712400778176006, "m_t": 0.517480373426896, "k_1": 30.571188952997353,
              "k_2": 14.884745045390686, "alpha_1": 1.5799950925874697, "alpha_2": 0.0,
              "c_1": 0.3127682934049044, "c_2": 0.208506128599657, "F_x": 0.0,
              "g": 9.571055351046294}
    for e in lib.analyze(params).equilibria:
        assert np.all(e.hi - e.lo < 1e-10)
    agree(lib, "double_pendulum", params)


def test_a_ridge_of_zero_spring_length_is_refused_not_guessed():
    """H = a: the isolation cannot decide the ridge where the spring's length vanishes and
    runs out of its budget of boxes: an error, never a partial list."""
    lib = load("flexible_doughty")
    with pytest.raises(lib.LibraryError, match="more equilibria or uncertain"):
        lib.analyze({**lib.EXAMPLE, "H": lib.EXAMPLE["a"]})


@pytest.mark.parametrize("name", NAMES)
def test_the_analysis_in_the_callers_memory_is_the_same_bit_for_bit(name):
    """NAME_analyze_work (the workspace the caller's, for firmware) against NAME_analyze (its
    own on the stack): the same result to the byte; a NULL workspace is refused."""
    lib = load(name)
    ffi, c, P = lib.ffi, lib.lib, lib.PREFIX
    params = lib._c_params(lib.EXAMPLE)
    own, callers = ffi.new(f"{P}_analysis *"), ffi.new(f"{P}_analysis *")
    workspace = ffi.new(f"{P}_workspace *")
    ffi.memmove(workspace, b"\xa5" * ffi.sizeof(workspace[0]), ffi.sizeof(workspace[0]))
    assert getattr(c, f"{P}_analyze")(params, own) == lib.STATUS["OK"]
    assert getattr(c, f"{P}_analyze_work")(params, callers, workspace) == lib.STATUS["OK"]
    assert bytes(ffi.buffer(own)) == bytes(ffi.buffer(callers)) and own.n_equilibria > 0
    assert (getattr(c, f"{P}_analyze_work")(params, callers, ffi.NULL)
            == lib.STATUS["ERR_NULL_POINTER"])
