"""A user's own model file, outside the package, through the CLI as a user runs it.

The model (a pendulum held by a linear spring from its tip to a fixed anchor, the walk-through
of docs/models.md, whose build() the README shows) is written into a temporary folder,
generated and built once per module with ``python -m codegen generate --model``, and analysed with
``python -m codegen analyze --model ... --json``. Its equilibria, M and K are checked against
an independent computation here (numpy and scipy only, no codegen import): the potential
V(theta) = m g (l/2) sin(theta) + k/2 (|P - A| - l_0)^2 with P the tip, its zeros of dV/dtheta
by a dense scan and brentq, K = V'' by central differences.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from codegen.resources import cflags

REPO = Path(__file__).resolve().parents[2]
NAME = "spring_pendulum"

# Kept identical to the listing in docs/models.md ("An example"); README.md shows its build().
MODEL = '''\
"""A pendulum held by a linear spring from its tip to a fixed anchor, as data.

A uniform bar O-P (length l, mass m) pivots at the origin at angle theta. A linear spring
(stiffness k, free length l_0) runs from the tip P to the fixed anchor A = (x_A, y_A); a
torsional damper c acts at the pivot. Gravity along -Y. There are no constraints.
"""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Requirement, Spring,
                                     distance, parameter)

PARAMETERS = (
    parameter("l", "m", "length of the bar", "1.0"),
    parameter("m", "kg", "mass of the bar", "1.0"),
    parameter("k", "N/m", "spring stiffness", "20"),
    parameter("l_0", "m", "free length of the spring", "1.0"),
    parameter("x_A", "m", "abscissa of the anchor A", "0.5"),
    parameter("y_A", "m", "ordinate of the anchor A", "1.5"),
    parameter("c", "N m s/rad", "damping coefficient at the pivot", "0.2"),
    parameter("g", "m/s^2", "gravitational acceleration (along -Y)", "9.81"),
)
COORDINATES = (Coordinate("theta", "rad", "angle of the bar"),)


def build() -> Mechanism:
    l, m, k, l_0, x_A, y_A, c, g = (p.symbol for p in PARAMETERS)
    (theta,) = (q.function for q in COORDINATES)
    tip = (l * sp.cos(theta), l * sp.sin(theta))
    return Mechanism(
        name="spring_pendulum",
        title="a pendulum held by a spring from its tip",
        parameters=PARAMETERS,
        coordinates=COORDINATES,
        independent="theta",
        constraints=(),
        bodies=(Body("bar", m, (tip[0] / 2, tip[1] / 2), inertia=m * l**2 / 12, angle=theta),),
        springs=(Spring(k, l_0, distance(tip, (x_A, y_A))),),  # a length root: declared
        dampers=(Damper(c, theta),),
        forces=(),
        gravity=g,
        points={"P": tip},
        requirements=(
            Requirement(l > 0, "L_NOT_POSITIVE", "l must be positive"),
            Requirement(m > 0, "M_NOT_POSITIVE", "m must be positive"),
            Requirement(sp.And(k >= 0, l_0 >= 0), "SPRING_NEGATIVE", "k, l_0 must not be negative"),
            Requirement(c >= 0, "C_NEGATIVE", "c must not be negative"),
        ),
        singular_state="the tip is at the anchor (zero spring length)",
    )
'''

#: The example values of MODEL, as floats (the independent computation's input).
EXAMPLE = dict(l=1.0, m=1.0, k=20.0, l_0=1.0, x_A=0.5, y_A=1.5, c=0.2, g=9.81)


# --------------------------------------------------------------------------- independent


def _tip_and_length(theta, p):
    px, py = p["l"] * np.cos(theta), p["l"] * np.sin(theta)
    return px, py, np.hypot(px - p["x_A"], py - p["y_A"])


def potential(theta, p, sign: float = 1.0):
    """V(theta); sign = -1 takes the spring length as -|P - A| (the extraneous branch)."""
    d = _tip_and_length(theta, p)[2]
    return p["m"] * p["g"] * p["l"] / 2 * np.sin(theta) + p["k"] / 2 * (sign * d - p["l_0"]) ** 2


def dpotential(theta, p, sign: float = 1.0):
    """dV/dtheta, by hand (chain rule)."""
    px, py, d = _tip_and_length(theta, p)
    dd = ((px - p["x_A"]) * -py + (py - p["y_A"]) * px) / d     # d|P - A|/dtheta
    return (p["m"] * p["g"] * p["l"] / 2 * np.cos(theta)
            + p["k"] * (sign * d - p["l_0"]) * sign * dd)


def zeros(p, sign: float = 1.0, n: int = 20_001) -> list[float]:
    """Every zero of dV/dtheta in [-pi, pi): a dense scan for sign changes, then brentq."""
    grid = np.linspace(-math.pi, math.pi, n)
    values = dpotential(grid, p, sign)
    brackets = np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]
    return [brentq(dpotential, grid[i], grid[i + 1], args=(p, sign), xtol=1e-15, rtol=1e-15)
            for i in brackets]


def stiffness(theta, p, h: float = 1e-6) -> float:
    """K = V''(theta), central differences of dV/dtheta."""
    return (dpotential(theta + h, p) - dpotential(theta - h, p)) / (2 * h)


def angle_gap(a: float, b: float) -> float:
    """|a - b| in radians, modulo a full turn."""
    return abs(math.remainder(a - b, 2 * math.pi))


def test_docs_list_this_model():
    """The model guide's walk-through (docs/models.md) shows exactly the file these tests run."""
    section = (REPO / "docs" / "models.md").read_text().split("## An example", 1)[1]
    listing = section.split("```python\n", 1)[1].split("```", 1)[0]
    assert listing == MODEL


