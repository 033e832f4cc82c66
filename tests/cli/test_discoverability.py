"""The newcomer list of issue 28: what a new user could not find or was misled by.

A drawing of every mechanism from its model's points, a parameter listing with units,
angles in degrees on the command line, one convention for complex quantities and for
extraneous roots in every output, one naming of angle columns in sweep files.
"""
from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from codegen.runtime import api
from codegen.runtime.analysis import analyze
from codegen.cli import common
from codegen.runtime.drawing import geometry
from codegen.compiler.model import SHIPPED, load
from commands import mechvib, need_matplotlib

REPO = Path(__file__).resolve().parents[2]
USER_MODEL = REPO / "tests" / "models" / "two_spring_pendulum.py"




def assert_points_are_the_library_s(mechanism, library, thetas) -> None:
    params = library.example_params()
    for theta in thetas:
        drawn = geometry(mechanism, library, params, theta)
        coords, rates = library.dependent_state(params, theta, 0.0)
        positions, _ = library.point_kinematics(params, coords, np.zeros_like(coords))
        expected = np.asarray(positions).reshape(-1, 2)
        assert drawn.model_points == tuple(mechanism.points)
        got = np.array([drawn.points[name] for name in drawn.model_points])
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
        assert drawn.theta == theta


@pytest.mark.parametrize("name", SHIPPED)
def test_drawn_points_are_where_the_library_puts_them(name):
    mechanism, library = load(name), api.load(name)
    assert mechanism.sketch is not None, f"{name} ships without a sketch"
    assert_points_are_the_library_s(mechanism, library, [math.radians(d) for d in (-40, 12, 40)])
    drawn = geometry(mechanism, library, library.example_params(), math.radians(40))
    named = set(drawn.points)
    for link in drawn.links:
        assert set(link) <= named
    assert {p for s in drawn.springs for p in s} <= named and set(drawn.fixed) <= named


def test_doughty_is_drawn_as_the_readme_describes_it():
    """A = (L cos theta, 0), B = (0, L sin theta), O' = (H, 0), P at distance a from B."""
    library = api.load("doughty")
    p = library.example_params()
    theta = math.radians(40)
    g = geometry(load("doughty"), library, p, theta)
    np.testing.assert_allclose(g.points["A"], (p.L * math.cos(theta), 0), atol=1e-12)
    np.testing.assert_allclose(g.points["B"], (0, p.L * math.sin(theta)), atol=1e-12)
    np.testing.assert_allclose(g.points["O'"], (p.H, 0), atol=1e-15)
    np.testing.assert_allclose(g.points["P"], (p.a * math.cos(theta), (p.L - p.a)
                                               * math.sin(theta)), atol=1e-12)
    assert g.angle[0] == "A" and g.angle[2] - g.angle[1] == pytest.approx(-theta)


@pytest.mark.parametrize("name", SHIPPED)
def test_draw_command_for_each_shipped_mechanism(name, tmp_path):
    need_matplotlib()
    run = mechvib("draw", "--mechanism", name, "--theta", "30", "-o", "m.svg", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "at theta = 30.0000 deg" in run.stdout
    assert (tmp_path / "m.svg").read_text().lstrip().startswith("<?xml")


@pytest.fixture(scope="module")
def user_library(tmp_path_factory):
    from codegen.user_model import library

    return library(USER_MODEL, tmp_path_factory.mktemp("user") / "build")


def test_a_user_model_is_drawn_from_its_points(user_library, tmp_path):
    """A model without a sketch: its points and bodies, at the library's positions."""
    mechanism = load(str(USER_MODEL))
    assert_points_are_the_library_s(mechanism, user_library, [0.3, 1.0, -2.0])
    need_matplotlib()
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"))
    run = mechvib("draw", "--model", str(USER_MODEL), "--theta", "1rad", "-o", "u.png",
                  cwd=tmp_path, env=env)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "u.png").stat().st_size > 1000
    listed = mechvib("params", "--model", str(USER_MODEL), cwd=tmp_path, env=env)
    assert listed.returncode == 0, listed.stderr
    for p in mechanism.parameters:
        assert any(line.split()[:1] == [p.symbol.name] and f"  {p.unit}  " in line
                   and line.rstrip().endswith(p.description)
                   for line in listed.stdout.splitlines()), p.symbol.name


