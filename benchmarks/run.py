"""`make bench`: time the C library (compiled -O2) and the Python batch path."""
from __future__ import annotations

import math
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
LIBRARY = "doughty"  # bench.c times the paper's example


def c_benchmark() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "bench"
        folders = [GENERATED / LIBRARY, GENERATED / "runtime"]
        sources = [str(c) for folder in folders for c in sorted(folder.glob("*.c"))]
        subprocess.run(["gcc", "-std=c99", "-O2", *(f"-I{f}" for f in folders),
                        str(ROOT / "benchmarks" / "bench.c"), *sources, "-lm", "-o", str(exe)],
                       check=True)
        print(subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout)


def python_benchmark() -> None:
    from codegen.api import load

    lib = load(LIBRARY)
    n = 100_000
    table = lib.params_array([lib.example_params()] * n)
    theta = np.linspace(-3, 3, n)
    start = time.perf_counter()
    lib.linearisation(table, theta)
    print(f"python batch linearisation: {n} items in {time.perf_counter() - start:.3f} s")
    table["F"] = np.linspace(50, 150, n)
    start = time.perf_counter()
    lib.analyze_batch(table[:10_000])
    print(f"python batch analyze:       10000 items in {time.perf_counter() - start:.3f} s")


def routes_benchmark(count: int = 200, repeats: int = 3) -> None:
    """Per parameter set, the C cost of each analysis route of every shipped mechanism, over
    sets within 5 % of its example (the C batch entry points through cffi: no Python objects)."""
    from codegen.api import load, shipped

    rng = np.random.default_rng(20_261_123)
    print(f"analysis routes, C per parameter set ({count} sets within 5 % of the example, "
          f"best of {repeats}):")
    for name in shipped():
        lib = load(name)
        table = lib.params_array([lib.example_params()] * count)
        for field in lib.PARAMETER_NAMES:
            table[field] *= rng.uniform(0.95, 1.05, count)
        results = lib.ffi.new(f"{lib.PREFIX}_analysis[]", count)
        statuses = np.zeros(count, dtype=np.intc)
        routes = ("analyze", "isolate") if lib.has_polynomial else ("isolate",)
        for route in routes:
            entry = getattr(lib.lib, f"{lib.PREFIX}_{route}_batch")
            best = math.inf
            for _ in range(repeats):
                start = time.perf_counter()
                entry(count, lib.ffi.from_buffer(f"{lib.PREFIX}_params[]", table), results,
                      lib.ffi.from_buffer(f"{lib.PREFIX}_status[]", statuses,
                                          require_writable=True))
                best = min(best, time.perf_counter() - start)
            label = "polynomial" if route == "analyze" else "isolation"
            ok = int((statuses == 0).sum())
            print(f"  {name:<17} {label:<10} {best / count * 1e6:9.1f} us/set  ({ok}/{count} OK)")


if __name__ == "__main__":
    c_benchmark()
    python_benchmark()
    routes_benchmark()
