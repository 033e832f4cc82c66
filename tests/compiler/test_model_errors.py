"""Model files with awkward names, model files that are wrong, and the build cache.

A model whose parameters are named like the generated C's own variables (v, out, params,
iv_flags, tmp0), like symbols the derivation makes (theta_d, t, tau, rho_1) or like names of
the C library (sin, M_PI), with a coordinate named like a Lagrange multiplier (lambda_1),
generates, builds, compiles strictly and has the same equilibria as the model of docs/models.md with
plain names. Every kind of bad model gives one line on stderr and exit status 2, before
anything is derived or written. ``analyze --model`` builds into the per-user cache once and
reuses it while the file is unchanged.
"""
from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from codegen.resources import cflags
from system.test_user_model import MODEL, NAME, PROG, codegen

#: The model of docs/models.md with every name replaced by an awkward one; the three extra
#: parameters are 1 or 0 where they enter, so the mechanics are the same.
RENAMES = {"l": "v", "m": "out", "k": "theta_d", "l_0": "iv_flags", "x_A": "tmp0",
           "y_A": "params", "c": "t", "g": "tau"}
AWKWARD_NAME = "awkward"


def awkward_model(coordinate: str = "lambda_1") -> str:
    text = MODEL.replace('name="spring_pendulum"', f'name="{AWKWARD_NAME}"')
    for old, new in RENAMES.items():
        text = text.replace(f'parameter("{old}",', f'parameter("{new}",')
    text = text.replace('    parameter("g", ', '    parameter("tau", ')
    text = text.replace(
        '(p.symbol for p in PARAMETERS)',
        '(p.symbol for p in PARAMETERS[:8])\n'
        '    rho_1, sin, M_PI = (p.symbol for p in PARAMETERS[8:])')
    text = text.replace(
        ')\nCOORDINATES = (Coordinate("theta"',
        '    parameter("rho_1", "1", "a factor of the stiffness", "1"),\n'
        '    parameter("sin", "1", "a factor of the mass", "1"),\n'
        '    parameter("M_PI", "m", "an offset of the anchor", "0"),\n'
        f')\nCOORDINATES = (Coordinate("{coordinate}"')
    text = text.replace("Spring(k, l_0, distance(tip, (x_A, y_A)))",
                        "Spring(rho_1 * k, l_0, distance(tip, (x_A + M_PI, y_A)))")
    text = text.replace('Body("bar", m,', 'Body("bar", sin * m,')
    text = text.replace('independent="theta"', f'independent="{coordinate}"')
    return text


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("model_errors")
    (folder / "plain.py").write_text(MODEL)
    (folder / "awkward.py").write_text(awkward_model())     # the coordinate a multiplier's name
    (folder / "awkward_theta.py").write_text(awkward_model("theta"))  # theta_d its rate's
    return folder


@pytest.fixture(scope="module", params=["awkward.py", "awkward_theta.py"])
def awkward(request, folder):
    out = codegen(folder, "generate", "--model", request.param, "--out",
                  f"lib_{Path(request.param).stem}")
    assert out.returncode == 0, out.stderr
    return request.param, folder / f"lib_{Path(request.param).stem}"


def genuine_angles(folder: Path, model: str) -> list[float]:
    out = codegen(folder, "analyze", "--model", model, "--out", f"lib_{Path(model).stem}",
                  "--json")
    assert out.returncode == 0, out.stderr
    return [r["theta_deg"] for r in json.loads(out.stdout)["roots"] if r["genuine"]]


def test_awkward_names_give_the_plain_models_equilibria(folder, awkward):
    plain = genuine_angles(folder, "plain.py")
    assert len(plain) == 4
    assert genuine_angles(folder, awkward[0]) == pytest.approx(plain, abs=1e-9)


def test_awkward_names_stay_the_users_in_the_api(awkward):
    awkward = awkward[1]
    spec = json.loads((awkward / AWKWARD_NAME / f"{AWKWARD_NAME}_api.json").read_text())
    assert [p["name"] for p in spec["parameters"]] == [
        *RENAMES.values(), "rho_1", "sin", "M_PI"]
    header = (awkward / AWKWARD_NAME / f"{AWKWARD_NAME}.h").read_text()
    for name in ("v", "out", "theta_d", "iv_flags", "tmp0", "params", "t", "tau", "sin"):
        assert f"    codegen_real {name};" in header or f" {name};" in header, name


