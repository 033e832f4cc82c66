"""The C libraries built into a program of one's own: CMake (find_package after an install,
and add_subdirectory) and pkg-config, each building examples/minimal.c and running it against
the Python API's analysis of the same parameters.

Locally a missing cmake or pkg-config skips with its install command; under CI it fails.
"""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

import codegen
from codegen.runtime.analysis import analyze
from codegen.api import load
from codegen.resources import cflags

ROOT = Path(__file__).resolve().parents[2]
MINIMAL = ROOT / "examples" / "minimal.c"
MECHANISMS = sorted(p.name for p in (ROOT / "generated").iterdir()
                    if (p / f"{p.name}.h").is_file())


def _run(command: list[str], **kwargs) -> str:
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    assert result.returncode == 0, (f"{' '.join(map(str, command))}\n"
                                    f"{result.stdout[-3000:]}{result.stderr[-3000:]}")
    return result.stdout


def _configure(source: Path, build: Path, *options: str) -> subprocess.CompletedProcess:
    return subprocess.run(["cmake", "-S", str(source), "-B", str(build), *options],
                          capture_output=True, text=True)


def _errors(process: subprocess.CompletedProcess) -> str:
    """stderr with CMake's line wrapping undone."""
    return " ".join(process.stderr.split())


def _build(source: Path, build: Path, *options: str) -> None:
    configured = _configure(source, build, *options)
    assert configured.returncode == 0, configured.stdout + configured.stderr
    _run(["cmake", "--build", str(build), "-j2"])


def _expected_minimal_output() -> str:
    """What examples/minimal.c prints, from the Python API: every root of Table 2."""
    analysis = analyze(load("doughty").example_params())
    return "".join(f"theta_E = {e.theta_deg:9.4f} deg  "
                   f"{'genuine' if e.genuine else 'extraneous':<10s}  K_EQ = {e.K:10.4f} N m\n"
                   for e in analysis.roots)


def _consumer_project(folder: Path, find: str, target: str, source: Path = MINIMAL) -> Path:
    """A project building SOURCE (minimal.c) into `minimal`; FIND is how it gets the library
    (find_package or add_subdirectory), TARGET what it links."""
    folder.mkdir()
    (folder / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\n"
        "project(consumer LANGUAGES C)\n"
        f"{find}\n"
        f"add_executable(minimal {source.as_posix()})\n"
        f"target_link_libraries(minimal PRIVATE {target})\n")
    return folder


@pytest.fixture(scope="module")
def cmake(need_tools):
    need_tools("cmake", "cc")


@pytest.fixture(scope="module")
def prefix(cmake, tmp_path_factory) -> Path:
    """The doughty libraries (double and float) configured, built and installed (Debug: quick)
    into a fresh prefix."""
    work = tmp_path_factory.mktemp("install")
    _build(ROOT, work / "build", "-DCMAKE_BUILD_TYPE=Debug", "-DMECHVIB_MECHANISMS=doughty")
    _run(["cmake", "--install", str(work / "build"), "--prefix", str(work / "prefix")])
    return work / "prefix"


def test_configure_discovers_every_mechanism(cmake, tmp_path):
    """A target pair and a .pc pair per folder of generated/, named after it."""
    configured = _configure(ROOT, tmp_path)
    assert configured.returncode == 0, configured.stderr
    assert len(MECHANISMS) >= 4
    assert (f"mechvib {codegen.__version__}: {';'.join(MECHANISMS)} (each also _float)"
            in configured.stdout)
    for name in MECHANISMS:
        assert (tmp_path / f"mechvib-{name}.pc").is_file()
        float_pc = (tmp_path / f"mechvib-{name}-float.pc").read_text()
        assert "-DCODEGEN_FLOAT" in float_pc and f"-lmechvib_{name}_float -lm" in float_pc


@pytest.mark.parametrize("flag", ["-ffast-math", "-fsingle-precision-constant"])
def test_configure_refuses_flags_that_break_the_arithmetic(cmake, tmp_path, flag):
    configured = _configure(ROOT, tmp_path, f"-DCMAKE_C_FLAGS=-O2 {flag}")
    assert configured.returncode != 0
    assert f"{flag} in the C flags breaks the analysis's arithmetic" in _errors(configured)


