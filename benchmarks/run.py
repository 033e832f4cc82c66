"""`make bench`: the library side by side with what a SymPy and numpy user would write.

For every shipped mechanism, over parameter sets drawn within +-5 % of its example (fixed
seed), medians of several repeats:

1. the whole analysis per set: the C API (benchmarks/bench.c), the Python batch API
   (``analyze_table``, one and two threads) and a numpy pipeline built from the derivation
   (benchmarks/pipeline.py);
2. thetaddot and sigma per call against SymPy's ccode of the same expressions;
3. the root finder against numpy.roots, and the real roots each finds;
4. the genuine equilibria of the library and of the pipeline against 40 digits;
5. the wall time of deriving everything afresh (``python -m codegen generate --no-cache
   --check``, which writes nothing);
6. ``Library.branches`` over a parameter range holding folds (benchmarks/branch_timing.py);
7. the time response: ``Library.simulate`` against scipy's solve_ivp (RK45) on the
   lambdified thetaddot, and both against a tight reference (benchmarks/simulate.py);
8. the mechanisms with several coordinates: the C analysis against a scipy multistart, and
   the modal analysis at one equilibrium (benchmarks/multibody.py; sections 1-7 take the
   mechanisms with one coordinate);
9. the FMU: Co-Simulation through fmpy against `mechvib simulate` (benchmarks/fmu.py);
10. the machine, its load, the compiler, the date and the commit.

Writes results.md and results.json (into benchmarks/, or --out) and prints the tables.
``--quick`` is a smoke run of a few seconds per mechanism (the derivations dominate).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
import zlib
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

import accuracy
import branch_timing
import driver
import fmu
import multibody
import pipeline
import report
import simulate
import sweep_timing
from codegen.api import load, shipped
from codegen.runtime.library import Library
from symbolic import Symbolic, naive_c, scalar_function, symbolic

HERE = Path(__file__).resolve().parent
SEED = 20_261_123
SPREAD = 0.05          # parameters within +-5 % of the example
MAX_RATE = 10.0        # |theta_d| of the thetaddot inputs [rad/s]
GENERATE = ("-m", "codegen", "generate", "--no-cache", "--check")


@dataclass(frozen=True)
class Sizes:
    """How much each measurement does."""

    sets: int            # parameter sets per mechanism (sections 1-3)
    repeats: int         # samples per timing; the median is reported
    states: int          # (theta, theta_d) inputs of thetaddot (section 2)
    accuracy_sets: int   # sets checked against 40 digits (section 4)
    min_seconds: float   # shortest C timing sample
    generate: bool       # time the command line's fresh derivation (section 5)
    branch_points: int   # parameter values of each branches run (section 6)
    throughput_seconds: float  # one thread's work per run when two threads are compared
    multibody_sets: int  # parameter sets per mechanism with several coordinates (section 8)
    sweep_sets: int      # doughty sets swept from the command line (section 10)
    sweep_repeats: int   # runs of that command; the median is reported


FULL = Sizes(sets=200, repeats=5, states=1000, accuracy_sets=50, min_seconds=0.02,
             generate=True, branch_points=2000, throughput_seconds=0.3, multibody_sets=20,
             sweep_sets=sweep_timing.TARGET_SETS, sweep_repeats=3)
QUICK = Sizes(sets=12, repeats=3, states=100, accuracy_sets=3, min_seconds=0.002,
              generate=False, branch_points=100, throughput_seconds=0.02, multibody_sets=3,
              sweep_sets=10_000, sweep_repeats=1)


@dataclass
class Mechanism:
    """One shipped mechanism with everything measured on it."""

    name: str
    library: Library
    symbols: Symbolic
    pipeline: pipeline.Pipeline | None
    build: driver.Build
    thetaddot: str       # the C name of the library's thetaddot function
    table: np.ndarray    # the parameter sets, a params_array
    states: np.ndarray   # (theta, theta_d) rows; state i uses set i % len(table)


def progress(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def rng_for(name: str) -> np.random.Generator:
    """A generator per mechanism: the same draws whichever mechanisms run, in any order."""
    return np.random.default_rng([SEED, zlib.crc32(name.encode())])


def parameter_sets(library: Library, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` sets, every parameter of the example scaled by a factor in 1 +- SPREAD."""
    table = library.params_array([library.example_params()] * count)
    for field in library.PARAMETER_NAMES:
        table[field] *= rng.uniform(1 - SPREAD, 1 + SPREAD, count)
    return table