def test_awkward_names_compile_strictly(awkward, tmp_path):
    awkward = awkward[1]
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc not found")
    sources = sorted((awkward / AWKWARD_NAME).glob("*.c"))
    for source in sources:
        out = subprocess.run(
            [gcc, *cflags("base", "strict"),
             f"-I{awkward / AWKWARD_NAME}", f"-I{awkward / 'runtime'}", "-c", str(source),
             "-o", str(tmp_path / f"{source.stem}.o")],
            capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, f"{source.name}:\n{out.stderr}"


def test_clashing_names_are_renamed_for_the_derivation_only(folder):
    """theta_d is the rate of theta, rho_1 a root, v the double-double values...: each is
    derived under a fresh name; a shipped mechanism keeps every name."""
    from codegen.compiler.derivation.names import internal_names
    from codegen.compiler.model import SHIPPED, load

    renamed = internal_names(load(str(folder / "awkward_theta.py")))
    assert renamed == {"v": "v_", "out": "out_", "theta_d": "theta_d_",
                       "iv_flags": "iv_flags_", "params": "params_", "t": "t_",
                       "rho_1": "rho_1_", "sin": "sin_", "M_PI": "M_PI_"}
    assert internal_names(load(str(folder / "awkward.py")))["lambda_1"] == "lambda_1_"
    assert all(internal_names(load(name)) == {} for name in SHIPPED)


def test_shipped_mechanisms_pass_the_checks():
    from codegen.compiler.model import SHIPPED, check, load

    for name in SHIPPED:
        check(load(name))


# --------------------------------------------------------------------------- bad models


def _edit(old: str, new: str) -> str:
    assert old in MODEL, old
    return MODEL.replace(old, new)


def _line(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if needle in line)


#: file -> (its text, what the one line says after "PROG: error: FILE")
BAD = {
    "dashed.py": (_edit('name="spring_pendulum"', 'name="slotted-lever"'),
                  "the mechanism's name 'slotted-lever' is not a C identifier"),
    "twice.py": (_edit('parameter("c", ', 'parameter("k", '), "'k' names two parameters"),
    "keyword.py": (_edit('parameter("c", ', 'parameter("int", '),
                   "the name 'int' is a C keyword"),
    "macro.py": (_edit('parameter("c", ', 'parameter("NAN", '),
                 "the name 'NAN' is a macro of the C headers"),
    "undeclared.py": (_edit("tip = (l * sp.cos(theta), l * sp.sin(theta))",
                            'tip = (sp.Symbol("L") * sp.cos(theta), l * sp.sin(theta))'),
                      "body 'bar': the symbol 'L' is not a declared parameter"),
    "root_in_body.py": (_edit("inertia=m * l**2 / 12", "inertia=m * sp.sqrt(1 + sp.cos(theta))"),
                        "body 'bar': the square root sqrt(cos(theta(t)) + 1) of an expression "
                        "of the coordinates is not declared: write a length"),
    "root_in_point.py": (_edit('points={"P": tip}',
                               'points={"P": (sp.sqrt(2 - sp.cos(theta)), 0)}'),
                         "point 'P': the square root sqrt(2 - cos(theta(t)))"),
    "runtime.py": (_edit('name="spring_pendulum"', 'name="runtime"'),
                   "the mechanism's name 'runtime' is the shared runtime's"),
    "root_in_spring.py": (_edit("Spring(k, l_0, distance(tip, (x_A, y_A)))",
                                "Spring(k, l_0, sp.sqrt(2 + sp.sin(theta)))"),
                          "spring 1: the square root"),
}


def _where(name: str) -> str:
    """The line of the bad file the message points at."""
    text = BAD[name][0]
    needle = {"dashed.py": "slotted-lever", "twice.py": 'parameter("k", "N/m"',
              "keyword.py": '"int"', "macro.py": '"NAN"', "undeclared.py": 'Symbol("L")',
              "root_in_body.py": "sqrt", "root_in_spring.py": "sqrt",
              "root_in_point.py": "sqrt", "runtime.py": 'name="runtime"'}[name]
    return f":{_line(text, needle)}:"


def assert_one_line_error(out, starts: str) -> None:
    assert out.returncode == 2, (out.returncode, out.stderr)
    assert out.stdout == ""
    assert "Traceback" not in out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert lines[0].startswith(f"{PROG}: error: {starts}"), lines[0]


@pytest.mark.parametrize("verb", ["generate", "analyze"])
@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_model_is_one_line_with_its_place(folder, verb, name):
    text, message = BAD[name]
    (folder / name).write_text(text)
    out = codegen(folder, verb, "--model", name, "--out", "bad")
    assert_one_line_error(out, f"{name}{_where(name)} {message}")
    assert not (folder / "bad").exists()


def test_missing_model_file_says_so(folder):
    out = codegen(folder, "analyze", "--model", "nonexist.py")
    assert_one_line_error(out, "nonexist.py: no such file")


@pytest.mark.parametrize("verb", ["analyze", "generate", "sources"])
def test_misspelled_mechanism_lists_and_suggests(folder, verb):
    out = codegen(folder, verb, "--mechanism", "doughtyy", *(["--out", "bad"]
                                                             if verb == "generate" else []))
    assert_one_line_error(out, "--mechanism doughtyy: no such mechanism (did you mean doughty?)")
    assert "four_bar" in out.stderr
    assert not (folder / "bad").exists()


# --------------------------------------------------------------------------- the cache

def test_analyze_reuses_its_cached_build_until_the_file_changes(tmp_path):
    cache, work = tmp_path / "cache", tmp_path / "work"
    work.mkdir()
    (work / "mine.py").write_text(MODEL)
    env = {"XDG_CACHE_HOME": str(cache)}
    first = codegen(work, "analyze", "--model", "mine.py", "--json", env=env)
    assert first.returncode == 0, first.stderr
    assert "building" in first.stderr.splitlines()
    again = codegen(work, "analyze", "--model", "mine.py", "--json", env=env)
    assert again.returncode == 0, again.stderr
    assert again.stderr == ""               # no stage: neither derived nor built
    assert again.stdout == first.stdout
    entries = [p for p in (cache / "mechvib").iterdir()]
    assert len(entries) == 1 and list(entries[0].glob(f"_native_{NAME}.*"))
    assert sorted(p.name for p in work.iterdir()) == ["mine.py"]   # no build/ here
    (work / "mine.py").write_text(MODEL + "# changed\n")
    changed = codegen(work, "simulate", "--model", "mine.py", "--theta0", "10", "--to", "0.1",
                      "--points", "3", env=env)
    assert changed.returncode == 0, changed.stderr
    assert "building" in changed.stderr.splitlines()
    assert len([p for p in (cache / "mechvib").iterdir()]) == 2
