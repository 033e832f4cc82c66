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
from codegen.runtime.analysis import analyze
from codegen.resources import cflags

REPO = Path(__file__).resolve().parents[2]
ROW = re.compile(r"^\s*(-?\d+\.\d{4})\s+(equilibrium|extraneous)\s")
ROOT_KEYS = {"theta_deg", "genuine", "M", "B", "K", "omega_n", "zeta"}
BALANCED_F = (0.143 + 9.124 / 2) * 9.81      # (m_B + m_C/2) g of Table 2: e4 = 0


def prose(text: str) -> str:
    """Output with its line wrapping undone."""
    return " ".join(text.split())


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
    assert sum(m[2] == "equilibrium" for m in rows) == 6
    angles = [float(m[1]) for m in rows]
    assert angles == sorted(angles)
    assert ("10 real roots of the polynomial: 6 equilibria, 4 extraneous (a negative length); "
            "6 certified by interval enclosures." in prose(table_run.stdout))
    assert sum(line.split()[2:3] == ["certified"] for line in table_run.stdout.splitlines()
               if ROW.match(line)) == 6
    assert not re.findall(r"^\s*sigma_\d+\s*=", table_run.stdout, re.M)  # only with --sigma


def test_table_angles_are_the_analysis(table_run):
    rows = [ROW.match(line) for line in table_run.stdout.splitlines()]
    printed = [(float(m[1]), m[2] == "equilibrium") for m in rows if m]
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
    assert "Certified isolation of the zeros of G: 3 equilibria." in prose(table.stdout)
    refused = run("--mechanism", "torsion_pendulum", "--method", "polynomial")
    assert refused.returncode == 2
    assert refused.stderr.startswith("python -m codegen: error: torsion_pendulum: G is not "
                                      "algebraic")
    assert len(refused.stderr.strip().splitlines()) == 1


# --------------------------------------------------------------- a well-made Unix tool
# Each runs the command as a user would: a subprocess, from a folder that is not the checkout.

