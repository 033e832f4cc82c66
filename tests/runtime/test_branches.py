"""codegen.runtime.branches: equilibria followed as one parameter varies.

References are independent where they are numerical: the single-set analysis at every
sample, a scan of the compiled G over the angle on either side of each fold (two zeros on
one side, none on the other), K_EQ and G evaluated at the fold, the torsion pendulum's
buckling threshold k_t = (m/2 + m_t) g l in closed form, and the joining on synthetic
angles whose correspondence is known.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from codegen.runtime import folds, joining
from codegen.runtime.analysis import STABILITY, analyze
from codegen.api import load
from codegen.runtime.branches import EVENTS, POINTS, Branches, branches

STABLE, UNSTABLE = STABILITY.index("stable"), STABILITY.index("unstable")
SAMPLE = POINTS.index("sample")


@pytest.fixture(scope="module")
def doughty_wide() -> Branches:
    """Doughty's F from -200 to 300 N: both folds of its S-shaped pair of branches."""
    return load("doughty").branches("F", -200, 300, points=501)


def _samples(result: Branches, value: float) -> np.ndarray:
    """The sampled points at one value, by angle."""
    at = result.points[(result.points["value"] == value) & (result.points["point"] == SAMPLE)]
    return at[np.argsort(at["theta"])]


def _zeros_near(library, params, theta: float, half_width: float = 2e-3,
                n: int = 4001) -> int:
    """Sign changes of the compiled G on [theta - w, theta + w]: an independent count."""
    grid = np.linspace(theta - half_width, theta + half_width, n)
    table = library.params_array([params] * n)
    g = library.equilibrium_residual(table, grid).residual
    return int(np.count_nonzero(np.sign(g[:-1]) != np.sign(g[1:])))


def _assert_fold_is_a_double_root(result: Branches, event, delta: float = 1e-6) -> None:
    """K_EQ and G vanish at the fold; just on the side where its pair exists G has two
    zeros near it, just on the other none; the pair's last points meet, one stable and
    one unstable."""
    library = result.library
    at = library.example_params(**{**vars(result.base), result.parameter: event.value})
    scale = max(abs(e.K) for e in analyze(library.example_params()).equilibria)
    assert abs(library.linearisation(at, event.theta).K) < 1e-9 * scale
    g = library.equilibrium_residual(at, event.theta)
    assert abs(g.residual) < 1e-10 * g.scale   # the value is good to the tolerance
    inside = 1 if event.side == "above" else -1
    for sign, count in ((inside, 2), (-inside, 0)):
        near = library.example_params(**{**vars(result.base),
                                         result.parameter: event.value + sign * delta})
        assert _zeros_near(library, near, event.theta) == count, (event, sign)
    rows = result.points
    ends = rows[(rows["point"] == POINTS.index(event.kind)) & np.isin(rows["branch"],
                                                                     event.branches)]
    ends = ends[np.abs(ends["value"] - event.value) < 1e-5]   # where the pair last is
    assert sorted(ends["branch"]) == list(event.branches)
    assert joining.distance(ends["theta"][0], ends["theta"][1], True) < 1e-4
    assert all(joining.distance(ends["theta"], event.theta, True) < 1e-4)
    assert sorted(ends["stability"] == UNSTABLE) == [False, True]   # stable (or marginal,
    assert ends["K"].min() < 0 < ends["K"].max()                      # b = 0) meets unstable


# ---------------------------------------------------------------- doughty, against analyze

def test_doughty_branches_agree_with_analyze_at_every_sample():
    lib = load("doughty")
    result = lib.branches("F", 0, 200, points=201)
    assert result.method == "polynomial" and result.count == 6 and not result.events
    assert np.all(result.statuses == 0)
    for value in result.values:
        mine = _samples(result, value)
        theirs = analyze(lib.example_params(F=float(value))).equilibria
        assert len(mine) == len(theirs) == 6
        assert np.array_equal(mine["theta"], [e.theta for e in theirs])
        assert np.array_equal(mine["K"], [e.K for e in theirs])
        assert [STABILITY[s] for s in mine["stability"]] == [e.stability for e in theirs]
        assert sorted(mine["branch"]) == list(range(6))   # one point of every branch


