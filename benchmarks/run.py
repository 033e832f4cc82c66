"""`make bench`: time the C library (compiled -O2) and the Python batch path."""
from __future__ import annotations

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


if __name__ == "__main__":
    c_benchmark()
    python_benchmark()
