"""`mechvib draw` for every number of coordinates (issue 50): a mechanism with several
independent coordinates is drawn at one of its equilibria, numbered as `mechvib analyze`
numbers them, or at the coordinates given, each point where its library puts it.

The drawing's points are checked against the library's own: ``points`` at the independent
coordinates for n of them (``point_kinematics`` at every coordinate for one: see
tests/cli/test_discoverability.py, whose tests of one coordinate still hold).
"""
from __future__ import annotations

import argparse
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from codegen.cli import draw as draw_cli
from codegen.compiler.model import load as load_model
from codegen.runtime import api
from codegen.runtime.drawing import geometry, independent_coordinates
from commands import mechvib, need_matplotlib

REPO = Path(__file__).resolve().parents[2]
FOUR_BAR_PENDULUM = REPO / "tests" / "models" / "four_bar_pendulum.py"




def assert_drawn_at_the_library_s_points(mechanism, library, params, theta) -> None:
    """The drawing at ``theta`` (the independent coordinates) has every point of the model
    where the library's ``points`` puts it, to 1e-12."""
    drawn = geometry(mechanism, library, params, theta)
    expected = np.asarray(library.points(params, theta)).reshape(-1, 2)
    assert drawn.model_points == tuple(mechanism.points) == tuple(library.SPEC["points"])
    got = np.array([drawn.points[name] for name in drawn.model_points])
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
    assert drawn.theta == tuple(float(v) for v in theta)
    assert drawn.coordinates == independent_coordinates(mechanism)
    assert [name for name, _ in drawn.coordinates] == [c["name"] for c in
                                                       library.SPEC["coordinates"]]
    named = set(drawn.points)
    for link in drawn.links:
        assert set(link) <= named
    assert {p for s in drawn.springs for p in s} <= named and set(drawn.fixed) <= named
    return drawn


def shown(library, theta) -> str:
    """The coordinates as the line of `mechvib draw` prints them."""
    return ", ".join(f"{c['name']} = {math.degrees(v) if c['unit'] == 'rad' else v:.4f}"
                     f"{' deg' if c['unit'] == 'rad' else ' ' + c['unit']}"
                     for c, v in zip(library.SPEC["coordinates"], theta))


# ----------------------------------------------------------------- the shipped mechanisms


@pytest.mark.parametrize("name", ["double_pendulum", "flexible_doughty"])
def test_drawn_at_each_equilibrium_and_at_given_coordinates(name):
    mechanism, library = load_model(name), api.load(name)
    params = library.example_params()
    equilibria = library.analyze(params).equilibria
    assert equilibria
    for e in equilibria:
        assert_drawn_at_the_library_s_points(mechanism, library, params, e.theta)
    for theta in ([math.radians(30), math.radians(-10)], [-0.4, 0.2]):
        assert_drawn_at_the_library_s_points(mechanism, library, params, theta)


def test_the_double_pendulum_is_where_its_bars_put_it():
    library = api.load("double_pendulum")
    p = library.example_params()
    theta_1, delta = math.radians(30), math.radians(-10)
    g = geometry(load_model("double_pendulum"), library, p, [theta_1, delta])
    A = (p.l_1 * math.cos(theta_1), p.l_1 * math.sin(theta_1))
    B = (A[0] + p.l_2 * math.cos(theta_1 + delta), A[1] + p.l_2 * math.sin(theta_1 + delta))
    np.testing.assert_allclose(g.points["A"], A, atol=1e-14)
    np.testing.assert_allclose(g.points["B"], B, atol=1e-14)
    assert g.points["O"] == (0.0, 0.0)
    assert g.at() == "theta_1 = 30.0000 deg, delta = -10.0000 deg"


def test_a_wrong_number_of_coordinates_is_one_error():
    library = api.load("double_pendulum")
    with pytest.raises(ValueError, match=r"2 independent coordinates \(theta_1, delta\)"):
        geometry(load_model("double_pendulum"), library, library.example_params(), [0.1])
    with pytest.raises(ValueError, match="not a finite state"):
        geometry(load_model("double_pendulum"), library, library.example_params(),
                 [0.1, math.nan])


def _table_rows(output: str, columns: int) -> dict[int, list[float]]:
    """The numbered rows of `mechvib analyze`'s table for n coordinates: # -> coordinates."""
    rows = {}
    for line in output.splitlines():
        cells = line.split()
        numbered = len(cells) > columns and cells[0].isdigit()
        if numbered and re.fullmatch(r"-?\d+\.\d+", cells[1]):
            rows[int(cells[0])] = [float(x) for x in cells[1:1 + columns]]
    return rows