def test_doughty_has_an_s_shaped_pair_with_two_folds(doughty_wide):
    result = doughty_wide
    assert [e.kind for e in result.events] == ["fold", "fold"]
    low, high = result.folds
    assert low.side == "above" and high.side == "below"
    assert -140 < low.value < -135 and 228 < high.value < 232
    # the unstable middle branch is born at one fold and dies at the other
    middle = set(low.branches) & set(high.branches)
    assert len(middle) == 1
    middle_rows = result.branch(middle.pop())
    assert np.all(middle_rows["stability"] == UNSTABLE)
    # its ends: where the analysis last resolves the pair, just inside the folds
    assert 0 <= middle_rows["value"][0] - low.value < 1e-5
    assert 0 <= high.value - middle_rows["value"][-1] < 1e-5
    for event in result.folds:
        assert event.bracket[1] - event.bracket[0] <= result.tolerance
        _assert_fold_is_a_double_root(result, event)


def test_every_sample_is_on_exactly_one_branch_and_branches_are_continuous(doughty_wide):
    result = doughty_wide
    per_value = [len(_samples(result, v)) for v in result.values]
    assert set(per_value) == {4, 6}
    for number in range(result.count):
        own = result.branch(number)
        sampled = own[own["point"] == SAMPLE]
        assert np.all(np.diff(own["value"]) >= 0)
        index = np.searchsorted(result.values, sampled["value"])
        assert np.array_equal(index, np.arange(index[0], index[0] + len(index)))  # no gaps
        steps = joining.distance(sampled["theta"][1:], sampled["theta"][:-1], True)
        assert steps.max() < math.radians(2)   # one N moves no equilibrium far
    assert set(result.points["point"]) == {SAMPLE, POINTS.index("fold")}


# ---------------------------------------------------------------- other mechanisms

def test_torsion_pendulum_buckles_in_a_pitchfork_at_its_threshold():
    lib = load("torsion_pendulum")
    result = lib.branches("k_t", 0, 50, points=201)
    p = lib.example_params()
    threshold = (p.m / 2 + p.m_t) * p.g * p.l
    kinds = [e.kind for e in result.events]
    assert sorted(kinds) == ["end", "end", "pitchfork", "stability change"]
    pitchfork = next(e for e in result.events if e.kind == "pitchfork")
    change = next(e for e in result.events if e.kind == "stability change")
    for event in (pitchfork, change):
        assert event.value == pytest.approx(threshold, rel=1e-8)
        assert event.theta == pytest.approx(p.theta_0, abs=1e-4)
        assert abs(event.K) < 1e-6 * threshold
    assert change.stability == ("unstable", "stable") and pitchfork.side == "below"
    # the upright branch runs through; the two buckled ones leave it at the threshold and
    # end, as k_t -> 0, at the ends of the angle's range (theta_0 -+ pi: hanging down)
    upright = change.branches[0]
    assert upright not in pitchfork.branches and result.count == 3
    ends = sorted(e.theta for e in result.events if e.kind == "end")
    assert ends == pytest.approx([p.theta_0 - math.pi, p.theta_0 + math.pi], abs=1e-6)
    assert all(e.value < 1e-6 and e.side == "above" for e in result.events if e.kind == "end")


@settings(max_examples=12, deadline=None)
@given(l=st.floats(0.3, 2.0), m=st.floats(0.1, 3.0), m_t=st.floats(0.0, 3.0),
       g=st.floats(1.0, 20.0))
def test_torsion_pitchfork_follows_the_closed_form_threshold(l, m, m_t, g):
    lib = load("torsion_pendulum")
    threshold = (m / 2 + m_t) * g * l
    result = lib.branches("k_t", 0.5 * threshold, 1.5 * threshold, points=41,
                          base={"l": l, "m": m, "m_t": m_t, "g": g})
    assert [e.kind for e in result.events if e.kind != "stability change"] == ["pitchfork"]
    for event in result.events:
        assert event.value == pytest.approx(threshold, rel=1e-7)


@pytest.mark.parametrize("parameter, start, stop, folds", [("F", -200, 200, 2),
                                                           ("T", -20, 20, 4)])
def test_slider_crank_folds_are_double_roots_of_g(parameter, start, stop, folds):
    result = load("slider_crank").branches(parameter, start, stop, points=401)
    assert [e.kind for e in result.events] == ["fold"] * folds
    for event in result.folds:
        _assert_fold_is_a_double_root(result, event)



def _zeros_all_round(library, params, n: int = 20_000) -> int:
    """Sign changes of the compiled G over a whole turn (an independent count)."""
    grid = np.linspace(-math.pi, math.pi, n)
    g = library.equilibrium_residual(library.params_array([params] * n), grid).residual
    return int(np.count_nonzero(np.sign(g[:-1]) != np.sign(g[1:])))


@pytest.mark.slow
@settings(max_examples=10, deadline=None)
@given(k=st.floats(1500, 6000), H=st.floats(0.1, 0.3), b=st.floats(0, 2000),
       centre=st.floats(-300, 300))