@pytest.mark.parametrize("name", SHIPPED)
def test_params_lists_units_meanings_and_examples(name, tmp_path):
    run = mechvib("params", "--mechanism", name, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    for p in load(name).parameters:
        line = next(line for line in lines if line.split()[:1] == [p.symbol.name])
        assert f"  {p.unit}  " in line and line.rstrip().endswith(p.description)
        value = (f"{math.degrees(float(p.example_value)):.10g} deg" if p.unit == "rad" else
                 p.example_value)
        assert f"  {value}  " in line
    assert "degrees" in run.stdout


@pytest.mark.parametrize("text, expected", [
    ("90", math.pi / 2), ("90deg", math.pi / 2), (" 90 deg", math.pi / 2),
    ("1.5rad", 1.5), ("-45", -math.pi / 4)])
def test_an_angle_parameter_is_read_in_degrees_or_with_its_unit(text, expected):
    assert common.overrides([("theta_0", text)], {"theta_0": "rad"})["theta_0"] == \
        pytest.approx(expected, rel=1e-15)
    assert common.overrides([("F", "90")], {"F": "N"})["F"] == 90.0
    with pytest.raises(ValueError, match="90rad"):
        common.overrides([("F", "90rad")], {"F": "N"})


def test_set_theta_0_90_is_90_degrees(tmp_path):
    runs = [json.loads(mechvib("analyze", "--mechanism", "torsion_pendulum", "--json", "--set",
                               f"theta_0={value}", cwd=tmp_path).stdout)
            for value in ("60", "60deg", f"{math.radians(60)!r}rad")]
    assert runs[0]["params"]["theta_0_deg"] == pytest.approx(60, rel=1e-15)
    assert runs[0] == runs[1] == runs[2]
    helped = mechvib("analyze", "--help", cwd=tmp_path).stdout
    assert "degrees" in " ".join(helped.split()) and "90deg" in helped


def test_complex_and_extraneous_convention_in_every_output(tmp_path):
    """omega_n and zeta: complex in Python, [re, im] in JSON, "x i" in the table with a
    legend; an extraneous root has no stability or damping in any output."""
    result = analyze(api.load("doughty").example_params())
    extraneous = [r for r in result.roots if r.kind == "extraneous"]
    assert extraneous and all(r.stability is None and r.damping is None for r in extraneous)
    unstable = [r for r in result.equilibria if r.K < 0]
    assert unstable and all(r.omega_n.real == 0 and r.omega_n.imag > 0 for r in unstable)
    data = json.loads(mechvib("analyze", "--json", cwd=tmp_path).stdout)
    for root in data["roots"]:
        assert len(root["omega_n"]) == 2 and len(root["zeta"]) == 2
        if root["kind"] == "extraneous":
            assert root["stability"] is None and root["damping"] is None
        else:
            assert root["stability"] in ("stable", "unstable", "marginal")
    text = mechvib("analyze", cwd=tmp_path).stdout
    assert ' i ' in text and 'A value "x i" is imaginary' in " ".join(text.split())
    assert "An extraneous root is not an equilibrium" in " ".join(text.split())
    for line in text.splitlines():
        if line.split()[1:2] == ["extraneous"] and line.split()[0][-1].isdigit():
            assert line.split()[-2:] == ["-", "-"]
    run = mechvib("sweep", "--vary", "F=100:110:2", "--all-roots", "--out", "s.csv",
                  cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    rows = list(csv.DictReader(open(tmp_path / "s.csv")))
    kinds = {(r["kind"], r["stability"], r["damping"]) for r in rows if r["kind"] == "extraneous"}
    assert kinds == {("extraneous", "", "")}


def test_sweep_files_name_angles_with_their_unit_and_round_trip(tmp_path):
    run = mechvib("sweep", "--mechanism", "torsion_pendulum", "--vary", "theta_0=60:90:3",
                  "--set", "l=0.03", "--out", "t.csv", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    text = (tmp_path / "t.csv").read_text()
    header = next(csv.reader([text.splitlines()[0]]))
    assert "theta_deg" in header and "theta_0_deg" in header and "theta" not in header
    assert "0.03," in text and "0.0299999" not in text
    rows = list(csv.DictReader(text.splitlines()))
    assert sorted({float(r["theta_0_deg"]) for r in rows}) == pytest.approx([60, 75, 90],
                                                                            rel=1e-15)
    library = api.load("torsion_pendulum")
    for r in rows:
        params = library.example_params(l=0.03, theta_0=math.radians(float(r["theta_0_deg"])))
        thetas = [e.theta_deg for e in analyze(params).equilibria]
        assert min(abs(float(r["theta_deg"]) - t) for t in thetas) < 1e-9
