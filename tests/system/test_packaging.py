"""Packaging: the Makefile's targets, the distribution's metadata, the sdist and the wheel.

Fast: `make help` lists every target of .PHONY and `make -n` accepts each; `make clean`
removes what builds leave; a second `make generate` does not reinstall; `make example` builds
and runs the README's C example in build/; pyproject.toml's metadata, build requirements (the
Makefile installs the same) and its single version; codegen.resources and generate's default
output folder, in a checkout and in an installed layout.

Slow (built once per module, in a copy of the tree): the sdist, then the wheel built from it
with pip (no build isolation: .venv holds the build requirements); their contents and
metadata; the wheel installed into a new virtual environment whose dependencies come from
this one through a .pth file, and run from a temporary directory (never the checkout):
analyze, generate, generate --model, pip show, and the installed C sources compile with gcc.
"""
from __future__ import annotations

import ast
import email.parser
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile
from importlib import metadata
from pathlib import Path

import pytest

import codegen
from codegen import resources

tomllib = pytest.importorskip("tomllib")  # Python 3.11+

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated"
TEMPLATES = ROOT / "templates"
RUNTIME = ROOT / "runtime"
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
#: What a library folder of generated/ ships (setup.py's SHIPPED_SUFFIXES).
SHIPPED_SUFFIXES = (".c", ".h", ".cdef", ".json")
LIBRARIES = sorted(p.name for p in GENERATED.iterdir() if (p / f"{p.name}_api.json").is_file())
REQUIRED_CLASSIFIERS = {
    "Programming Language :: C",
    "Programming Language :: Python :: 3",
    "Topic :: Scientific/Engineering :: Physics",
    "Operating System :: POSIX",
}
AUTHOR = "The mechvib developers"


def _make(*args: str, cwd: Path = ROOT, check: bool = True) -> str:
    result = subprocess.run(["make", "--no-print-directory", *args], cwd=cwd,
                            capture_output=True, text=True)
    if check:
        assert result.returncode == 0, f"make {' '.join(args)}:\n{result.stdout}{result.stderr}"
    return result.stdout + result.stderr


def _phony_targets() -> list[str]:
    text = (ROOT / "Makefile").read_text().replace("\\\n", " ")
    targets = []
    for line in text.splitlines():
        if line.startswith(".PHONY:"):
            targets += line.split(":", 1)[1].split()
    assert targets, "no .PHONY line in the Makefile"
    return targets


def _shipped_data() -> dict[str, Path]:
    """Path inside the installed package -> the checkout's file, for every file of
    codegen/data/ (the generated libraries and the runtime's copy, the C runtime with its FMI
    glue and flags, the templates)."""
    files = {}
    for folder in LIBRARIES + ["runtime"]:
        for src in sorted((GENERATED / folder).iterdir()):
            if src.is_file() and src.suffix in SHIPPED_SUFFIXES:
                files[f"codegen/data/generated/{folder}/{src.name}"] = src
    for top in (TEMPLATES, RUNTIME):
        for src in sorted(top.rglob("*")):
            if src.is_file() and src.suffix != ".o":
                files[f"codegen/data/{src.relative_to(ROOT).as_posix()}"] = src
    return files


def _ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def _need_gcc() -> None:
    if shutil.which("gcc") is None:
        message = "gcc is not installed: install with `apt-get install gcc`"
        if _ci():
            pytest.fail(message, pytrace=False)
        pytest.skip(message)


# --------------------------------------------------------------------------- the Makefile


def test_make_help_lists_every_phony_target():
    out = _make("help")
    described = {}
    for line in out.splitlines():
        name, _, description = line.strip().partition(" ")
        described[name] = description.strip()
    targets = _phony_targets()
    assert {"all", "help", "build", "clean", "lint", "sanitize", "example"} <= set(targets)
    for target in targets:
        assert described.get(target), f"`make help` does not describe {target!r}:\n{out}"
    assert set(described) == set(targets), "make help lists a target that is not .PHONY"


def test_every_target_dry_runs(tmp_path):
    """Every target has a rule and its prerequisites exist or can be made (make -n), even
    without a virtual environment."""
    for target in _phony_targets():
        _make("-n", target, f"VENV={tmp_path / 'venv'}")