def test_random_doughty_branches_match_an_independent_count(k, H, b, centre):
    """Over a random set near Table 2 and a 500 N range of F: at every sample as many
    branches as G has zeros round the turn, and every fold a double root of G."""
    lib = load("doughty")
    result = lib.branches("F", centre - 250, centre + 250, points=101,
                          base={"k": k, "H": H, "b": b})
    near_events = [e.value for e in result.events]
    step = result.values[1] - result.values[0]
    for value in result.values:
        if any(abs(value - v) < step for v in near_events):
            continue   # a pair there may be closer than the scan's spacing
        at = lib.example_params(k=k, H=H, b=b, F=float(value))
        assert len(_samples(result, value)) == _zeros_all_round(lib, at), value
    assert {e.kind for e in result.events} <= {"fold"}
    for event in result.folds:
        _assert_fold_is_a_double_root(result, event)

# ---------------------------------------------------------------- the joining on its own

def test_align_drops_the_pair_that_vanishes_and_keeps_order():
    before = np.array([-1.0, 0.20, 0.22, 1.5])
    after = np.array([-0.99, 1.52])
    assert list(joining.align(before, after, False)) == [0, 3]
    assert list(joining.align(after, before, False)) == [0, -1, -1, 1]
    # a pitchfork: the middle one continues
    assert list(joining.align(np.array([0.9, 1.0, 1.1]), np.array([1.0]), False)) == [1]


def test_a_branch_crossing_the_seam_keeps_its_number():
    theta = [np.array([-3.0, 0.5, 3.13]), np.array([-3.13, -2.99, 0.5])]   # 3.13 -> -3.13
    shift = joining.rotations(theta[0][None], theta[1][None], True)
    continues = (np.arange(3) + shift[0]) % 3
    assert list(continues) == [2, 0, 1]
    assert list(joining.align(theta[0], theta[1], True)) == [2, 0, 1]
    assert list(joining.align(theta[0], theta[1], False)) == [0, 1, 2]  # on a line: in order


