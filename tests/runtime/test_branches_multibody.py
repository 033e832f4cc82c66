"""codegen.runtime.branches for mechanisms with n coordinates (issue 50): the same pipeline as
for one, its equilibria points of the box of the coordinates' ranges.

The references are independent: every fold is solved again at 40 digits from
multibody_reference.py (its own kinematics and potential, G and K = dG/dq by numerical
differentiation, nothing from the compiler or the library) as G(q, p) = 0, det K(q, p) = 0;
the double pendulum's pitchfork, where its upright loses stability, from det K = 0 there;
and the branch points at sampled values against single ``analyze`` calls.
"""
from __future__ import annotations

import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from mpmath import mp

import multibody_reference as reference
from codegen.api import load
from codegen.runtime import joining
from codegen.runtime.analysis import STABILITY
from codegen.runtime.branches import POINTS, Branches

SAMPLE = POINTS.index("sample")
STABLE, UNSTABLE = STABILITY.index("stable"), STABILITY.index("unstable")

#: (parameter, from, to, the other parameters, folds): ranges of the double pendulum where
#: equilibria appear and vanish in folds (an imperfect pitchfork: the load F_x, or a
#: spring with a load on).
FOLDS = {"F_x": ("F_x", -10.0, 10.0, {"k_1": 20.0}, 2),
         "k_1": ("k_1", 5.0, 40.0, {"F_x": 0.5}, 1)}


def reference_fold(name: str, params: dict, parameter: str, q: tuple[float, ...],
                   p: float) -> tuple[np.ndarray, float]:
    """The fold near (q, p) at 40 digits: G(q, p) = 0 and det K(q, p) = 0 by Newton's method
    on the reference's own G and K; (coordinates, parameter) as floats."""
    with mp.workdps(40):
        def equations(*x):
            values = {**params, parameter: x[-1]}
            coordinates = list(x[:-1])
            return [*reference.generalised_force(name, values, coordinates),
                    mp.det(reference.stiffness(name, values, coordinates))]

        found = mp.findroot(equations, [*map(mp.mpf, q), mp.mpf(p)], tol=mp.mpf(10) ** -30)
        x = [found[i] for i in range(len(q) + 1)]
        assert max(abs(r) for r in equations(*x)) < mp.mpf(10) ** -25
        return np.array([float(v) for v in x[:-1]]), float(x[-1])


@pytest.fixture(scope="module")
def double_pendulum():
    return load("double_pendulum")


@pytest.fixture(scope="module", params=sorted(FOLDS))
def with_folds(request, double_pendulum) -> Branches:
    parameter, start, stop, base, _ = FOLDS[request.param]
    return double_pendulum.branches(parameter, start, stop, points=501, base=base)


@pytest.fixture(scope="module")
def buckling(double_pendulum) -> Branches:
    """The issue's range: the example's k_1 from 5 to 40 N m/rad."""
    return double_pendulum.branches("k_1", 5, 40)


# ---------------------------------------------------------------- folds, against 40 digits

def test_the_folds_are_where_the_40_digit_reference_puts_them(with_folds):
    result = with_folds
    *_, count = FOLDS[result.parameter]
    params = {**reference.EXAMPLES["double_pendulum"], **vars(result.base)}
    assert result.method == "isolate" and np.all(result.statuses == 0)
    assert [e.kind for e in result.events] == ["fold"] * count
    for event in result.folds:
        q, p = reference_fold("double_pendulum", params, result.parameter, event.theta,
                              event.value)
        assert abs(event.value - p) <= 1e-10 * abs(p), (event, p)
        assert event.bracket[0] <= event.value <= event.bracket[1]
        assert np.allclose(event.theta, q, rtol=0, atol=1e-8), (event.theta, q)
        assert abs(event.K) < 1e-10 * np.abs(result.points["K"]).max()   # det K there