def test_build_requirements_are_installed_by_the_makefile():
    """The Makefile installs pyproject.toml's [build-system] requires into .venv, so builds
    without isolation (make build, the wheel below) have them."""
    line = re.search(r"^BUILD_REQUIRES\s*=\s*(.*)$", (ROOT / "Makefile").read_text(), re.M)
    assert line, "no BUILD_REQUIRES in the Makefile"
    in_makefile = {word.strip("'\"") for word in line.group(1).split()}
    assert in_makefile == set(PYPROJECT["build-system"]["requires"])


def _fake_tree(tmp_path: Path) -> Path:
    """The Makefile with the files its rules name, and a stand-in virtual environment."""
    tree = tmp_path / "tree"
    for name in ("Makefile", "pyproject.toml", "setup.py", "codegen/__init__.py",
                 "codegen/compiler/build.py", "examples/minimal.c", "runtime/cflags.txt"):
        (tree / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / name, tree / name)
    shutil.copytree(GENERATED, tree / "generated",
                    ignore=shutil.ignore_patterns("*.o"))
    python = tree / "venv" / "bin" / "python"
    python.parent.mkdir(parents=True)
    python.write_text("#!/bin/sh\nexit 0\n")
    python.chmod(0o755)
    for stamp in (".build-requires", ".installed"):
        (tree / "venv" / stamp).touch()
    # Everything older than the stamps, as after `make venv`.
    past = (1_700_000_000, 1_700_000_000)
    for path in tree.rglob("*"):
        if path.parent.name != "venv":
            os.utime(path, past)
    return tree


def test_clean_removes_build_products_and_invalidates_the_install(tmp_path):
    tree = _fake_tree(tmp_path)
    products = ["build/minimal", "dist/mechvib-0.1.0.tar.gz", "mechvib.egg-info/PKG-INFO",
                "codegen/_native_doughty.abi3.so", "codegen/_native_doughty.c",
                ".pytest_cache/v/x", "minimal", "generated/doughty/doughty.o"]
    for name in products:
        (tree / name).parent.mkdir(parents=True, exist_ok=True)
        (tree / name).write_text("x")
    _make("clean", "VENV=venv", cwd=tree)
    for name in products:
        assert not (tree / name).exists(), f"make clean left {name}"
    assert not (tree / "venv" / ".installed").exists()
    kept = ["generated/doughty/doughty.c", "codegen/compiler/build.py", "venv/bin/python",
            "venv/.build-requires", "examples/minimal.c"]
    assert all((tree / name).exists() for name in kept)


def test_generate_touching_nothing_does_not_reinstall(tmp_path):
    """.venv/.installed depends on generated/: untouched files (a second `make generate`
    rewrites none) leave it current; a rewritten file makes the next target reinstall."""
    tree = _fake_tree(tmp_path)
    assert "pip install" not in _make("-n", "check", "VENV=venv", cwd=tree)
    (tree / "generated" / "doughty" / "doughty.c").touch()
    assert "pip install" in _make("-n", "check", "VENV=venv", cwd=tree)


def test_write_folder_leaves_unchanged_files_alone(tmp_path):
    """What makes a second `make generate` cheap for make: no file is rewritten."""
    from codegen.compiler import generate

    files = {"a.c": "int a;\n", "a.h": "extern int a;\n"}
    generate.write_folder(tmp_path, files)
    os.utime(tmp_path / "a.c", ns=(1, 1))
    os.utime(tmp_path / "a.h", ns=(1, 1))
    generate.write_folder(tmp_path, files)
    # (generate's own manifest of what it wrote, .mechvib-manifest, is not a library file)
    assert {p.name: p.stat().st_mtime_ns for p in tmp_path.iterdir()
            if not p.name.startswith(".")} == {"a.c": 1, "a.h": 1}
    generate.write_folder(tmp_path, {**files, "a.c": "int a = 1;\n"})
    assert (tmp_path / "a.c").stat().st_mtime_ns > 1 and (tmp_path / "a.h").stat().st_mtime_ns == 1


def test_make_example_builds_into_build_and_runs(tmp_path):
    _need_gcc()
    tree = _fake_tree(tmp_path)
    out = _make("example", cwd=tree)
    assert (tree / "build" / "minimal").is_file() and not (tree / "minimal").exists()
    assert out.count("theta_E =") == 10 and "-8.8981 deg  genuine" in out


