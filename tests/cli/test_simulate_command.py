"""`mechvib simulate` as a user runs it (a subprocess): CSV on stdout, CSV and JSON files,
PNG and SVG figures, the linearised response, and one-line errors with exit status 2 (a
missing matplotlib included). The numbers are the Python API's (tests/runtime/test_simulate.py
checks those against independent references)."""
from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from codegen.runtime import simulation
from codegen.api import load
from codegen.cli.common import ProgressBar


def simulate(*args: str, cwd: Path, env=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", "simulate", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120, env=env)


def _api(theta0_deg: float, to: float, points: int, linearised: bool = False, **set_):
    library = load("doughty")
    trajectory = library.simulate(library.example_params(**set_), math.radians(theta0_deg),
                                  0.0, np.linspace(0.0, to, points))
    return trajectory, simulation.linearised(trajectory) if linearised else None


def test_csv_on_stdout_is_the_python_api_in_degrees(tmp_path):
    out = simulate("--theta0", "160", "--to", "2", "--points", "21", cwd=tmp_path)
    assert out.returncode == 0 and out.stderr == ""          # no progress bar in a pipe
    rows = list(csv.reader(io.StringIO(out.stdout)))
    assert rows[0] == ["t_s", "theta_deg", "thetadot_deg_s"] and len(rows) == 22
    values = np.array(rows[1:], dtype=float)
    trajectory, _ = _api(160.0, 2.0, 21)
    assert np.array_equal(values[:, 0], trajectory.t)
    assert np.array_equal(values[:, 1], trajectory.theta_deg)       # 17 digits: exact
    assert np.array_equal(values[:, 2], trajectory.theta_d_deg)
    assert values[0, 1] == 160.0 and values[-1, 0] == 2.0


def test_json_file_with_the_linearised_response(tmp_path):
    out = simulate("--theta0", "160", "--to", "1.5", "--points", "31", "--set", "F=90",
                   "--linearised", "--out", "m.json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "m.json" in out.stdout and "theta_E = " in out.stdout
    data = json.loads((tmp_path / "m.json").read_text())
    trajectory, linear = _api(160.0, 1.5, 31, linearised=True, F=90.0)
    assert data["mechanism"] == "doughty" and data["params"]["F"] == 90.0
    assert data["theta_deg"] == trajectory.theta_deg.tolist()
    assert data["thetadot_deg_s"] == trajectory.theta_d_deg.tolist()
    lin = data["linearised"]
    assert lin["theta_e_deg"] == pytest.approx(math.degrees(linear.theta_e))
    assert lin["theta_deg"] == linear.theta_deg.tolist() and lin["K"] > 0
    assert data["steps"] == trajectory.steps and data["rtol"] == 1e-9


def test_csv_file_with_the_linearised_columns(tmp_path):
    out = simulate("--mechanism", "torsion_pendulum", "--theta0", "40", "--thetadot0", "-20",
                   "--to", "3", "--points", "7", "--linearised", "--out", "p.csv",
                   "--rtol", "1e-11", "--atol", "1e-14", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader((tmp_path / "p.csv").open()))
    assert rows[0] == ["t_s", "theta_deg", "thetadot_deg_s", "theta_lin_deg",
                       "thetadot_lin_deg_s"]
    first = [float(v) for v in rows[1]]
    assert first[1] == 40.0 and first[2] == -20.0
    assert first[3] == pytest.approx(40.0) and first[4] == pytest.approx(-20.0)
    assert "rtol 1e-11, atol 1e-14" in " ".join(out.stdout.split())


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG\r\n\x1a\n"), (".svg", b"<?xml")])
def test_figures_are_written_headless(tmp_path, suffix, magic):
    out = simulate("--theta0", "160", "--to", "2", "--linearised", "--plot", f"f{suffix}",
                   cwd=tmp_path, env={"PATH": "/usr/bin:/bin", "MPLBACKEND": "TkAgg"})
    assert out.returncode == 0, out.stderr
    data = (tmp_path / f"f{suffix}").read_bytes()
    assert data.startswith(magic) and len(data) > 10_000
    if suffix == ".svg":
        text = data.decode()
        assert "t [s]" in text and "deg/s" in text and "linearised about" in text


def test_a_missing_matplotlib_is_one_line_saying_how_to_install_it(tmp_path):
    """matplotlib hidden by a module that fails to import: exit 2, the install hint, no
    traceback, nothing simulated or written."""
    shadow = tmp_path / "shadow"
    shadow.mkdir()
    (shadow / "matplotlib.py").write_text("raise ImportError('matplotlib is not installed')\n")
    out = simulate("--theta0", "160", "--to", "2", "--plot", "f.png", "--out", "m.csv",
                   cwd=tmp_path, env={"PYTHONPATH": str(shadow), "PATH": "/usr/bin:/bin"})
    assert out.returncode == 2 and out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr
    assert "pip install 'mechvib[plot]'" in lines[0]
    assert not (tmp_path / "f.png").exists() and not (tmp_path / "m.csv").exists()


@pytest.mark.parametrize("args, message", [
    (("--theta0", "160", "--to", "2", "--out", "m.txt"), "--out m.txt: "),
    (("--theta0", "160", "--to", "2", "--plot", "m.pdf"), "m.pdf: a figure is written as"),
    (("--theta0", "160", "--to", "0"), "--to: "),
    (("--theta0", "160", "--to", "nan"), "--to: "),
    (("--theta0", "160", "--to", "2", "--points", "1"), "--points: "),
    (("--theta0", "nan", "--to", "2"), "theta0: an input value is NaN"),
    (("--theta0", "160", "--to", "2", "--set", "k=-1"), "k: k must not be negative"),
    (("--theta0", "160", "--to", "2", "--rtol", "0"), "rtol: "),
    (("--to", "2",), "--theta0"),
    (("--theta0", "160", "--to", "2", "--set", "nope=1"), "nope")])
def test_errors_are_one_line_with_status_2(tmp_path, args, message):
    out = simulate(*args, cwd=tmp_path)
    assert out.returncode == 2 and out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    assert message in lines[0]


def test_a_failed_integration_writes_what_it_computed_and_says_where_it_stopped(tmp_path):
    """Exit status 2 and one line naming the failure and the time, after the points before
    it: on stdout as CSV, or in the --out file."""
    out = simulate("--theta0", "160", "--to", "2", "--points", "201", "--max-steps", "20",
                   cwd=tmp_path)
    lines = out.stderr.strip().splitlines()
    assert out.returncode == 2 and len(lines) == 1 and "step budget" in lines[0], out.stderr
    rows = np.array(list(csv.reader(io.StringIO(out.stdout)))[1:], dtype=float)
    trajectory, _ = _api(160.0, 2.0, 201)
    assert 1 < len(rows) < 201
    assert np.array_equal(rows[:, 1], trajectory.theta_deg[:len(rows)])   # the same steps
    out = simulate("--theta0", "160", "--to", "2", "--points", "201", "--max-steps", "20",
                   "--out", "m.json", cwd=tmp_path)
    saved = json.loads((tmp_path / "m.json").read_text())
    assert out.returncode == 2 and out.stdout == ""
    assert f"the {len(rows)} points before it written to m.json" in out.stderr
    assert np.array_equal(saved["theta_deg"], rows[:, 1])


def test_help_shows_examples_and_units(tmp_path):
    out = subprocess.run([sys.executable, "-m", "codegen", "simulate", "--help"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0
    assert "examples:\n  python -m codegen simulate" in out.stdout
    assert "[deg]" in out.stdout and "[deg/s]" in out.stdout and "[s]" in out.stdout
    assert max(map(len, out.stdout.splitlines())) <= 100


def test_the_progress_bar_counts_points():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    screen = Terminal()
    with ProgressBar(screen, unit="points", mininterval=0) as bar:
        bar(0, 1000)
        bar(250, 1000)
        assert re.search(r"25%\|[^|]*\| 250/1000 \[.*points/s\]$", screen.getvalue())
