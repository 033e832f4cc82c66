"""The C side of `make bench`: bench.c built per mechanism, run over the runner's inputs."""
from __future__ import annotations

import json
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from codegen.resources import cflags
from codegen.runtime.library import Library

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
BENCH_C = Path(__file__).resolve().parent / "bench.c"
CC = "gcc"
#: The flags of every C compilation of the benchmark: the library, the naive C and the driver
#: (runtime/cflags.txt's sets).
CFLAGS = tuple(cflags("base", "optimize"))


def thetaddot_name(library: Library, theta_dd: str) -> str:
    """The C name of the function giving thetaddot (output ``theta_dd``), checked against
    the header."""
    found = [f["name"] for f in library.SPEC["functions"]
             if [o["name"] for o in f["outputs"]] == [theta_dd]]
    if len(found) != 1:
        raise RuntimeError(f"{library.PREFIX}: no single function returns {theta_dd}: {found}")
    c_name = f"{library.PREFIX}_{found[0]}"
    if f"{c_name}(" not in header(library).read_text():
        raise RuntimeError(f"{c_name} is not declared in {header(library)}")
    return c_name


def header(library: Library) -> Path:
    return GENERATED / library.PREFIX / f"{library.PREFIX}.h"


@dataclass
class Build:
    """A driver being compiled in the background (compilations overlap the derivations)."""

    executable: Path
    process: subprocess.Popen[bytes]

    def wait(self) -> Path:
        """The executable, once compiled (waits the first time; raises if gcc failed)."""
        if self.process.returncode is None:
            _, errors = self.process.communicate()
            if self.process.returncode != 0:
                raise RuntimeError(f"compiling {self.executable} failed:\n{errors.decode()}")
        return self.executable


def start_build(library: Library, naive_source: str, thetaddot: str, folder: Path) -> Build:
    """Write naive.c and start compiling bench.c with it and the library into ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    naive = folder / "naive.c"
    naive.write_text(naive_source)
    P = library.PREFIX
    include = [GENERATED / P, GENERATED / "runtime"]
    sources = [str(c) for f in include for c in sorted(f.glob("*.c"))]
    defines = [f"-DPREFIX={P}", f"-DPREFIX_UPPER={P.upper()}", f'-DBENCH_HEADER="{P}.h"',
               f'-DKERNELS_HEADER="{P}_kernels.h"',
               f"-DTHETADDOT={thetaddot}", f"-DHAS_POLYNOMIAL={int(library.has_polynomial)}"]
    executable = folder / "bench"
    command = [CC, *CFLAGS, *defines, *(f"-I{f}" for f in include), str(BENCH_C), str(naive),
               *sources, "-lm", "-o", str(executable)]
    return Build(executable, subprocess.Popen(command, stdout=subprocess.DEVNULL,
                                              stderr=subprocess.PIPE))


@dataclass(frozen=True)
class CResults:
    """What one driver run measured (ns), and the library's sigma and real-root counts."""

    timings: dict[str, Any]
    sigma: np.ndarray | None   # n_sets x (degree + 1)
    counts: np.ndarray | None  # real roots per set (-1: the root finder failed)


def run(executable: Path, library: Library, table: np.ndarray, states: np.ndarray,
        repeats: int, min_seconds: float) -> CResults:
    """Run a built driver over ``table`` (a params_array) and ``states`` ((theta, theta_d)
    rows, state i with set i % len(table))."""
    folder = executable.parent
    params, state_file, out = folder / "params.bin", folder / "states.bin", folder / "roots.bin"
    np.ascontiguousarray(table, dtype=library.PARAMS_DTYPE).tofile(params)
    np.ascontiguousarray(states, dtype=np.float64).tofile(state_file)
    done = subprocess.run([str(executable), str(params), str(len(table)), str(state_file),
                           str(len(states)), str(repeats), repr(min_seconds), str(out)],
                          capture_output=True, text=True, check=True)
    timings = json.loads(done.stdout)
    if not library.has_polynomial:
        return CResults(timings, None, None)
    width = int(library.SPEC["sizes"]["N_SIGMA"])
    data = np.fromfile(out, dtype=np.float64)
    n = len(table)
    return CResults(timings, data[:n * width].reshape(n, width), data[n * width:].astype(int))


def stale_extension(library: Library) -> bool:
    """Whether the Python extension was built from other sources than generated/ holds now
    (the C driver compiles generated/, the Python side runs the extension): compared by
    their API descriptions, which carry the version and every signature."""
    spec = GENERATED / library.PREFIX / f"{library.PREFIX}_api.json"
    return json.loads(spec.read_text()) != library.SPEC


def compiler_version() -> str:
    """The first line of ``gcc --version``."""
    done = subprocess.run([CC, "--version"], capture_output=True, text=True, check=True)
    return done.stdout.splitlines()[0]