def test_configure_refuses_an_unknown_mechanism(cmake, tmp_path):
    configured = _configure(ROOT, tmp_path, "-DMECHVIB_MECHANISMS=no_such_mechanism")
    assert configured.returncode != 0
    assert "names no_such_mechanism, not a folder of generated/" in _errors(configured)


def test_install_layout(prefix):
    include = prefix / "include" / "mechvib"
    assert {"doughty.h", "doughty_kernels.h", "codegen_runtime.h", "codegen_interval.h"} <= {
        p.name for p in include.iterdir()}
    lib = prefix / "lib"
    assert (lib / "libmechvib_doughty.a").is_file()
    assert (lib / "libmechvib_doughty_float.a").is_file()
    assert (lib / "cmake" / "mechvib" / "mechvibConfig.cmake").is_file()


def test_find_package_consumer(prefix, tmp_path):
    project = _consumer_project(tmp_path / "app", "find_package(mechvib 0.1 REQUIRED "
                                "COMPONENTS doughty doughty_float)", "mechvib::doughty")
    _build(project, tmp_path / "build", f"-DCMAKE_PREFIX_PATH={prefix}")
    assert _run([str(tmp_path / "build" / "minimal")]) == _expected_minimal_output()


def test_find_package_fails_on_a_missing_component(prefix, tmp_path):
    project = _consumer_project(tmp_path / "app", "find_package(mechvib REQUIRED COMPONENTS "
                                "no_such_mechanism)", "mechvib::doughty")
    configured = _configure(project, tmp_path / "build", f"-DCMAKE_PREFIX_PATH={prefix}")
    assert configured.returncode != 0 and "no_such_mechanism" in _errors(configured)


def test_pkg_config_consumer(prefix, tmp_path, need_tools):
    """`cc app.c $(pkg-config --cflags --libs mechvib-doughty)`, the .pc found from where it
    lies (the prefix given only at install)."""
    need_tools("pkg-config")
    env = {**os.environ, "PKG_CONFIG_PATH": str(prefix / "lib" / "pkgconfig")}
    flags = _run(["pkg-config", "--cflags", "--libs", "mechvib-doughty"], env=env).split()
    _run(["cc", *cflags("base", "optimize"), str(MINIMAL), *flags, "-o",
          str(tmp_path / "minimal")])
    assert _run([str(tmp_path / "minimal")]) == _expected_minimal_output()


def test_float_variants_define_codegen_float(prefix, tmp_path, need_tools):
    """mechvib::NAME_float and mechvib-NAME-float.pc hand CODEGEN_FLOAT to their users (the
    float build selects on it), the double ones do not."""
    need_tools("pkg-config")
    env = {**os.environ, "PKG_CONFIG_PATH": str(prefix / "lib" / "pkgconfig")}
    assert "-DCODEGEN_FLOAT" in _run(["pkg-config", "--cflags", "mechvib-doughty-float"],
                                     env=env)
    assert "CODEGEN_FLOAT" not in _run(["pkg-config", "--cflags", "mechvib-doughty"], env=env)
    probe = tmp_path / "probe.c"
    probe.write_text('#include "doughty.h"\n'
                     "#ifndef CODEGEN_FLOAT\n#error CODEGEN_FLOAT is not defined\n#endif\n"
                     "int main(void) { return doughty_analyze(0, 0) == DOUGHTY_OK; }\n")
    project = _consumer_project(tmp_path / "app", "find_package(mechvib REQUIRED)",
                                "mechvib::doughty_float", probe)
    _build(project, tmp_path / "build", f"-DCMAKE_PREFIX_PATH={prefix}")
    # NULL pointers: a status, not a crash; the program exits 0 when that status is not OK
    _run([str(tmp_path / "build" / "minimal")])


def test_add_subdirectory_consumer(cmake, tmp_path):
    """The checkout as a subproject: only what the program links is built, nothing installed."""
    project = _consumer_project(tmp_path / "app", f"add_subdirectory({ROOT.as_posix()} mechvib "
                                "EXCLUDE_FROM_ALL)", "mechvib::doughty")
    _build(project, tmp_path / "build")
    assert _run([str(tmp_path / "build" / "minimal")]) == _expected_minimal_output()
    built = {p.name for p in (tmp_path / "build" / "mechvib").glob("*.a")}
    assert built == {"libmechvib_doughty.a"}