def cli(*args: str, cwd: Path, command: tuple[str, ...] = (sys.executable, "-m", "codegen"),
        **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([*command, *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120, **kwargs)


def test_help_names_the_command_and_shows_examples(tmp_path):
    out = cli("--help", cwd=tmp_path)
    assert out.returncode == 0 and out.stderr == ""
    assert out.stdout.startswith("usage: python -m codegen ")
    assert "Layer" not in out.stdout and "examples:" in out.stdout
    for verb in ("analyze", "generate", "sources", "list"):
        assert re.search(rf"^\s+{verb}\s+\w", out.stdout, re.M), verb
        sub = cli(verb, "--help", cwd=tmp_path)
        assert sub.returncode == 0 and sub.stdout.startswith(f"usage: python -m codegen {verb}")
        assert f"examples:\n  python -m codegen {verb}" in sub.stdout


def test_console_command_has_its_own_name_and_version(tmp_path):
    import codegen

    command = Path(sys.executable).with_name("mechvib")
    assert command.is_file(), "the package's console script is not installed"
    out = cli("--help", cwd=tmp_path, command=(str(command),))
    assert out.returncode == 0 and out.stdout.startswith("usage: mechvib ")
    assert "  mechvib analyze" in out.stdout
    version = cli("--version", cwd=tmp_path, command=(str(command),))
    assert version.returncode == 0 and version.stdout == f"mechvib {codegen.__version__}\n"


def test_bare_command_prints_the_help_and_fails(tmp_path):
    out = cli(cwd=tmp_path)
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.startswith("usage: python -m codegen") and "analyze" in out.stderr


def test_usage_errors_are_one_line(tmp_path):
    for args in (("analyze", "--bogus"), ("frobnicate",), ("analyze", "--method", "magic"),
                 ("analyze", "--set", "F")):
        out = cli(*args, cwd=tmp_path)
        assert out.returncode == 2 and out.stdout == ""
        lines = out.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("python -m codegen"), out.stderr
        assert "--help" in lines[0]


@pytest.mark.parametrize("args", [("analyze",), ("analyze", "--json"), ("analyze", "--wide"),
                                  ("list",), ("simulate", "--theta0", "160", "--to", "20",
                                              "--points", "200000")])
def test_output_survives_a_closed_pipe(tmp_path, args):
    """`mechvib analyze | head -1`: the reader leaves early; no traceback, SIGPIPE's status."""
    process = subprocess.Popen([sys.executable, "-m", "codegen", *args], cwd=tmp_path,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, bufsize=0)
    process.stdout.read(1)
    process.stdout.close()
    stderr = process.stderr.read().decode()
    process.wait(timeout=120)
    assert stderr == "", stderr
    assert process.returncode in (0, 141)   # 0 when the output fitted the pipe before closing


@pytest.mark.parametrize("assignments, name", [(("F=1e308", "L=100"), "L, F"),
                                               (("k=1e300", "L=1e10"), "L, k"), (("H=1e200",), "H")])
def test_overflow_is_one_line_naming_the_parameter(tmp_path, assignments, name):
    """K ~ F L beyond the largest double: one line naming the parameters."""
    out = cli("analyze", *(a for x in assignments for a in ("--set", x)), cwd=tmp_path)
    assert out.returncode == 2 and out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    assert re.search(rf"error: {name}\b", lines[0]), lines[0]


def test_a_huge_force_whose_results_are_representable_is_answered(tmp_path):
    """F = 1e308 N: K ~ 9e307 N m fits a double, and the analysis, in units of the
    parameters' own scale, proves both equilibria (it overflowed before)."""
    out = cli("analyze", "--set", "F=1e308", "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    roots = json.loads(out.stdout)["roots"]
    assert [round(r["theta_deg"], 6) for r in roots] == [-90.0, 90.0]
    assert all(r["certified"] for r in roots)


SHIPPED = ["doughty", "slider_crank", "four_bar", "torsion_pendulum"]


@pytest.mark.parametrize("mechanism", SHIPPED)
def test_table_fits_100_columns_and_wide_shows_everything(tmp_path, mechanism):
    narrow = cli("analyze", "--mechanism", mechanism, cwd=tmp_path)
    wide = cli("analyze", "--mechanism", mechanism, "--wide", cwd=tmp_path)
    assert narrow.returncode == 0 and wide.returncode == 0, narrow.stderr + wide.stderr
    assert max(map(len, narrow.stdout.splitlines())) <= 100
    assert "eigenvalues" not in narrow.stdout and "M_EQ" not in narrow.stdout
    assert "eigenvalues [1/s]" in wide.stdout and "M_EQ" in wide.stdout
    assert "sigma_0" not in narrow.stdout + wide.stdout


def test_extraneous_roots_show_no_physical_quantities(table_run):
    for line in table_run.stdout.splitlines():
        if ROW.match(line) and " extraneous " in line:
            assert line.split()[2:] == ["-"] * 6, line   # proof to damping


def test_sigma_option_and_no_negative_zeros(tmp_path):
    """k = 0 makes the odd sigma_i exact zeros, which used to print as -0.0000000000e+00."""
    out = cli("analyze", "--set", "k=0", "--sigma", "--wide", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert len(re.findall(r"^\s*sigma_\d+\s*=", out.stdout, re.M)) == 13
    assert re.search(r"sigma_1\s*=\s+0\.0+e\+00$", out.stdout, re.M)
    assert not re.search(r"-0\.0+(e[+-]00)?(?![\d])", out.stdout), out.stdout
    isolated = cli("analyze", "--mechanism", "torsion_pendulum", "--sigma", cwd=tmp_path)
    assert "No sigma: the isolation route works on G itself." in isolated.stdout


def test_list_names_every_shipped_mechanism(tmp_path):
    out = cli("list", cwd=tmp_path)
    assert out.returncode == 0
    assert [line.split()[0] for line in out.stdout.splitlines()] == sorted(
        SHIPPED + ["double_pendulum", "flexible_doughty"])


def test_sources_prints_the_folders_and_copies_a_library_that_compiles(tmp_path):
    out = cli("sources", "--mechanism", "four_bar", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    folders = [Path(line) for line in out.stdout.splitlines()]
    assert len(folders) == 2 and (folders[0] / "four_bar.h").is_file()
    assert (folders[1] / "codegen_runtime.h").is_file()
    copied = cli("sources", "--mechanism", "four_bar", "--copy", "vendor", cwd=tmp_path)
    assert copied.returncode == 0, copied.stderr
    sources = sorted((tmp_path / "vendor").glob("*.c"))
    assert {p.name for p in sources} >= {"four_bar.c", "four_bar_model.c"}
    program = tmp_path / "app.c"
    program.write_text('#include "four_bar.h"\nint main(void) { four_bar_params p = {0};\n'
                       '  return four_bar_check_params(&p) == FOUR_BAR_OK; }\n')
    cc = cli(*cflags("base"), "-Ivendor", "app.c", *map(str, sources), "-lm", "-o", "app",
             cwd=tmp_path, command=("gcc",))
    assert cc.returncode == 0, cc.stderr
    unknown = cli("sources", "--mechanism", "nonesuch", cwd=tmp_path)
    assert unknown.returncode == 2 and unknown.stderr.count("\n") == 1
    assert "nonesuch" in unknown.stderr


def test_the_unrelated_codegen_distribution_is_reported(tmp_path):
    """PyPI's `codegen` owns the same import package; the CLI says so rather than misbehave."""
    info = tmp_path / "site" / "codegen-0.57.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: codegen\nVersion: 0.57\n")
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "site")}
    out = cli("list", cwd=tmp_path, env=env)
    assert out.returncode == 0
    assert out.stderr.startswith("python -m codegen: warning: the unrelated distribution "
                                 "codegen 0.57 is installed"), out.stderr
    clean = cli("list", cwd=tmp_path)
    assert "warning" not in clean.stderr


def _this_checkout() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(REPO)}


@pytest.mark.parametrize("start", ["-1e308", "-.5", "-1E+2", "-200"])
def test_a_negative_number_is_the_value_of_its_option(tmp_path, start):
    """Issue 48: --from -1e308 is --from=-1e308, not an unknown option -1e308."""
    common = ("branches", "--vary", "F", "--to", "300", "--points", "11")
    spaced = cli(*common, "--from", start, cwd=tmp_path, env=_this_checkout())
    joined = cli(*common, f"--from={start}", cwd=tmp_path, env=_this_checkout())
    assert spaced.returncode == 0, spaced.stderr
    assert spaced.stdout == joined.stdout


def test_a_negative_infinity_is_refused_as_a_value_by_name(tmp_path):
    out = cli("branches", "--vary", "F", "--from", "-inf", "--to", "0", cwd=tmp_path,
              env=_this_checkout())
    assert out.returncode == 2 and "F: the range needs finite from < to" in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1, out.stderr


def test_negative_initial_angles_in_exponent_form(tmp_path):
    out = cli("simulate", "--theta0", "-1.6e2", "--thetadot0", "-2e1", "--to", "0.01",
              "--points", "3", cwd=tmp_path, env=_this_checkout())
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[1] == "0,-160,-20"


def _mechvib(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


def _header_value(text: str, name: str) -> str:
    """NAME's value in a header's 'NAME=VALUE, ...' list, line wrapping undone."""
    return re.search(rf"\b{name}=([^,;\s]+)", prose(text)).group(1)


@pytest.mark.parametrize("mechanism, angle", [("torsion_pendulum", "theta_0"),
                                              ("double_pendulum", "alpha_1")])
def test_an_angle_copied_from_the_header_gives_the_same_analysis(mechanism, angle):
    """The header prints an angle parameter as --set reads it back (degrees), not radians
    that --set would take for degrees; JSON names it with its unit."""
    shown = run("--mechanism", mechanism, "--set", f"{angle}=60")
    assert shown.returncode == 0, shown.stderr
    value = _header_value(shown.stdout, angle)
    again = run("--mechanism", mechanism, "--set", f"{angle}={value}")
    assert again.stdout == shown.stdout
    if mechanism == "torsion_pendulum":   # one coordinate: the JSON has the parameters
        data = json.loads(run("--mechanism", mechanism, "--json", "--set", f"{angle}={value}"
                              ).stdout)
        assert data["params"][f"{angle}_deg"] == pytest.approx(60, rel=1e-12)
        assert angle not in data["params"]


def test_branches_show_angle_parameters_as_they_are_read(tmp_path):
    """The other parameters of the header read back through --set; a varied angle's column
    is in degrees under NAME_deg, as every angle of a file."""
    others = _mechvib("branches", "--mechanism", "torsion_pendulum", "--vary", "k_t", "--from",
                      "1", "--to", "50", "--points", "20", "--set", "theta_0=60",
                      "--out", str(tmp_path / "k.json"))
    assert others.returncode == 0, others.stderr
    assert _header_value(others.stdout, "theta_0") in ("60deg", "60 deg")
    data = json.loads((tmp_path / "k.json").read_text())
    assert data["params"]["theta_0_deg"] == pytest.approx(60, rel=1e-12)
    varied = _mechvib("branches", "--mechanism", "torsion_pendulum", "--vary", "theta_0",
                      "--from", "0", "--to", "90", "--points", "20",
                      "--out", str(tmp_path / "theta_0.csv"))
    assert varied.returncode == 0, varied.stderr
    header, first = (tmp_path / "theta_0.csv").read_text().splitlines()[:2]
    assert '"theta_0_deg"' in header.split(",") and '"theta_0"' not in header.split(",")
    assert float(first.split(",")[header.split(",").index('"theta_0_deg"')]) == 0.0
    assert max(float(line.split(",")[2]) for line in
               (tmp_path / "theta_0.csv").read_text().splitlines()[1:]) == pytest.approx(90)


def test_a_varied_angle_parameter_is_shown_in_degrees(tmp_path):
    """--from 0 --to 90 reads degrees; the summary's range, branch ends, events and
    tolerance say degrees too (they said radians: 'from 0 to 1.5708 rad')."""
    out = _mechvib("branches", "--mechanism", "torsion_pendulum", "--vary", "theta_0",
                   "--from", "0", "--to", "90", "--points", "41", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    text = prose(out.stdout)
    assert "runs from 0 to 90 deg over 41 values" in text and " rad" not in text
    fold = next(line for line in out.stdout.splitlines() if line.startswith("fold"))
    assert 80 < float(fold.split()[1]) < 90
