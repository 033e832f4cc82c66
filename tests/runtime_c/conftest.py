"""The C runtime of runtime/, compiled and tested on its own: its root finder, intervals,
boxes, double-double, modal algebra, integrator and analysis, each built from runtime/'s
sources alone (with a driver of drivers/ fed commands on stdin, or into a cffi extension)
with runtime/cflags.txt's flags.

Nothing generated or built is needed: ``pytest tests/runtime_c`` passes in a fresh clone.
So nothing here loads a mechanism's library or imports codegen.api; of the package, only
codegen.resources (standard library only) is read, for the flags. A package (this folder's
__init__.py), so that this conftest and tests/conftest.py are two modules.
"""
from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest

from codegen import resources

ROOT = Path(__file__).resolve().parents[2]
#: The hand-written C runtime, as edited (generated/runtime/ is its copy).
RUNTIME = ROOT / resources.RUNTIME
DRIVERS = Path(__file__).resolve().parent / "drivers"
#: runtime/cflags.txt's sets, of this checkout's runtime.
CFLAGS = resources.cflag_sets(RUNTIME / resources.CFLAGS)


def cflags(*names: str) -> list[str]:
    """The flags of the named sets of runtime/cflags.txt, in order."""
    return [flag for name in names for flag in CFLAGS[name]]


class DriverProgram:
    """A compiled test driver: one command per line on stdin, one answer line per command."""

    def __init__(self, exe: Path, env=None):
        self.exe, self.env = exe, env

    def raw(self, lines, timeout=120.0) -> str:
        r = subprocess.run([str(self.exe)], input="\n".join(lines) + "\n", capture_output=True,
                           text=True, env=self.env, timeout=timeout)
        assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-4000:]
        return r.stdout

    def __call__(self, lines, timeout=120.0) -> list[list[str]]:
        """The words of each answer line."""
        out = self.raw(lines, timeout).splitlines()
        assert len(out) == len(lines)
        return [line.split() for line in out]


@dataclass(frozen=True)
class RuntimeDriverCompiler:
    """Builds a driver of drivers/ with sources of runtime/ (strict: the sets base, optimize
    and strict, unless other flags are given)."""

    cc: str
    strict: tuple[str, ...] = tuple(cflags("base", "optimize", "strict"))
    #: The warnings, to add to other flags (the sanitizers').
    warnings: tuple[str, ...] = tuple(cflags("strict"))

    def build(self, exe: Path, driver: str, runtime: str | tuple[str, ...], flags=None,
              defines=()) -> Path:
        sources = [RUNTIME / name for name in ((runtime,) if isinstance(runtime, str) else runtime)]
        r = subprocess.run([self.cc, *(self.strict if flags is None else flags), *defines,
                            f"-I{RUNTIME}", str(DRIVERS / driver),
                            *map(str, sources), "-lm", "-o", str(exe)],
                           capture_output=True, text=True)
        assert r.returncode == 0, f"compilation failed:\n{r.stderr}"
        return exe

    @staticmethod
    def program(exe: Path, env=None) -> DriverProgram:
        """A built driver, to feed commands (``env``: its environment, e.g. ASAN_OPTIONS)."""
        return DriverProgram(exe, env)


@pytest.fixture(scope="session")
def runtime_driver() -> RuntimeDriverCompiler:
    """Compiles the runtime's test drivers; skips where there is no C compiler."""
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler")
    return RuntimeDriverCompiler(cc)