def states(library: Library, table: np.ndarray, count: int, rng: np.random.Generator
           ) -> np.ndarray:
    """``count`` (theta, theta_d) rows, theta anywhere in the coordinate's range (a turn
    around its centre, which may be a parameter of the set the state uses)."""
    centre = library.SPEC["range_centre"]
    sets = np.arange(count) % len(table)
    middle = table[centre][sets] if centre in library.PARAMETER_NAMES else float(centre)
    theta = middle + rng.uniform(-math.pi, math.pi, count)
    return np.column_stack([theta, rng.uniform(-MAX_RATE, MAX_RATE, count)])


def median_seconds(work: Callable[[], object], repeats: int) -> float:
    """The median wall time of ``work`` over ``repeats`` runs, after one warm-up run."""
    work()
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples)


def prepare(name: str, sizes: Sizes, folder: Path) -> Mechanism:
    """Derive a mechanism, draw its inputs and start compiling its driver."""
    library = load(name)
    progress(f"{name}: deriving")
    symbols = symbolic(name, library.PARAMETER_NAMES)
    thetaddot = driver.thetaddot_name(library, str(symbols.theta_dd))
    progress(f"{name}: printing naive C and lambdifying")
    build = driver.start_build(library, naive_c(library.PREFIX, symbols), thetaddot,
                               folder / name)
    rng = rng_for(name)
    table = parameter_sets(library, sizes.sets, rng)
    return Mechanism(name, library, symbols, pipeline.build(symbols), build, thetaddot, table,
                     states(library, table, sizes.states, rng))


def measure(m: Mechanism, sizes: Sizes) -> dict[str, Any]:
    """Sections 1-4 for one mechanism."""
    progress(f"{m.name}: C driver")
    c = driver.run(m.build.wait(), m.library, m.table, m.states, sizes.repeats, sizes.min_seconds)
    progress(f"{m.name}: Python and numpy")
    columns = pipeline.columns(m.table, m.library.PARAMETER_NAMES)
    found = pipeline.analyze(m.pipeline, columns) if m.pipeline else None
    analysed = m.library.analyze_table(m.table)
    check = m.symbols.verification
    result = {"derive_seconds": m.symbols.derive_seconds,
              "verify": {"seconds": check.seconds, "sets": check.sets, "points": check.points,
                         "zeros": check.zeros},
              "analysis": analysis_timings(m, c, analysed, columns, sizes),
              "kernels": kernels(m, c),
              "roots": roots(m, c, sizes) if c.sigma is not None else None,
              "accuracy": None,
              "branches": branch_timing.measure(m.name, m.library, sizes.branch_points,
                                                sizes.repeats, median_seconds)}
    progress(f"{m.name}: time response")
    result["simulate"] = simulate.measure(m.library, m.symbols, sizes.repeats, median_seconds)
    if found is not None:
        progress(f"{m.name}: 40-digit references")
        count = min(sizes.accuracy_sets, len(m.table))
        G = scalar_function((m.symbols.theta, *m.symbols.parameters), m.symbols.residual)
        result["accuracy"] = accuracy.compare(G, m.table[:count], m.library.PARAMETER_NAMES,
                                              analysed.equilibria, found)
    return result


