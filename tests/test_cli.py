"""`python -m codegen analyze` as a user runs it: a subprocess, its exit code and its output."""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from codegen.api import load

api = load("doughty")
from codegen.analysis import analyze

REPO = Path(__file__).resolve().parent.parent
ROW = re.compile(r"^\s*(-?\d+\.\d{4})\s+(genuine|extraneous)\s")
ROOT_KEYS = {"theta_deg", "genuine", "M", "B", "K", "omega_n", "zeta"}
BALANCED_F = (0.143 + 9.124 / 2) * 9.81      # (m_B + m_C/2) g of Table 2: e4 = 0


def run(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run([sys.executable, "-m", "codegen", "analyze", *args], cwd=REPO,
                          env=env, capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def table_run():
    return run()


@pytest.fixture(scope="module")
def json_run():
    return run("--json")


def test_table_has_ten_roots_six_genuine(table_run):
    assert table_run.returncode == 0, table_run.stderr
    assert table_run.stderr == ""
    rows = [ROW.match(line) for line in table_run.stdout.splitlines()]
    rows = [m for m in rows if m]
    assert len(rows) == 10
    assert sum(m[2] == "genuine" for m in rows) == 6
    angles = [float(m[1]) for m in rows]
    assert angles == sorted(angles)
    assert ("10 real roots of the polynomial: 6 equilibria, 4 extraneous (a negative length); "
            "6 certified by interval enclosures." in table_run.stdout)
    assert sum(line.split()[2:3] == ["certified"] for line in table_run.stdout.splitlines()
               if ROW.match(line)) == 6
    assert len(re.findall(r"^\s*sigma_\d+\s*=", table_run.stdout, re.M)) == 13


def test_table_angles_are_the_analysis(table_run):
    rows = [ROW.match(line) for line in table_run.stdout.splitlines()]
    printed = [(float(m[1]), m[2] == "genuine") for m in rows if m]
    ours = [(round(r.theta_deg, 4), r.genuine) for r in analyze(api.example_params()).roots]
    assert printed == ours


def test_json_output(json_run):
    assert json_run.returncode == 0, json_run.stderr
    data = json.loads(json_run.stdout)
    assert data["params"] == {n: getattr(api.example_params(), n) for n in api.PARAMETER_NAMES}
    assert len(data["sigma"]) == 13 and all(isinstance(s, float) for s in data["sigma"])
    roots = data["roots"]
    assert len(roots) == 10
    assert [r["theta_deg"] for r in roots] == sorted(r["theta_deg"] for r in roots)
    for r in roots:
        assert ROOT_KEYS <= set(r)
        assert isinstance(r["genuine"], bool)
        for key in ("omega_n", "zeta"):
            assert len(r[key]) == 2 and all(isinstance(v, float) for v in r[key])
    assert sum(r["genuine"] for r in roots) == 6
    # Same numbers as the library in-process, bit for bit (JSON floats round-trip).
    assert data == json.loads(json.dumps(analyze(api.example_params()).to_dict()))


def test_json_is_strict_json(json_run):
    """No NaN/Infinity tokens, which json.loads accepts but strict parsers reject."""
    def refuse(token):
        raise ValueError(f"non-standard JSON constant {token}")

    json.loads(json_run.stdout, parse_constant=refuse)


def test_set_changes_the_result(json_run):
    out = run("--json", "--set", "F=0")
    assert out.returncode == 0, out.stderr
    data, base = json.loads(out.stdout), json.loads(json_run.stdout)
    assert data["params"]["F"] == 0.0
    assert data["sigma"] != base["sigma"]
    assert [r["theta_deg"] for r in data["roots"]] != [r["theta_deg"] for r in base["roots"]]


def test_set_balanced_force_gives_a_genuine_root_at_180_deg():
    out = run("--json", "--set", f"F={BALANCED_F!r}")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["params"]["F"] == BALANCED_F
    at_180 = [r for r in data["roots"] if abs(abs(r["theta_deg"]) - 180) < 1e-7]
    assert at_180 and all(r["genuine"] for r in at_180)
    assert any(r["theta_deg"] == 180.0 for r in at_180)


def test_repeated_set_applies_every_assignment():
    out = run("--json", "--set", "k=1000", "--set", "b=0")
    assert out.returncode == 0, out.stderr
    params = json.loads(out.stdout)["params"]
    assert params["k"] == 1000.0 and params["b"] == 0.0
    assert params["L"] == 0.9


BAD = [
    ("L=-1", "L"),
    ("a=5", "a"),
    ("k=nan", "k"),
    ("Q=1", "Q"),
    pytest.param("k=abc", "k"),
]


@pytest.mark.parametrize("assignment, name", BAD)
@pytest.mark.parametrize("json_flag", [(), ("--json",)], ids=["table", "json"])
def test_bad_input_is_one_line_naming_the_parameter(assignment, name, json_flag):
    out = run(*json_flag, "--set", assignment)
    assert out.returncode != 0
    assert "Traceback" not in out.stderr + out.stdout
    assert out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert re.search(rf"(?<![\w]){re.escape(name)}(?![\w])", lines[0]), lines[0]


def test_balanced_force_value_is_e4_zero():
    """BALANCED_F is typed from Table 2: make sure it is (m_B + m_C/2) g."""
    p = api.example_params()
    assert BALANCED_F == pytest.approx((p.m_B + p.m_C / 2) * p.g, rel=1e-15)
    # Without the spring, gravity and the force balance: G vanishes at every angle.
    G, scale = api.equilibrium_residual(api.example_params(F=BALANCED_F, k=0.0), 0.3)
    assert abs(G) < 1e-12 * scale and math.isfinite(G)


def test_isolation_route_from_the_cli_agrees_with_the_polynomial_route(json_run):
    isolated = run("--method", "isolate", "--json")
    assert isolated.returncode == 0, isolated.stderr
    result = json.loads(isolated.stdout)
    assert result["method"] == "isolate" and result["sigma"] == [] and result["uncertain"] == []
    assert all(r["certified"] and r["kind"] == "equilibrium" for r in result["roots"])
    for r in result["roots"]:
        lo, hi = r["theta_interval_deg"]
        assert lo <= r["theta_deg"] <= hi
    polynomial = [r["theta_deg"] for r in json.loads(json_run.stdout)["roots"] if r["genuine"]]
    assert [r["theta_deg"] for r in result["roots"]] == pytest.approx(polynomial, abs=1e-9)


def test_the_torsion_pendulum_is_analysed_by_isolation_and_has_no_polynomial_route():
    table = run("--mechanism", "torsion_pendulum")
    assert table.returncode == 0, table.stderr
    assert "Certified isolation of the zeros of G: 3 equilibria." in table.stdout
    refused = run("--mechanism", "torsion_pendulum", "--method", "polynomial")
    assert refused.returncode == 2
    assert refused.stderr.startswith("error: torsion_pendulum: G is not algebraic")
    assert len(refused.stderr.strip().splitlines()) == 1