def test_a_fold_is_where_a_stable_and_an_unstable_equilibrium_meet(with_folds):
    """Just on the side where the pair exists the analysis finds both of it, just beyond it
    neither; the pair's last points meet at the fold, one stable and one unstable."""
    result = with_folds
    library = result.library
    for event in result.folds:
        inside = 1 if event.side == "above" else -1
        counts = [len(library.analyze({**vars(result.base), result.parameter:
                                       event.value + sign * 1e-4}).equilibria)
                  for sign in (inside, -inside)]
        assert counts[0] == counts[1] + 2, (event, counts)
        rows = result.points
        ends = rows[(rows["point"] == POINTS.index("fold"))
                    & np.isin(rows["branch"], event.branches)]
        ends = ends[np.abs(ends["value"] - event.value) < 1e-6]
        assert sorted(ends["branch"]) == list(event.branches)
        assert joining.distance(ends["theta"][0], ends["theta"][1], (False, False)) < 1e-3
        assert np.all(joining.distance(ends["theta"], event.theta, (False, False)) < 1e-3)
        assert sorted(ends["stability"]) == [STABLE, UNSTABLE]
        assert ends["K"].min() < 0 < ends["K"].max()   # det K changes sign across the fold


def test_the_pitchfork_and_the_uprights_stability_change_where_det_K_vanishes(buckling):
    """The example's upright (90 deg, 0) is an equilibrium at every k_1; the two buckled ones
    merge into it where its det K vanishes (40 digits), and it turns stable there."""
    with mp.workdps(40):
        base = reference.EXAMPLES["double_pendulum"]
        k = float(mp.findroot(lambda k: mp.det(reference.stiffness(
            "double_pendulum", {**base, "k_1": k}, [mp.pi / 2, 0])), 31))
    pitchfork, change = buckling.events
    assert (pitchfork.kind, change.kind) == ("pitchfork", "stability change")
    assert buckling.count == 3 and len(pitchfork.branches) == 2
    for event in (pitchfork, change):
        assert abs(event.value - k) < 1e-6 * k, (event, k)   # bisection on the analysis
        assert np.allclose(event.theta, [math.pi / 2, 0], atol=1e-4)
    assert change.bracket[0] <= k <= change.bracket[1]
    assert change.stability == ("unstable", "stable")
    upright = buckling.branch(change.branches[0])
    sampled = upright[upright["point"] == SAMPLE]
    assert np.allclose(sampled["theta"], [math.pi / 2, 0], atol=1e-9)
    # next to the pitchfork K is nearly singular: the analysis' root is good to less there
    assert np.allclose(upright["theta"], [math.pi / 2, 0], atol=1e-6)
    assert upright["value"][0] == 5 and upright["value"][-1] == 40
    for number in pitchfork.branches:
        buckled = buckling.branch(number)
        assert np.all(buckled["stability"] == STABLE)
        assert buckled["value"][-1] < k


# ---------------------------------------------------------------- against analyze

def test_the_branch_points_are_the_analysis_at_each_value(with_folds):
    """At sampled values the points are the single-set analysis' equilibria, and each point
    refined next to an event is one of the equilibria there: coordinates, stability, each
    mode's omega_n and zeta, and det K of the library's stiffness matrix."""
    result = with_folds
    library = result.library

    def analysis(value: float) -> list:
        return list(library.analyze({**vars(result.base), result.parameter: value}).equilibria)

    def check(row: np.void, e, value: float) -> None:
        assert np.array_equal(row["theta"], e.theta)
        assert STABILITY[row["stability"]] == e.stability   # one vocabulary
        assert np.array_equal(row["omega_n"], e.frequencies, equal_nan=True)
        assert np.array_equal(row["zeta"], e.modal_damping, equal_nan=True)
        params = library.example_params(**{**vars(result.base), result.parameter: value})
        K = np.reshape(library.stiffness_matrix(params, e.theta), (2, 2))
        assert row["K"] == pytest.approx(np.linalg.det(K), rel=1e-12, abs=1e-12)

    sampled = result.points[result.points["point"] == SAMPLE]
    for value in result.values[::20]:
        at = sampled[sampled["value"] == value]
        expected = analysis(value)
        assert len(at) == len(expected)
        for row, e in zip(at[np.lexsort(at["theta"].T[::-1])], expected):
            check(row, e, value)
    refined = result.points[result.points["point"] != SAMPLE]
    assert len(refined) == 2 * len(result.folds)
    for row in refined:
        expected = analysis(row["value"])
        e = min(expected, key=lambda e: np.abs(e.theta - row["theta"]).max())
        check(row, e, row["value"])