def test_independent_potential_is_self_consistent():
    """dpotential is the derivative of potential, and the example has several equilibria."""
    theta = np.linspace(-3.0, 3.0, 61)
    for sign in (1.0, -1.0):
        h = 1e-6
        numeric = (potential(theta + h, EXAMPLE, sign) - potential(theta - h, EXAMPLE, sign)) / (2 * h)
        assert np.allclose(numeric, dpotential(theta, EXAMPLE, sign), rtol=1e-7, atol=1e-7)
    roots = zeros(EXAMPLE)
    assert len(roots) == 4
    assert sorted(stiffness(t, EXAMPLE) > 0 for t in roots) == [False, False, True, True]


# --------------------------------------------------------------------------- the CLI


def codegen(cwd: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """python -m codegen ARGS in cwd; a model's build is cached in cwd/.cache, not the user's
    (unless env says where)."""
    env = {**os.environ, "XDG_CACHE_HOME": str(cwd / ".cache"), **(env or {})}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("user_model")
    (folder / "mine.py").write_text(MODEL)
    return folder


@pytest.fixture(scope="module")
def generated(workdir):
    return codegen(workdir, "generate", "--model", "mine.py", "--out", "lib")


def analyze_json(workdir: Path, *extra: str) -> dict:
    out = codegen(workdir, "analyze", "--model", "mine.py", "--out", "lib", "--json", *extra)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


@pytest.fixture(scope="module")
def example_run(workdir, generated):
    return analyze_json(workdir)


def test_generate_writes_and_builds_the_library(workdir, generated):
    assert generated.returncode == 0, generated.stderr
    assert "Traceback" not in generated.stderr
    assert f"wrote and built {NAME}" in generated.stdout
    lib = workdir / "lib"
    for file in (f"{NAME}.h", f"{NAME}.c", f"{NAME}_model.c", f"{NAME}.cdef",
                 f"{NAME}_api.json"):
        assert (lib / NAME / file).is_file(), file
    assert list(lib.glob(f"_native_{NAME}.*")), sorted(p.name for p in lib.iterdir())
    assert "#include" in (lib / NAME / f"{NAME}.c").read_text()


def check_against_independent(data: dict, p: dict) -> None:
    assert data["params"] == p
    roots = data["roots"]
    assert [r["theta_deg"] for r in roots] == sorted(r["theta_deg"] for r in roots)
    genuine = [r for r in roots if r["genuine"]]
    assert all(r["kind"] == "equilibrium" for r in genuine)
    expected = zeros(p)
    assert len(genuine) == len(expected), ([r["theta_deg"] for r in genuine], expected)
    for r, theta in zip(genuine, expected):
        assert angle_gap(math.radians(r["theta_deg"]), theta) < 1e-7, (r["theta_deg"], theta)
        assert r["M"] == pytest.approx(p["m"] * p["l"] ** 2 / 3, rel=1e-12)
        assert r["B"] == pytest.approx(p["c"], rel=1e-12)
        K = stiffness(theta, p)
        assert r["K"] == pytest.approx(K, rel=1e-5), (r["theta_deg"], r["K"], K)
        assert r["stability"] == ("stable" if K > 0 else "unstable")
    # The other roots of the polynomial are equilibria with the spring length taken negative.
    others = [r for r in roots if not r["genuine"]]
    assert all(r["kind"] == "extraneous" for r in others)
    extraneous = zeros(p, sign=-1.0)
    assert len(others) == len(extraneous)
    for r, theta in zip(others, extraneous):
        assert angle_gap(math.radians(r["theta_deg"]), theta) < 1e-6, (r["theta_deg"], theta)
    assert data["singular_roots_deg"] == [] and data["unassembled_roots_deg"] == []


def test_analyze_matches_the_independent_equilibria(example_run):
    check_against_independent(example_run, EXAMPLE)
    assert sum(r["genuine"] for r in example_run["roots"]) == 4


def test_set_changes_the_answer_as_the_potential_says(workdir, generated, example_run):
    softer = dict(EXAMPLE, k=5.0)
    data = analyze_json(workdir, "--set", "k=5")
    check_against_independent(data, softer)
    assert sum(r["genuine"] for r in data["roots"]) == 2   # two of the four are gone


def test_generated_c_compiles_standalone_strict(workdir, generated, tmp_path):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc not found")
    assert generated.returncode == 0, generated.stderr
    lib = workdir / "lib"
    sources = sorted((lib / NAME).glob("*.c")) + sorted((lib / "runtime").glob("*.c"))
    assert len(sources) >= 3
    for source in sources:
        out = subprocess.run(
            [gcc, *cflags("base", "strict"), f"-I{lib / NAME}",
             f"-I{lib / 'runtime'}", "-c", str(source), "-o", str(tmp_path / f"{source.stem}.o")],
            capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, f"{source.name}:\n{out.stderr}"


# --------------------------------------------------------------------------- bad input

#: Model files that give no Mechanism -> what the one-line error says after "PROG: error: FILE".
BAD_FILES = {
    "no_build.py": ("X = 1\n", ": a model file defines build() -> Mechanism"),
    "not_a_mechanism.py": ("def build():\n    return 42\n",
                           ": build() returned int, not a Mechanism"),
    "raises.py": ('import math\n\nraise RuntimeError("no anchor\\nsecond line")\n',
                  ":3: RuntimeError: no anchor"),
    "build_raises.py": ("def tip():\n    return 1 / 0\n\n\ndef build():\n    return tip()\n",
                        ":2: ZeroDivisionError: division by zero"),
    "syntax.py": ("def build(:\n    pass\n", ":1: SyntaxError: "),
}
PROG = "python -m codegen"  # the name the CLI gives itself when run as a module
BAD_MODELS = [(verb, model) for verb in ("generate", "analyze")
              for model in ("missing.py", *BAD_FILES)]


@pytest.mark.parametrize("verb, model", BAD_MODELS)
def test_bad_model_is_one_line_and_nonzero_exit(workdir, verb, model):
    for name, (text, _) in BAD_FILES.items():
        (workdir / name).write_text(text)
    out = codegen(workdir, verb, "--model", model, "--out", "bad")
    assert out.returncode == 2, (out.returncode, out.stderr)
    assert "Traceback" not in out.stderr + out.stdout, out.stderr
    assert out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    if model in BAD_FILES:
        assert lines[0].startswith(f"{PROG}: error: {model}{BAD_FILES[model][1]}"), lines[0]
    else:
        assert lines[0] == f"{PROG}: error: {model}: no such file", lines[0]
    assert not (workdir / "bad").exists()   # nothing generated from a bad model


def test_branches_of_the_user_model_follow_the_independent_equilibria(workdir):
    """`branches --model`: at every sampled k the equilibria are the independent zeros of
    dV/dtheta, and the fold where two of them vanish lies where the independent count of
    zeros changes."""
    out = codegen(workdir, "branches", "--model", "mine.py", "--vary", "k", "--from", "2",
                  "--to", "30", "--points", "57", "--out", "k.json")
    assert out.returncode == 0, out.stderr
    data = json.loads((workdir / "k.json").read_text())
    samples = [r for r in data["rows"] if r["point"] == "sample"]
    for k in sorted({r["k"] for r in samples}):
        mine = sorted(math.radians(r["theta_deg"]) for r in samples if r["k"] == k)
        expected = zeros(dict(EXAMPLE, k=k))
        assert len(mine) == len(expected), k
        assert all(angle_gap(a, b) < 1e-7 for a, b in zip(mine, expected)), k
    folds = [e for e in data["events"] if e["kind"] == "fold"]
    assert len(folds) == 1 and folds[0]["side"] == "above"
    k_fold = folds[0]["value"]
    assert len(zeros(dict(EXAMPLE, k=k_fold - 1e-5))) == 2
    assert len(zeros(dict(EXAMPLE, k=k_fold + 1e-5))) == 4


# --------------------------------------------------------------------------- helper modules

#: MODEL with its bar's inertia factor taken from a helper module beside the model file.
MODEL_WITH_HELPER = MODEL.replace(
    "import sympy as sp\n", "import sympy as sp\nfrom hb_geom import INERTIA_FACTOR\n", 1
).replace("inertia=m * l**2 / 12", "inertia=m * l**2 * INERTIA_FACTOR")


def helper_module(factor: str) -> str:
    return f"import sympy as sp\n\nINERTIA_FACTOR = sp.Rational({factor})\n"


def pivot_inertia(data: dict) -> set[float]:
    """M of every equilibrium: the bar's inertia about the pivot."""
    return {round(r["M"], 12) for r in data["roots"] if r["genuine"]}


def test_a_changed_helper_module_rebuilds_the_cached_model(tmp_path):
    """A model imports a module beside it with no PYTHONPATH for its folder (the run is
    from another folder), and the cached build follows a change of that module."""
    assert "INERTIA_FACTOR" in MODEL_WITH_HELPER.split("def build", 1)[1]
    models = tmp_path / "models"
    models.mkdir()
    (models / "mine.py").write_text(MODEL_WITH_HELPER)
    (models / "hb_geom.py").write_text(helper_module("1, 12"))
    first = codegen(tmp_path, "analyze", "--model", "models/mine.py", "--json")
    assert first.returncode == 0, first.stderr
    assert pivot_inertia(json.loads(first.stdout)) == {round(1 / 12 + 1 / 4, 12)}
    (models / "hb_geom.py").write_text(helper_module("1, 3"))
    second = codegen(tmp_path, "analyze", "--model", "models/mine.py", "--json")
    assert second.returncode == 0, second.stderr
    assert "building" in second.stderr   # built again, not the first build reused
    assert pivot_inertia(json.loads(second.stdout)) == {round(1 / 3 + 1 / 4, 12)}