@settings(max_examples=60, deadline=None)
@given(data=st.data(), n=st.integers(2, 12), periodic=st.booleans())
def test_align_recovers_a_known_correspondence(data, n, periodic):
    """Distinct angles moved by less than a quarter of their least gap, maybe a pair of
    neighbours removed (a fold), maybe the whole set turned across the seam: align finds
    which is which."""
    spread = 2 * math.pi if periodic else 6.0
    gaps = np.array(data.draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    base = np.cumsum(gaps / gaps.sum() * spread * 0.999) - (math.pi if periodic else 3.0)
    least = np.diff(np.concatenate([base, [base[0] + spread]] if periodic else [base])).min()
    moved = base + np.array(data.draw(st.lists(st.floats(-0.24, 0.24), min_size=n,
                                               max_size=n))) * least
    turn = data.draw(st.floats(-math.pi, math.pi)) if periodic else 0.0
    moved = np.remainder(moved + turn + math.pi, 2 * math.pi) - math.pi if periodic else moved
    base = np.remainder(base + turn + math.pi, 2 * math.pi) - math.pi if periodic else base
    order = np.argsort(moved)
    keep = np.ones(n, bool)
    if n > 2 and data.draw(st.booleans()):
        first = data.draw(st.integers(0, n - 2))
        keep[order[first:first + 2]] = False         # neighbours (in the moved order)
    after_index = [i for i in order if keep[i]]      # original labels, sorted by angle
    before_sorted = np.argsort(base)
    link = joining.align(base[before_sorted], moved[after_index], periodic)
    assert [int(before_sorted[j]) for j in link] == after_index


def test_zero_closes_a_bracket_to_its_tolerance():
    root = 2 ** (1 / 3)
    calls = []

    def f(x):
        calls.append(x)
        return x**3 - 2

    lo, hi = folds.zero(f, 0.0, 2.0, -2.0, 6.0, 1e-13)
    assert lo <= root <= hi and hi - lo <= 1e-13 and len(calls) < 40   # superlinear
    lo, hi = folds.zero(f, 2.0, 0.0, 6.0, -2.0, 0.0)    # as narrow as doubles allow
    assert hi - lo <= 2 * math.ulp(root) and abs(lo - root) <= 2 * math.ulp(root)


def test_labels_number_branches_by_their_first_rows():
    previous = np.array([-1, -1, 0, 1, -1, 2, 4])
    assert list(joining.labels(previous)) == [0, 1, 0, 1, 2, 0, 2]


# ---------------------------------------------------------------- files and figures

def test_csv_and_json_hold_every_point_in_degrees(doughty_wide, tmp_path):
    import csv
    import json

    result = doughty_wide
    assert result.write(tmp_path / "b.csv") == len(result.points)
    with open(tmp_path / "b.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["branch", "point", "F", "theta_deg", "certified", "stability",
                             "damping", "omega_n", "zeta", "K", "M", "B"]
    assert len(rows) == len(result.points)
    assert [float(r["theta_deg"]) for r in rows] == pytest.approx(
        np.degrees(result.points["theta"]), rel=1e-15)
    assert {r["point"] for r in rows} == {"sample", "fold"}
    assert {r["stability"] for r in rows} == {"stable", "unstable"}
    result.write(tmp_path / "b.json")
    data = json.loads((tmp_path / "b.json").read_text())
    assert data["mechanism"] == "doughty" and data["parameter"] == "F" and data["unit"] == "N"
    assert "F" not in data["params"] and data["params"]["k"] == 3500
    assert [e["kind"] for e in data["events"]] == ["fold", "fold"]
    fold = result.folds[0]
    assert data["events"][0]["theta_deg"] == fold.theta_deg and data["events"][0]["value"] == \
        fold.value
    assert len(data["rows"]) == len(result.points) and len(data["branches"]) == result.count
    assert data["rows"][0]["theta_deg"] == float(np.degrees(result.points["theta"][0]))
    assert all(r["omega_n"] is None for r in data["rows"] if r["stability"] == "unstable")


@pytest.mark.parametrize("path, message", [("b.txt", "written as .csv, .json or .parquet"),
                                           ("nowhere/b.csv", "no folder")])
def test_a_table_path_is_checked(doughty_wide, tmp_path, path, message):
    with pytest.raises(ValueError, match=message):
        doughty_wide.write(tmp_path / path)


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG"), (".svg", b"<?xml")])
def test_the_figure_is_written_headless(doughty_wide, tmp_path, suffix, magic):
    pytest.importorskip("matplotlib")
    from codegen.presentation import plot_branches

    path = plot_branches(doughty_wide, tmp_path / f"f{suffix}")
    assert path.read_bytes().startswith(magic) and path.stat().st_size > 10_000


def test_the_figure_draws_stable_solid_unstable_dashed_and_labels_units():
    """What the figure holds: the lines' styles by stability, the axes' labels."""
    pytest.importorskip("matplotlib")
    from codegen.presentation import branches_figure, figures

    result = load("torsion_pendulum").branches("k_t", 0, 50, points=51)
    figure = branches_figure(result)
    top, frequency, damping = figure.axes
    figures.pyplot().close(figure)
    assert top.get_ylabel() == r"$\theta_E$ [deg]" and damping.get_xlabel() == "k_t [N m/rad]"
    assert "[rad/s]" in frequency.get_ylabel() and damping.get_yscale() == "log"
    styles = {line.get_linestyle() for line in top.get_lines() if line.get_marker() == "None"}
    assert styles == {"-", "--"}
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert legend == ["stable", "unstable", "pitchfork", "branch end", "stability change"]
    # the upright branch, dashed below the threshold, is at 90 deg
    dashed = [line for line in top.get_lines() if line.get_linestyle() == "--"]
    assert all(np.allclose(line.get_ydata(), 90) for line in dashed)
    assert max(x for line in dashed for x in line.get_xdata()) == pytest.approx(24.525)


# ---------------------------------------------------------------- the Python API

def test_progress_counts_the_samples_and_bad_arguments_are_value_errors():
    lib = load("doughty")
    calls = []
    lib.branches("F", 0, 10, points=7, progress=lambda done, total: calls.append((done, total)))
    assert calls[0] == (0, 7) and calls[-1] == (7, 7)
    for args, message in [(("Q", 0, 1), "unknown parameter 'Q'"),
                          (("F", 1, 1), "F: the range needs finite from < to"),
                          (("F", 0, math.inf), "the range needs finite"),
                          (("F", 0, 1, 1), "points must be an integer of at least 2")]:
        with pytest.raises(ValueError, match=message):
            branches(lib, *args)
    with pytest.raises(ValueError, match="k: k must not be negative"):
        lib.branches("k", -20, -10, points=3)     # every sample fails: the first's error
    with pytest.raises(ValueError, match="method must be one of"):
        lib.branches("F", 0, 1, method="magic")


def test_failed_samples_are_reported_and_skipped():
    result = load("doughty").branches("k", -1000, 1000, points=11)
    assert list(result.failed) == [-1000, -800, -600, -400, -200]
    assert not np.any(np.isin(result.points["value"], result.failed))
    assert all(e.value >= -200 for e in result.events)


def test_result_types_have_hints_and_units_in_their_docs():
    import inspect
    import typing

    from codegen.runtime.branches import Event

    for cls in (Branches, Event):
        assert typing.get_type_hints(cls)
        assert "radians" in inspect.getdoc(cls) or "[rad]" in inspect.getdoc(cls)
    assert "radians" in inspect.getdoc(branches) and "radians" in inspect.getdoc(
        load("doughty").branches)
    assert set(EVENTS) <= set(POINTS)


# ---------------------------------------------------------------- the command line

def _cli(tmp_path, *args: str):
    import os
    import subprocess
    import sys
    from pathlib import Path

    repo = Path(__file__).resolve().parents[2]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(repo), env.get("PYTHONPATH")]))
    return subprocess.run([sys.executable, "-m", "codegen", "branches", *args], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=300)