def test_each_branch_moves_little_from_sample_to_sample(with_folds):
    """Joined by the least movement: along every branch the coordinates step by far less than
    the branches lie apart."""
    result = with_folds
    for number in range(result.count):
        sampled = result.branch(number)
        sampled = sampled[sampled["point"] == SAMPLE]
        steps = joining.distance(sampled["theta"][1:], sampled["theta"][:-1], (False, False))
        assert steps.max() < 0.05, (number, steps.max())


# ---------------------------------------------------------------- the outputs

def test_the_table_names_each_coordinate_and_mode(with_folds, tmp_path):
    result = with_folds
    table = result.table()
    parameter = result.parameter
    assert table.dtype.names == ("branch", "point", parameter, "theta_1_deg", "delta_deg",
                                 "stability", "omega_n_1", "omega_n_2", "zeta_1", "zeta_2", "K")
    assert np.array_equal(table["theta_1_deg"], np.degrees(result.points["theta"][:, 0]))
    assert np.array_equal(table["delta_deg"], np.degrees(result.points["theta"][:, 1]))
    assert np.array_equal(table["omega_n_2"], result.points["omega_n"][:, 1], equal_nan=True)
    assert np.array_equal(table[parameter], result.points["value"])

    assert result.write(tmp_path / "b.csv") == len(table)
    with open(tmp_path / "b.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == list(table.dtype.names) and len(rows) == len(table) + 1
    assert {r[5] for r in rows[1:]} <= {"stable", "unstable", "undecided"}

    result.write(tmp_path / "b.json")
    data = json.loads((tmp_path / "b.json").read_text())
    assert data["mechanism"] == "double_pendulum" and data["parameter"] == parameter
    assert len(data["rows"]) == len(table) and set(data["rows"][0]) == set(table.dtype.names)
    for event, written in zip(result.events, data["events"]):
        assert written["kind"] == event.kind and written["value"] == event.value
        assert written["theta_1_deg"] == pytest.approx(math.degrees(event.theta[0]))
        assert written["delta_deg"] == pytest.approx(math.degrees(event.theta[1]))
        assert "theta_deg" not in written


def test_the_figure_has_a_panel_for_each_coordinate(with_folds, tmp_path):
    pytest.importorskip("matplotlib")
    from codegen.presentation import branches_figure, plot_branches

    figure = branches_figure(with_folds)
    labels = [axis.get_ylabel() for axis in figure.axes]
    assert labels[:2] == ["theta_1 [deg]", "delta [deg]"] and len(labels) == 4
    path = plot_branches(with_folds, tmp_path / "b.png")
    assert path.stat().st_size > 10_000


def test_the_issues_command_prints_the_branches(tmp_path):
    """`mechvib branches --mechanism double_pendulum --vary k_1 --from 5 --to 40` (the issue's
    `error: no field of name kind`), with the table and the figure written."""
    command = [sys.executable, "-m", "codegen", "branches", "--mechanism", "double_pendulum",
               "--vary", "k_1", "--from", "5", "--to", "40", "--out", str(tmp_path / "k.csv")]
    out = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert out.returncode == 0, out.stderr
    text = out.stdout
    assert "isolate route): 3 branches, 1 pitchfork." in " ".join(text.split())
    assert "theta_1, delta [deg] from" in text
    assert any(line.startswith("pitchfork") and line.endswith("0, 2 (exist below)")
               for line in text.splitlines())
    assert any(line.startswith("stability change") and "(unstable -> stable)" in line
               for line in text.splitlines())
    assert "det K" in text and (tmp_path / "k.csv").is_file()


# ---------------------------------------------------------------- three coordinates

@pytest.fixture(scope="module")
def triple_pendulum(tmp_path_factory):
    """docs/multibody.md's triple pendulum, generated and built (~15 s)."""
    from .test_multibody import triple_pendulum as listed
    from codegen.user_model import library

    folder = tmp_path_factory.mktemp("triple")
    return library(listed(folder), folder / "build")


@pytest.mark.slow   # a whole generation and build
def test_a_three_coordinate_fold_matches_the_reference(triple_pendulum):
    """The triple pendulum with its last spring's free angle off zero: its buckled
    equilibria vanish in a fold as k_1 stiffens."""
    base = {"alpha_3": 0.1}
    result = triple_pendulum.branches("k_1", 2, 40, points=381, base=base)
    assert [e.kind for e in result.events] == ["fold"]
    event = result.folds[0]
    params = {**reference.EXAMPLES["triple_pendulum"], **base}
    q, p = reference_fold("triple_pendulum", params, "k_1", event.theta, event.value)
    assert abs(event.value - p) <= 1e-10 * abs(p) and np.allclose(event.theta, q, atol=1e-8)
    assert result.table().dtype.names[3:6] == ("theta_1_deg", "delta_2_deg", "delta_3_deg")
    for value in result.values[::40]:
        at = result.points[(result.points["value"] == value)
                           & (result.points["point"] == SAMPLE)]
        expected = triple_pendulum.analyze({**vars(result.base), "k_1": value}).equilibria
        assert sorted(map(tuple, at["theta"])) == [tuple(e.theta) for e in expected]


# ---------------------------------------------------------------- joining in n coordinates

def test_joining_recovers_a_known_correspondence_across_a_seam():
    """Four points of a torus moved a little, one across the seam of its periodic first
    coordinate: the order is lost, the movement says who continues whom."""
    periodic = (True, False)
    before = np.array([[-3.1, 0.2], [-1.0, 0.0], [0.5, -0.3], [3.05, 1.0]])
    moved = before + np.array([[-0.05, 0.01], [0.02, -0.02], [0.03, 0.0], [0.1, 0.02]])
    moved[:, 0] = np.remainder(moved[:, 0] + math.pi, 2 * math.pi) - math.pi
    order = np.lexsort(moved.T[::-1])
    after = moved[order]
    index = joining.follow(before[None], after[None], periodic)[0]
    assert list(index) == list(order)
    assert list(joining.align(before, after, periodic)) == list(order)
    # one ends: the rest still continue whom they moved from
    assert list(joining.align(before, after[1:], periodic)) == list(order[1:])
    assert list(joining.align(before[[0, 2]], after, periodic)) == [
        {0: 0, 2: 1}.get(int(i), -1) for i in order]


def test_the_assignment_is_the_least_total_movement():
    """Against every permutation, on random rectangular cost matrices."""
    from itertools import permutations

    rng = np.random.default_rng(50)
    for _ in range(200):
        rows = int(rng.integers(1, 5))
        columns = rows + int(rng.integers(0, 3))
        cost = rng.random((rows, columns))
        chosen = joining._assignment(cost)
        assert len(set(chosen.tolist())) == rows
        best = min(sum(cost[i, j] for i, j in enumerate(p))
                   for p in permutations(range(columns), rows))
        assert cost[np.arange(rows), chosen].sum() == pytest.approx(best, abs=1e-12)


def test_between_is_the_ball_on_the_pair():
    periodic = (True, False)
    a, b = np.array([3.1, 0.0]), np.array([-3.1, 0.1])   # across the seam
    assert joining.between(np.array([math.pi, 0.05]), a, b, periodic)
    assert not joining.between(np.array([0.0, 0.05]), a, b, periodic)
    assert not joining.between(np.array([3.1, 0.5]), a, b, periodic)
    assert np.allclose(joining.mean_angle(a, b, periodic), [3.1 + (2 * math.pi - 6.2) / 2,
                                                            0.05])