def test_stray_example_binaries_are_ignored():
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    result = subprocess.run(["git", "check-ignore", "minimal", "examples/minimal",
                             "build/minimal"], cwd=ROOT, capture_output=True, text=True)
    assert result.stdout.split() == ["minimal", "examples/minimal", "build/minimal"]


# --------------------------------------------------------------------------- metadata


def test_one_version_in_codegen_init():
    project = PYPROJECT["project"]
    assert "version" not in project and "version" in project["dynamic"]
    assert PYPROJECT["tool"]["setuptools"]["dynamic"]["version"] == {
        "attr": "codegen.__version__"}
    assert re.fullmatch(r"\d+\.\d+\.\d+([ab]|rc)?\d*", codegen.__version__)
    try:  # an installation made from this checkout (make venv) reports the same
        assert metadata.version("mechvib") == codegen.__version__
    except metadata.PackageNotFoundError:
        pass


def test_project_metadata():
    project = PYPROJECT["project"]
    assert project["name"] == "mechvib"
    assert project["scripts"] == {"mechvib": "codegen.cli:main"}
    assert project["license"] == "BSD-3-Clause" and project["license-files"] == ["LICENSE"]
    assert project["authors"] == [{"name": AUTHOR}]
    assert project["readme"] == "README.md" and project["keywords"]
    assert REQUIRED_CLASSIFIERS <= set(project["classifiers"])
    # setuptools refuses license classifiers beside a license expression (PEP 639)
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]
    assert "urls" not in project  # no public home page
    extras = project["optional-dependencies"]
    assert "tqdm>=4.60" in project["dependencies"]   # the CLI's progress bars
    assert extras["plot"] == ["matplotlib>=3.7"]
    assert extras["sweep"] == ["pyarrow>=14"]
    assert extras["dask"] == ["dask[distributed]>=2023.1", "pyarrow>=14"]
    assert set(extras["dask"]) <= set(extras["test"])   # CI runs the Dask and Parquet sweeps
    assert {"sympy==1.14.0", "jinja2>=3.1"} <= set(extras["generate"]) & set(extras["test"])
    license_text = (ROOT / "LICENSE").read_text()
    assert license_text.startswith("BSD 3-Clause License")
    assert "Copyright (c) 2026, the mechvib developers" in license_text
    assert (ROOT / "codegen" / "py.typed").is_file()


# --------------------------------------------------------------------------- resources


def test_every_subpackage_is_packaged():
    """setuptools' list of packages names every folder of codegen with an __init__.py (one
    left out is missing from the wheel, though it imports in a checkout)."""
    folders = {".".join(p.parent.relative_to(ROOT).parts)
               for p in (ROOT / "codegen").rglob("__init__.py")}
    assert set(PYPROJECT["tool"]["setuptools"]["packages"]) == folders


def test_resources_in_the_checkout():
    assert resources.in_checkout()
    assert resources.templates() == TEMPLATES and resources.generated() == GENERATED
    assert resources.runtime() == RUNTIME


def test_compiler_flags_are_written_once():
    """runtime/cflags.txt names every set of flags; nothing else spells the language, the
    warnings or the sanitizers (a user's command in a doc or a comment aside)."""
    sets = resources.cflag_sets()
    assert {"base", "optimize", "strict", "promotion", "sanitize"} <= set(sets)
    assert "-std=c99" in sets["base"] and "-Werror" in sets["strict"]
    assert resources.cflags("base", "optimize") == sets["base"] + sets["optimize"]
    flag = re.compile(r"(?<![-\w])-(std=c99|Wpedantic|fsanitize=)")
    builds = [ROOT / "Makefile", ROOT / "CMakeLists.txt", *ROOT.glob("embedded/*.mk")]
    python = [p for top in ("codegen", "tests", "benchmarks", "embedded")
              for p in (ROOT / top).rglob("*.py") if p != Path(__file__).resolve()]
    spelled = [f"{path.relative_to(ROOT)}: {line.strip()}" for path in builds + python
               for line in path.read_text().splitlines()
               if flag.search(line) and not line.lstrip().startswith("#")
               and (path.suffix != ".py" or re.search(r"[\"']-(std=c99|Wpedantic|fsanitize=)",
                                                       line))]
    assert spelled == [], spelled