def test_cli_prints_the_branches_and_writes_the_table_and_the_figure(tmp_path):
    pytest.importorskip("matplotlib")
    out = _cli(tmp_path, "--vary", "F", "--from", "-200", "--to", "300", "--points", "201",
               "--out", "b.csv", "--plot", "b.svg")
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""          # no progress bar in a pipe
    text = " ".join(out.stdout.split())
    assert "Doughty's two-slider mechanism as F runs from -200 to 300 N over 201 values" in text
    assert "6 branches, 2 folds" in text
    folds = [line.split() for line in out.stdout.splitlines() if line.startswith("fold ")]
    assert len(folds) == 2 and float(folds[0][1]) == pytest.approx(-137.748, abs=1e-3)
    assert all(len(line) <= 100 for line in out.stdout.splitlines())
    assert (tmp_path / "b.csv").read_text().startswith('"branch","point","F","theta_deg"')
    assert (tmp_path / "b.svg").read_text().startswith("<?xml")


def test_cli_without_a_fold_says_so(tmp_path):
    out = _cli(tmp_path, "--vary", "F", "--from", "0", "--to", "200", "--points", "101")
    assert out.returncode == 0, out.stderr
    assert "6 branches." in " ".join(out.stdout.split())
    assert "No branch ends or changes stability in this range." in out.stdout


@pytest.mark.parametrize("args, message", [
    (("--vary", "Q", "--from", "0", "--to", "1"), "unknown parameter 'Q'; doughty has H"),
    (("--vary", "F", "--from", "5", "--to", "1"), "F: the range needs finite from < to"),
    (("--vary", "F", "--from", "0", "--to", "1", "--set", "F=3"), "F: given more than once"),
    (("--vary", "F", "--from", "0", "--to", "1", "--out", "b.txt"),
     "b.txt: the table is written as .csv, .json or .parquet"),
    (("--vary", "F", "--from", "0", "--to", "1", "--plot", "b.pdf"),
     "b.pdf: a figure is written as .png or .svg"),
    (("--vary", "F", "--from", "0", "--to", "1", "--points", "1"),
     "points must be an integer of at least 2"),
    (("--vary", "F", "--from", "x", "--to", "1"), "--from: 'x' is not a number"),
    (("--mechanism", "torsion_pendulum", "--vary", "k_t", "--from", "0", "--to", "1",
      "--method", "polynomial"), "G is not algebraic"),
])
def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, args, message):
    out = _cli(tmp_path, *args)
    assert out.returncode == 2, out
    assert out.stdout == "" and len(out.stderr.strip().splitlines()) == 1, out.stderr
    assert message in out.stderr and "Traceback" not in out.stderr
    assert not any(tmp_path.iterdir())   # nothing written


def test_cli_without_matplotlib_says_how_to_install_it(monkeypatch, capsys, tmp_path):
    import sys

    from codegen.cli import main

    monkeypatch.setitem(sys.modules, "matplotlib", None)   # `import matplotlib` now fails
    status = main(["branches", "--vary", "F", "--from", "0", "--to", "1",
                   "--plot", str(tmp_path / "f.png")])
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    assert captured.err.strip().endswith(
        ": error: figures need matplotlib: pip install 'mechvib[plot]'")
    assert len(captured.err.strip().splitlines()) == 1 and "Traceback" not in captured.err


def test_cli_draws_a_progress_bar_on_a_terminal(monkeypatch, capsys):
    import io
    import sys

    from codegen.cli import main

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["branches", "--vary", "F", "--from", "0", "--to", "10", "--points", "5"]) == 0
    drawn = terminal.getvalue()   # tqdm's bar, redrawn at most every 0.1 s, then cleared
    assert "| 0/5 [" in drawn and "sets/s]" in drawn and drawn.endswith("\r")
    assert "6 branches" in capsys.readouterr().out
