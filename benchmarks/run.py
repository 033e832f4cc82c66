"""`make bench`: time the C library (compiled -O2) and the Python batch path."""
from __future__ import annotations

import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"


def c_benchmark() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "bench"
        subprocess.run(["gcc", "-std=c99", "-O2", "-I", str(GENERATED),
                        str(ROOT / "benchmarks" / "bench.c"),
                        *map(str, sorted(GENERATED.glob("*.c"))), "-lm", "-o", str(exe)],
                       check=True)
        print(subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout)


def python_benchmark() -> None:
    from codegen import api
    from codegen.analysis import analyze_batch

    n = 100_000
    table = api.params_array([api.example_params()] * n)
    theta = np.linspace(-3, 3, n)
    start = time.perf_counter()
    api.linearisation(table, theta)
    print(f"python batch linearisation: {n} items in {time.perf_counter() - start:.3f} s")
    table["F"] = np.linspace(50, 150, n)
    start = time.perf_counter()
    analyze_batch(table[:10_000])
    print(f"python batch analyze:       10000 items in {time.perf_counter() - start:.3f} s")


if __name__ == "__main__":
    c_benchmark()
    python_benchmark()