def certificate(t: dict[str, float]) -> float | None:
    """us per set that the proof adds to the C analysis, from its parts timed apart: the bound
    on sigma's coefficients (the bounded double-double program less the plain one), the discs
    and spans of every root over an uncertified real-root finder (codegen_poly_root_spans
    less PREFIX_poly_real_roots), and the enclosures of G that decide the spans (re-run at the
    analysis' intervals). None without a polynomial route."""
    keys = ("sigma_bounds_ns", "sigma_kernel_ns", "spans_ns", "roots_ns", "enclosures_ns")
    if any(t.get(k) is None for k in keys):
        return None
    return ((t["sigma_bounds_ns"] - t["sigma_kernel_ns"]) + (t["spans_ns"] - t["roots_ns"])
            + t["enclosures_ns"]) / 1e3


def analysis_timings(m: Mechanism, c: driver.CResults, analysed: Any,
                     columns: list[np.ndarray], sizes: Sizes) -> dict[str, Any]:
    """Section 1: us per set of the C API, the Python batch API and the numpy pipeline."""
    n = len(m.table)

    def per_set(work: Callable[[], object]) -> float:
        return median_seconds(work, sizes.repeats) / n * 1e6

    python = {w: per_set(lambda w=w: m.library.analyze_table(m.table, workers=w)) for w in (1, 2)}
    # Threads against one on a batch long enough for two threads to pay off (each is started
    # per call): the sets repeated to about sizes.throughput_seconds of one thread's work.
    count = max(n, round(sizes.throughput_seconds / (python[1] * 1e-6)))
    big = np.resize(m.table, count)
    threads = {w: median_seconds(lambda w=w: m.library.analyze_table(big, workers=w),
                                 sizes.repeats) for w in (1, 2)}
    c_us = c.timings["analyze_ns"] / 1e3
    numpy_us = per_set(lambda: pipeline.analyze(m.pipeline, columns)) if m.pipeline else None
    certificate_us = certificate(c.timings)
    return {"sets": n, "ok_sets": int((analysed.statuses == 0).sum()), "route": analysed.method,
            "c_analyze_us": c_us, "c_isolate_us": c.timings["isolate_ns"] / 1e3,
            "certificate_us": certificate_us,
            "certificate_share": report.ratio(certificate_us, c_us),
            "python_w1_us": python[1], "python_w2_us": python[2],
            "throughput_sets": count, "w2_over_w1_throughput": threads[1] / threads[2],
            "numpy_us": numpy_us, "numpy_over_c": report.ratio(numpy_us, c_us),
            "numpy_over_python": report.ratio(numpy_us, python[1])}


def kernels(m: Mechanism, c: driver.CResults) -> dict[str, Any]:
    """Section 2: ns per call of thetaddot and sigma, library and naive."""
    t = c.timings
    keys = ("thetaddot_library_ns", "thetaddot_kernel_ns", "thetaddot_naive_ns",
            "thetaddot_max_rel_diff", "sigma_library_ns", "sigma_kernel_ns", "sigma_fast_ns",
            "sigma_naive_ns", "sigma_max_rel_diff", "sigma_fast_max_rel_diff")
    return {"thetaddot": m.thetaddot,
            **{k: t.get(k) for k in keys}}


def roots(m: Mechanism, c: driver.CResults, sizes: Sizes) -> dict[str, Any]:
    """Section 3: the root finder against numpy.roots on the library's sigma vectors."""
    good = np.isfinite(c.sigma).all(axis=1) & (c.counts >= 0)
    sigma, counts = c.sigma[good], c.counts[good]
    numpy_us = median_seconds(lambda: pipeline.numpy_roots_counts(sigma), sizes.repeats) \
        / max(len(sigma), 1) * 1e6
    theirs = pipeline.numpy_roots_counts(sigma)
    return {"degree": sigma.shape[1] - 1, "polynomials": int(len(sigma)),
            "c_us": c.timings["roots_ns"] / 1e3, "numpy_us": numpy_us,
            "c_real_roots": int(counts.sum()), "numpy_real_roots": int(theirs.sum()),
            "disagreements": int((counts != theirs).sum())}