def test_resources_is_standard_library_only():
    tree = ast.parse((ROOT / "codegen" / "resources.py").read_text())
    modules = {alias.name.split(".")[0] for node in ast.walk(tree)
               if isinstance(node, ast.Import) for alias in node.names}
    modules |= {node.module.split(".")[0] for node in ast.walk(tree)
                if isinstance(node, ast.ImportFrom) and node.level == 0}
    assert modules <= set(sys.stdlib_module_names) | {"__future__"}, modules


def _load_resources(package: Path):
    shutil.copy(ROOT / "codegen" / "resources.py", package / "resources.py")
    spec = importlib.util.spec_from_file_location("resources_copy", package / "resources.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_resources_in_an_installed_layout(tmp_path):
    package = tmp_path / "site-packages" / "codegen"
    (package / "data" / "templates").mkdir(parents=True)
    (package / "data" / "generated").mkdir()
    (package / "data" / "runtime").mkdir()
    shutil.copy(RUNTIME / "cflags.txt", package / "data" / "runtime" / "cflags.txt")
    installed = _load_resources(package)
    assert not installed.in_checkout()
    assert installed.templates() == package / "data" / "templates"
    assert installed.generated() == package / "data" / "generated"
    assert installed.runtime() == package / "data" / "runtime"
    assert installed.cflags("base") == resources.cflags("base")
    checkout = tmp_path / "repo"
    (checkout / "codegen").mkdir(parents=True)
    (checkout / "templates").mkdir()
    (checkout / "pyproject.toml").write_text("")
    source = _load_resources(checkout / "codegen")
    assert source.in_checkout() and source.templates() == checkout / "templates"
    assert source.generated() == checkout / "generated"
    assert source.runtime() == checkout / "runtime"


def test_generate_default_output(monkeypatch, tmp_path):
    """A checkout writes its generated/; an installed package ./generated, never its own
    folder (site-packages), following the current directory at the time of the call."""
    from codegen.compiler import generate

    assert generate.TEMPLATES == TEMPLATES
    assert generate.default_output() == GENERATED
    monkeypatch.setattr(resources, "in_checkout", lambda: False)
    monkeypatch.chdir(tmp_path)
    assert generate.default_output() == tmp_path / "generated"
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")
    assert generate.default_output() == tmp_path / "elsewhere" / "generated"


# --------------------------------------------------------------------------- sdist and wheel


def _copy_tree(dst: Path) -> Path:
    """The checkout as a fresh clone plus the working changes would have it (no venv, no
    build products), so that building leaves nothing behind in the checkout."""
    shutil.copytree(ROOT, dst, ignore=shutil.ignore_patterns(
        ".git", ".venv", "venv", "build", "dist", "*.egg-info", "__pycache__", ".pytest_cache",
        ".hypothesis", ".benchmarks", "_native_*", "*.o", "*.so", "minimal"))
    return dst


@pytest.fixture(scope="module")
def dists(tmp_path_factory):
    """(sdist, wheel): the sdist of a copy of the tree, and the wheel pip builds from it."""
    setuptools_version = metadata.version("setuptools")
    if int(setuptools_version.split(".")[0]) < 77:
        pytest.fail(f"setuptools {setuptools_version} in {sys.prefix} is older than the build "
                    "requirement (>=77): run `make venv`", pytrace=False)
    base = tmp_path_factory.mktemp("dist")
    tree = _copy_tree(base / "tree")
    out = base / "out"
    out.mkdir()
    subprocess.run([sys.executable, "-c", "import sys; from setuptools import build_meta; "
                    "build_meta.build_sdist(sys.argv[1])", str(out)],
                   cwd=tree, check=True, capture_output=True)
    (sdist,) = out.glob("*.tar.gz")
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps",
                             "--no-build-isolation", "--no-index", "-w", str(out), str(sdist)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    (wheel,) = out.glob("*.whl")
    return sdist, wheel


@pytest.mark.slow
def test_sdist_holds_what_the_wheel_is_built_from(dists):
    sdist, _ = dists
    with tarfile.open(sdist) as archive:
        top = archive.getnames()[0].split("/")[0]
        names = {name.split("/", 1)[1] for name in archive.getnames() if "/" in name}
    assert top == f"mechvib-{codegen.__version__}"
    expected = {str(src.relative_to(ROOT)) for src in _shipped_data().values()}
    expected |= {"LICENSE", "README.md", "pyproject.toml", "setup.py", "codegen/py.typed",
                 "codegen/compiler/build.py", "codegen/resources.py", "CMakeLists.txt",
                 "cmake/mechvibConfig.cmake.in", "cmake/mechvib.pc.in"}
    assert expected <= names, sorted(expected - names)
    assert not [n for n in names if n.endswith((".o", ".so"))]


@pytest.mark.slow
def test_wheel_carries_the_libraries_templates_and_license(dists):
    _, wheel = dists
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
        for inside, src in _shipped_data().items():
            assert inside in names, f"{inside} is not in the wheel"
            assert archive.read(inside) == src.read_bytes(), f"{inside} differs from {src}"
        dist_info = f"mechvib-{codegen.__version__}.dist-info"
        assert archive.read(f"{dist_info}/licenses/LICENSE") == (ROOT / "LICENSE").read_bytes()
        meta = email.parser.Parser().parsestr(archive.read(f"{dist_info}/METADATA").decode())
        entry_points = archive.read(f"{dist_info}/entry_points.txt").decode()
    assert "codegen/py.typed" in names and "codegen/resources.py" in names
    for name in LIBRARIES:
        assert [n for n in names if re.fullmatch(rf"codegen/_native_{name}\..*\.so", n)], name
    assert not [n for n in names if n.endswith(".o") or n.startswith("generated/")]
    # every file of every library folder and of the runtime is shipped
    for folder in LIBRARIES + ["runtime"]:
        for src in (GENERATED / folder).iterdir():
            if src.suffix != ".o" and not src.name.startswith("."):  # not the manifest
                assert f"codegen/data/generated/{folder}/{src.name}" in names
    assert meta["Name"] == "mechvib" and meta["Version"] == codegen.__version__
    assert (meta["License-Expression"] or meta["License"]) == "BSD-3-Clause"
    assert meta["Author"] == AUTHOR
    assert REQUIRED_CLASSIFIERS <= set(meta.get_all("Classifier"))
    assert {"generate", "test", "plot", "dask"} <= set(meta.get_all("Provides-Extra"))
    scripts = entry_points.split("[console_scripts]", 1)[1].split("[", 1)[0].split("\n")
    assert [s.strip() for s in scripts if s.strip()] == ["mechvib = codegen.cli:main"]


class Installed:
    """The wheel installed into a new virtual environment; runs commands outside the checkout."""

    def __init__(self, venv: Path, cwd: Path):
        self.venv, self.cwd = venv, cwd
        self.python = venv / "bin" / "python"
        self.env = {k: v for k, v in os.environ.items()
                    if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONSAFEPATH")}

    def run(self, *args, cwd: Path | None = None, check: bool = True):
        result = subprocess.run([str(a) for a in args], cwd=cwd or self.cwd, env=self.env,
                                capture_output=True, text=True)
        if check:
            assert result.returncode == 0, (f"{' '.join(map(str, args))}:\n"
                                            f"{result.stdout[-3000:]}{result.stderr[-3000:]}")
        return result

    def python_json(self, code: str):
        return json.loads(self.run(self.python, "-c", code).stdout)


@pytest.fixture(scope="module")
def installed(dists, tmp_path_factory):
    """A virtual environment from the interpreter that made this one, the wheel installed
    without dependencies; numpy, cffi, sympy, jinja2 (and setuptools, for --model builds)
    are this environment's, reached through a .pth file (which adds the folders only: the
    editable install's finder there is not activated)."""
    _, wheel = dists
    base = tmp_path_factory.mktemp("installed")
    venv = base / "venv"
    interpreter = getattr(sys, "_base_executable", None) or sys.executable
    subprocess.run([interpreter, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    purelib = subprocess.run([python, "-c", "import sysconfig; "
                              "print(sysconfig.get_paths()['purelib'])"],
                             check=True, capture_output=True, text=True).stdout.strip()
    here = sysconfig.get_paths()
    Path(purelib, "_mechvib_test_dependencies.pth").write_text(
        "\n".join(dict.fromkeys([here["purelib"], here["platlib"]])) + "\n")
    result = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install",
                             "--quiet", "--no-deps", "--no-index", str(wheel)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    work = base / "work"
    work.mkdir()
    return Installed(venv, work)


@pytest.mark.slow
def test_installed_package_finds_its_copies(installed):
    where = installed.python_json(
        "import json, codegen, codegen.compiler.generate as g, codegen.resources as r; "
        "print(json.dumps([codegen.__file__, r.in_checkout(), str(r.generated()), "
        "str(r.templates()), str(g.default_output()), str(g.TEMPLATES), str(r.runtime()), "
        "r.cflags('base')]))")
    package = Path(where[0]).parent
    assert package.is_relative_to(installed.venv), f"codegen imported from {package}"
    assert where[1:] == [False, str(package / "data" / "generated"),
                         str(package / "data" / "templates"),
                         str(installed.cwd / "generated"), str(package / "data" / "templates"),
                         str(package / "data" / "runtime"), resources.cflags("base")]
    shown = installed.run(sys.executable, "-m", "pip", "--python", installed.python, "show",
                          "mechvib").stdout
    assert "Name: mechvib" in shown and f"Author: {AUTHOR}" in shown
    assert re.search(r"^License(-Expression)?: BSD-3-Clause$", shown, re.M), shown
    version = installed.run(installed.venv / "bin" / "mechvib", "--version").stdout
    assert codegen.__version__ in version


@pytest.mark.slow
def test_installed_package_analyzes(installed):
    from codegen.runtime.analysis import analyze
    from codegen.api import load

    table = installed.run(installed.python, "-m", "codegen", "analyze").stdout
    assert "-8.8981" in table and "176.7155" in table, table
    roots = json.loads(installed.run(installed.python, "-m", "codegen", "analyze",
                                     "--json").stdout)["roots"]
    here = analyze(load("doughty").example_params()).roots
    assert [(round(r["theta_deg"], 9), r["genuine"]) for r in roots] == [
        (round(r.theta_deg, 9), r.genuine) for r in here]


@pytest.mark.slow
def test_installed_package_generates_into_the_current_directory(installed):
    package = Path(installed.python_json(
        "import json, codegen; print(json.dumps(codegen.__file__))")).parent
    before = {p: p.stat().st_mtime_ns for p in package.rglob("*") if "__pycache__" not in p.parts}
    result = installed.run(installed.python, "-m", "codegen", "generate", "--mechanism",
                           "torsion_pendulum")
    out = installed.cwd / "generated"
    assert "generated" in result.stdout, result.stdout
    for folder in ("torsion_pendulum", "runtime"):
        written = {p.name: p.read_bytes() for p in (out / folder).iterdir()
                   if not p.name.startswith(".")}  # not generate's manifest
        committed = {p.name: p.read_bytes() for p in (GENERATED / folder).iterdir()
                     if p.suffix != ".o" and not p.name.startswith(".")}
        assert written == committed, folder
    after = {p: p.stat().st_mtime_ns for p in package.rglob("*") if "__pycache__" not in p.parts}
    assert after == before  # nothing written into the installed package


@pytest.mark.slow
def test_installed_package_generates_and_builds_a_model(installed):
    text = (ROOT / "codegen" / "compiler" / "model" / "torsion_pendulum.py").read_text()
    model = installed.cwd / "my_pendulum.py"
    model.write_text(text.replace("from .mechanism import", "from codegen.model.mechanism import")
                     .replace('name="torsion_pendulum"', 'name="my_pendulum"'))
    installed.run(installed.python, "-m", "codegen", "generate", "--model", model.name,
                  "--out", "mine")
    assert list((installed.cwd / "mine").glob("_native_my_pendulum.*.so"))
    assert (installed.cwd / "mine" / "my_pendulum" / "my_pendulum.c").is_file()


@pytest.mark.slow
def test_installed_c_sources_compile(installed, tmp_path):
    _need_gcc()
    root = Path(installed.python_json(
        "import json, codegen.resources as r; print(json.dumps(str(r.generated())))"))
    assert root.is_relative_to(installed.venv)
    names = sorted(p.name for p in root.iterdir() if (p / f"{p.name}_api.json").is_file())
    assert names == LIBRARIES
    for folder in names + ["runtime"]:
        for source in sorted((root / folder).glob("*.c")):
            obj = tmp_path / f"{folder}_{source.stem}.o"
            installed.run("gcc", *resources.cflags("base"), "-c", f"-I{root / folder}",
                          f"-I{root / 'runtime'}", source, "-o", obj)
            assert obj.stat().st_size > 0
