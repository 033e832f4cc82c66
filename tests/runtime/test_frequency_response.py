"""The frequency response about a stable equilibrium (issue 31, n = 1): the library's C
receptance (PREFIX_frequency_response) against H = 1 / (K - omega^2 M + i omega B) built
from the independent reference's M, B, K (tests/support/model_reference.py: numerical derivatives of
the model at 75 digits, sharing nothing with the derivation), its textbook landmarks, the
Python API's choices and refusals, and `mechvib frf` as a user runs it.
"""
from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))   # whatever pytest's import mode
from gallery import example  # noqa: E402
from model_reference import Reference  # noqa: E402

from codegen.api import load  # noqa: E402
from codegen.compiler.model import doughty, four_bar  # noqa: E402
from codegen.runtime import response  # noqa: E402

MODELS = {"doughty": doughty, "four_bar": four_bar}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_receptance_is_the_reference_linearisations(name):
    """At every stable equilibrium, at frequencies through resonance: H from the C library
    equals 1 / (K - omega^2 M + i omega B) of the reference's M, B, K (30 digits) to 1e-8
    relative to the peak."""
    library = load(name)
    params = library.example_params()
    mechanism = MODELS[name].build()
    reference = Reference(mechanism, example(mechanism))
    stable = [(i, e) for i, e in enumerate(library.analyze(params).equilibria)
              if response.is_stable(e)]
    assert stable
    for i, e in stable:
        v = reference.values(e.theta)
        omega_n = math.sqrt(float(v.K / v.M))
        omega = np.linspace(0.0, 3 * omega_n, 61)
        got = library.frequency_response(params, omega, equilibrium=i).H
        with mpmath.workdps(30):
            expected = np.array([complex(1 / (v.K - mpmath.mpf(w) ** 2 * v.M
                                              + 1j * mpmath.mpf(w) * v.B)) for w in omega])
        assert np.max(np.abs(got - expected)) <= 1e-8 * np.max(np.abs(expected)), e.theta


def test_landmarks_of_a_single_degree_of_freedom():
    """About the paper's underdamped equilibrium (176.7 deg): H(0) = 1/K (the static
    compliance), the phase is -90 deg at omega_n, and the amplitude peaks at
    omega_n sqrt(1 - 2 zeta^2)."""
    library = load("doughty")
    params = library.example_params()
    r = library.frequency_response(params, points=20001, equilibrium=5)
    e = r.equilibrium
    assert e.damping == "underdamped"
    assert r.H[0] == pytest.approx(1 / e.K, rel=1e-14)
    omega_n, zeta = float(e.omega_n.real), float(e.zeta.real)
    at_omega_n = library.frequency_response(params, [omega_n], equilibrium=5)
    assert math.degrees(at_omega_n.phase[0]) == pytest.approx(-90.0, abs=1e-9)
    peak_hz, _ = r.peak
    step = r.frequency[1] - r.frequency[0]
    assert abs(peak_hz - omega_n * math.sqrt(1 - 2 * zeta**2) / (2 * math.pi)) <= step
    assert np.all(r.phase <= 0) and np.all(np.diff(r.phase) <= 0)   # the lag only grows


def test_default_equilibrium_is_the_first_stable_one_and_unstable_ones_are_refused():
    library = load("doughty")
    params = library.example_params()
    equilibria = library.analyze(params).equilibria
    first = next(e for e in equilibria if response.is_stable(e))
    assert library.frequency_response(params).equilibrium.theta == first.theta
    unstable = next(i for i, e in enumerate(equilibria) if not response.is_stable(e))
    with pytest.raises(ValueError, match="unstable"):
        library.frequency_response(params, equilibrium=unstable)
    with pytest.raises(ValueError, match="equilibria"):
        library.frequency_response(params, equilibrium=len(equilibria))
    with pytest.raises(ValueError, match="omega"):
        library.frequency_response(params, [1.0, math.nan])


def test_receptance_errors_name_what_is_wrong():
    library = load("doughty")
    params = library.example_params()
    with pytest.raises(library.LibraryError, match="theta"):
        response.receptance(params, math.inf, np.array([1.0]))


def test_files_round_trip(tmp_path):
    library = load("doughty")
    r = library.frequency_response(equilibrium=5, points=11)
    data = json.loads(response.write(r, tmp_path / "frf.json").read_text())
    assert data["amplitude"] == pytest.approx(list(r.amplitude), rel=1e-15)
    assert data["equilibrium"]["natural_frequency_hz"] == pytest.approx(r.natural_frequency)
    rows = list(csv.reader(response.write(r, tmp_path / "frf.csv").open()))
    assert tuple(rows[0]) == response.COLUMNS and len(rows) == 12
    assert [float(x) for x in rows[-1][4:]] == [r.H[-1].real, r.H[-1].imag]


# --------------------------------------------------------------------------- command line


def frf(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", "frf", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120)


def test_cli_csv_on_stdout_is_the_python_api(tmp_path):
    """--equilibrium N counts from 1 as analyze's table lists the equilibria: 6 is the
    Python API's index 5 (176.7 deg)."""
    out = frf("--equilibrium", "6", "--points", "21", cwd=tmp_path)
    assert out.returncode == 0 and out.stderr == ""
    rows = list(csv.reader(io.StringIO(out.stdout)))
    r = load("doughty").frequency_response(equilibrium=5, points=21)
    assert len(rows) == 22
    assert [float(row[2]) for row in rows[1:]] == list(r.amplitude)


def test_cli_counts_the_equilibria_of_several_coordinates_as_analyze_numbers_them(tmp_path):
    """With several coordinates --equilibrium N is the row # N of analyze's table: the
    Python API's index N - 1."""
    lib = load("double_pendulum")
    found = lib.analyze(None).equilibria
    for number in (1, 3):
        out = frf("--mechanism", "double_pendulum", "--equilibrium", str(number), "--points",
                  "5", "--out", "f.json", cwd=tmp_path)
        assert out.returncode == 0, out.stderr
        data = json.loads((tmp_path / "f.json").read_text())
        assert data["equilibrium"] == found[number - 1].theta.tolist()


def test_cli_files_and_figure(tmp_path):
    pytest.importorskip("matplotlib")
    out = frf("--equilibrium", "6", "--max-frequency", "10", "--out", "f.json", "--plot",
              "f.png", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "natural frequency 3.157" in " ".join(out.stdout.split())
    assert json.loads((tmp_path / "f.json").read_text())["frequency_hz"][-1] == 10.0
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("args, message", [
    (("--equilibrium", "1"), "--equilibrium 1 is unstable"),
    (("--equilibrium", "0"), "--equilibrium 0: doughty has 6 equilibria at these parameters "
                             "(numbered 1 to 6"),
    (("--equilibrium", "7"), "--equilibrium 7: doughty has 6 equilibria"),
    (("--mechanism", "double_pendulum", "--equilibrium", "4"),
     "--equilibrium 4: double_pendulum has 3 equilibria"),
    (("--mechanism", "double_pendulum", "--equilibrium", "2"),
     "--equilibrium 2 is unstable: it has no steady response to a harmonic force (the "
     "stable ones are 1, 3)"),
    (("--max-frequency", "-1"), "--max-frequency"),
    (("--out", "f.txt"), "--out"),
])
def test_cli_errors_are_one_line_with_status_2(tmp_path, args, message):
    out = frf(*args, cwd=tmp_path)
    assert out.returncode == 2 and message in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