def time_generate(enabled: bool) -> dict[str, Any]:
    """Section 5: one fresh derivation of every mechanism by the command line (no writes)."""
    command = ".venv/bin/python " + " ".join(GENERATE)
    if not enabled:
        return {"command": command, "cli": None}
    progress("timing " + command)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, *GENERATE], cwd=driver.ROOT, capture_output=True)
    return {"command": command,
            "cli": {"seconds": time.perf_counter() - start, "exit": done.returncode}}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run: small sizes, "
                        "no command-line generation timing")
    parser.add_argument("--sets", type=int, help="parameter sets per mechanism")
    parser.add_argument("--repeats", type=int, help="samples per timing (the median is kept)")
    parser.add_argument("--mechanism", action="append", choices=shipped(),
                        help="only these (repeatable; default every shipped mechanism)")
    parser.add_argument("--out", type=Path, default=HERE,
                        help="folder for results.md and results.json (default benchmarks/)")
    args = parser.parse_args(argv)
    sizes = QUICK if args.quick else FULL
    sizes = Sizes(**{**asdict(sizes), **{k: getattr(args, k) for k in ("sets", "repeats")
                                        if getattr(args, k) is not None}})
    load_before = os.getloadavg()
    selected = args.mechanism or shipped()
    several = multibody.names(selected)  # section 8's; sections 1-7 take the others
    with tempfile.TemporaryDirectory(prefix="mechvib-bench-") as tmp:
        multibodies = [multibody.prepare(name, parameter_sets(
            load(name), sizes.multibody_sets, rng_for(name)), Path(tmp)) for name in several]
        mechanisms = [prepare(name, sizes, Path(tmp)) for name in selected
                      if name not in several]
        for m in [*mechanisms, *multibodies]:  # every compilation done before anything is timed
            m.build.wait()
        results = {m.name: measure(m, sizes) for m in mechanisms}
        multibody_results = {}
        for m in multibodies:
            progress(f"{m.name}: C analysis against a scipy multistart")
            multibody_results[m.name] = multibody.measure(m, sizes.repeats, sizes.min_seconds,
                                                          median_seconds)
    fmu_results = {}
    sweep_results = {}
    if "doughty" in selected:
        progress("doughty: the FMU's Co-Simulation against mechvib simulate")
        fmu_results["doughty"] = fmu.measure(load("doughty"), sizes.repeats)
        progress(f"doughty: {sizes.sweep_sets} sets swept from the command line to Parquet")
        sweep_results["doughty"] = sweep_timing.measure("doughty", sizes.sweep_sets,
                                                        sizes.sweep_repeats, median_seconds)
    generate = time_generate(sizes.generate)
    info = {**report.machine(driver.ROOT, driver.compiler_version()),
            "cflags": " ".join(driver.CFLAGS), "load_before": load_before,
            "stale_extensions": [m.name for m in [*mechanisms, *multibodies]
                                 if driver.stale_extension(m.library)],
            "load_after": os.getloadavg()}
    config = {**asdict(sizes), "seed": SEED, "spread": SPREAD,
              "genuine_tolerance": pipeline.GENUINE, "real_tolerance": pipeline.REAL,
              "offset": simulate.OFFSET, "span": simulate.SPAN, "points": simulate.POINTS,
              "rtol": simulate.RTOL, "atol": simulate.ATOL, **multibody.config(),
              "fmu_span": fmu.SPAN, "fmu_step": fmu.STEP, "fmu_theta0": fmu.THETA0,
              "fmu_target": fmu.TARGET, "sweep_target": sweep_timing.TARGET,
              "sweep_target_sets": sweep_timing.TARGET_SETS, "sweep_workers": sweep_timing.WORKERS,
              "sweep_vary": " ".join(f"--vary {v}" for v in sweep_timing.VARY),
              "note": " (--quick: a smoke run, not for quoting)" if args.quick else ""}
    text = report.markdown(results, generate, info, config, multibody_results, fmu_results,
                           sweep_results)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "results.md").write_text(text)
    (args.out / "results.json").write_text(json.dumps(
        {"config": config, "machine": info, "generate": generate, "mechanisms": results,
         "multibody": multibody_results, "fmu": fmu_results, "sweep": sweep_results},
        indent=2) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