def test_the_command_draws_the_equilibrium_analyze_numbers(tmp_path):
    """--equilibrium N is the row # N of analyze's table; the default, the first stable."""
    need_matplotlib()
    analyzed = mechvib("analyze", "--mechanism", "double_pendulum", cwd=tmp_path)
    assert analyzed.returncode == 0, analyzed.stderr
    rows = _table_rows(analyzed.stdout, 2)
    assert len(rows) == 3
    for number, (theta_1, delta) in rows.items():
        run = mechvib("draw", "--mechanism", "double_pendulum", "--equilibrium", str(number),
                      "-o", f"e{number}.svg", cwd=tmp_path)
        assert run.returncode == 0, run.stderr
        found = re.fullmatch(r"Drew a double pendulum on torsional springs at theta_1 = "
                             r"(\S+) deg, delta = (\S+) deg \(equilibrium (\d), (\w+)\) to "
                             r"e\d\.svg\.\n", run.stdout)
        assert found, run.stdout
        assert float(found[1]) == pytest.approx(theta_1, abs=1e-4)
        assert float(found[2]) == pytest.approx(delta, abs=1e-4)
        assert int(found[3]) == number
        assert (tmp_path / f"e{number}.svg").read_text().lstrip().startswith("<?xml")
    default = mechvib("draw", "--mechanism", "double_pendulum", "-o", "dp.png", cwd=tmp_path)
    assert default.returncode == 0, default.stderr
    assert "(equilibrium 1, stable) to dp.png." in default.stdout
    assert (tmp_path / "dp.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_command_draws_at_the_coordinates_given(tmp_path):
    need_matplotlib()
    run = mechvib("draw", "--mechanism", "double_pendulum", "--at", "delta=-0.2rad",
                  "--at", "theta_1=30", "-o", "dp.svg", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    library = api.load("double_pendulum")
    assert run.stdout == (f"Drew a double pendulum on torsional springs at "
                          f"{shown(library, [math.radians(30), -0.2])} to dp.svg.\n")
    assert (tmp_path / "dp.svg").stat().st_size > 1000


@pytest.mark.parametrize("options, message", [
    (["--theta", "30"], "--theta: double_pendulum has 2 independent coordinates"),
    (["--at", "theta_1=30"], "missing delta"),
    (["--at", "theta_1=30", "--at", "theta_2=3"], "no independent coordinate 'theta_2'"),
    (["--at", "theta_1=30", "--at", "theta_1=3"], "--at theta_1 is given twice"),
    (["--at", "theta_1=x", "--at", "delta=0"], "--at theta_1: 'x' is not a number"),
    (["--equilibrium", "4"], "has 3 equilibria at these parameters (numbered 1 to 3"),
    (["--equilibrium", "0"], "--equilibrium 0: double_pendulum has 3 equilibria at these"),
    (["--equilibrium", "1", "--at", "delta=0"], "not allowed with argument"),
])
def test_wrong_options_are_one_line(options, message, tmp_path):
    run = mechvib("draw", "--mechanism", "double_pendulum", *options, "-o", "dp.svg",
                  cwd=tmp_path)
    assert run.returncode == 2
    assert message in run.stderr and "Traceback" not in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1, run.stderr
    assert not (tmp_path / "dp.svg").exists()


# ------------------------------------------------------------------------ one coordinate


def test_one_coordinate_takes_the_equilibrium_analyze_lists(tmp_path):
    """With one coordinate, --equilibrium N is the N-th row of kind 'equilibrium' of
    analyze's table (by angle), and --at theta=... is --theta."""
    need_matplotlib()
    from codegen.runtime.analysis import analyze

    library = api.load("doughty")
    equilibria = analyze(library.example_params()).equilibria
    for number in (1, len(equilibria)):
        run = mechvib("draw", "--equilibrium", str(number), "-o", "d.svg", cwd=tmp_path)
        assert run.returncode == 0, run.stderr
        degrees = math.degrees(equilibria[number - 1].theta)
        assert (f"at theta = {degrees:.4f} deg (equilibrium {number}, "
                f"{equilibria[number - 1].stability}) to d.svg." in run.stdout)
    run = mechvib("draw", "--at", "theta=40", "-o", "d.svg", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert run.stdout == "Drew Doughty's two-slider mechanism at theta = 40.0000 deg to d.svg.\n"


def _options(**given) -> argparse.Namespace:
    return argparse.Namespace(**{"theta": None, "at": [], "equilibrium": None, **given})


@pytest.mark.parametrize("name", ["doughty", "double_pendulum"])
def test_the_default_without_a_stable_equilibrium(name, monkeypatch):
    """The first equilibrium where none is stable; the centre of the ranges where there is
    none; and the line says which."""
    mechanism, library = load_model(name), api.load(name)
    params = library.example_params()
    n = library.dof
    monkeypatch.setattr(draw_cli, "_equilibria",
                        lambda library, params: [((0.25,) * n, "unstable"),
                                                 ((0.5,) * n, "undecided")])
    assert draw_cli._state(_options(), mechanism, library, params) == (
        (0.25,) * n, " (equilibrium 1, unstable: none is stable)")
    monkeypatch.setattr(draw_cli, "_equilibria", lambda library, params: [])
    theta, which = draw_cli._state(_options(), mechanism, library, params)
    centre = [getattr(params, str(c)) if str(c) in library.UNITS else float(c)
              for c in mechanism.centres]
    assert theta == pytest.approx(centre)
    assert which == " (no equilibrium at these parameters: the centre of the coordinates' ranges)"
    with pytest.raises(ValueError, match="no equilibrium at these parameters"):
        draw_cli._state(_options(equilibrium=1), mechanism, library, params)


# ------------------------------------------------------------------ a user's model file


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """A per-user cache holding the build of four_bar_pendulum.py (built once, ~1 min):
    the command line run with it as XDG_CACHE_HOME reuses that build."""
    from codegen.user_model import library

    folder = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("XDG_CACHE_HOME", str(folder))
        built = library(FOUR_BAR_PENDULUM)
    return folder, built


def test_a_user_model_with_two_coordinates_is_drawn_at_the_library_s_points(cache):
    _, library = cache
    mechanism = load_model(str(FOUR_BAR_PENDULUM))
    params = library.example_params()
    equilibria = library.analyze(params).equilibria
    assert equilibria
    for e in equilibria:
        assert_drawn_at_the_library_s_points(mechanism, library, params, e.theta)
    for theta in ([math.radians(100), math.radians(-60)], [-2.0, 0.3], [3.0, 3.0]):
        assert_drawn_at_the_library_s_points(mechanism, library, params, theta)
    # a crank too long to turn fully: the loop does not close at 180 deg
    long_crank = library.example_params(a_2=0.3)
    with pytest.raises(ValueError, match=r"cannot be assembled at theta = 180 deg, psi = 0 deg"):
        geometry(mechanism, library, long_crank, [math.pi, 0.0])


def test_the_command_draws_a_user_model_with_two_coordinates(cache, tmp_path):
    need_matplotlib()
    folder, library = cache
    env = dict(os.environ, XDG_CACHE_HOME=str(folder))
    model = str(FOUR_BAR_PENDULUM)
    first = library.analyze(library.example_params()).equilibria[0]
    run = mechvib("draw", "--model", model, "-o", "fbp.png", cwd=tmp_path, env=env)
    assert run.returncode == 0, run.stderr
    assert run.stdout == (f"Drew a four-bar linkage carrying a pendulum at "
                          f"{shown(library, first.theta)} (equilibrium 1, {first.stability}) "
                          f"to fbp.png.\n")
    assert (tmp_path / "fbp.png").stat().st_size > 1000
    run = mechvib("draw", "--model", model, "--at", "theta=100", "--at", "psi=-60",
                  "-o", "fbp.svg", cwd=tmp_path, env=env)
    assert run.returncode == 0, run.stderr
    assert "at theta = 100.0000 deg, psi = -60.0000 deg to fbp.svg." in run.stdout
    assert (tmp_path / "fbp.svg").read_text().lstrip().startswith("<?xml")
    unassembled = mechvib("draw", "--model", model, "--set", "a_2=0.3", "--at", "theta=180",
                          "--at", "psi=0", "-o", "no.svg", cwd=tmp_path, env=env)
    assert unassembled.returncode == 2
    last = unassembled.stderr.strip().splitlines()[-1]
    assert "error: the mechanism cannot be assembled at theta = 180 deg, psi = 0 deg" in last
    assert "Traceback" not in unassembled.stderr
    assert not (tmp_path / "no.svg").exists()
