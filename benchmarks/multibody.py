"""Section 8 of `make bench`: the mechanisms with n independent coordinates (issue 31).

For each shipped mechanism with more than one coordinate, over parameter sets drawn within
+-5 % of its example (the runner's seed and draws), medians of several repeats:

- ``NAME_analyze`` in C (benchmarks/multibody_bench.c, compiled with the library like
  bench.c): every equilibrium in the box of the ranges, each proven, with its modes; us per
  set;
- what a scipy user would write instead, which proves nothing: ``scipy.optimize.root``
  (method 'hybr') on G from a GRID x GRID grid of starts spanning the range box (cell centres),
  with the Jacobian K, the converged roots kept inside the half-open ranges (a periodic
  coordinate wrapped into its range first: the same state) and deduplicated within
  DEDUPLICATE, then ``scipy.linalg.eig(K, M)`` at each for the undamped modes. G, K and M are
  the library's compiled functions called from Python (``lib.generalised_force``,
  ``lib.stiffness_matrix``, ``lib.mass_matrix``, each one C call per evaluation), the
  fastest G a scipy user could have: a lambdified G would only be slower. us per set;
- the equilibria each finds: the multistart's roots outside every proven box of the library
  (issue 31: must be none), those inside a box the library reported as undecided, and the
  library's equilibria the multistart did not reach; at the equilibria both found, the
  largest difference of their coordinates (max norm) and of omega^2 (relative to the
  largest omega^2);
- the modal analysis alone in C at one equilibrium: ``NAME_modes`` (M, B and K at theta,
  then the modes), the mean over every equilibrium found and at the slowest one, and the
  runtime's ``codegen_mb_modes`` on M, B and K computed beforehand; ns per call.

Issue 31's targets: the multistart at least SPEEDUP_TARGET times slower than the C analysis,
and the modal analysis at one equilibrium under MODES_TARGET_NS.

Run directly (``.venv/bin/python benchmarks/multibody.py [--quick] [--json FILE]``) for this
section alone; it prints its table.
"""
from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg
import scipy.optimize
import sympy as sp

import driver
import report
from codegen.api import load, shipped
from codegen.errors import LibraryError
from codegen.runtime.library import Library

BENCH_C = Path(__file__).resolve().parent / "multibody_bench.c"
GRID = 20               # starts per coordinate of the multistart
DEDUPLICATE = 1e-7      # two roots closer than this (max norm) are one
MATCH = 1e-6            # a root this far outside a proven box is still in it (rounding)
SPEEDUP_TARGET = 10.0   # multistart / C analyze, at least
MODES_TARGET_NS = 2000.0  # the modal analysis at one equilibrium, under
#: Which G the multistart solves (stated in results.md).
G_USED = ("`lib.generalised_force` with Jacobian `lib.stiffness_matrix` (and `lib.mass_matrix` "
          "for eig): the library's compiled C functions through the Python API")
FULL_SETS, QUICK_SETS = 20, 3


def names(selected: list[str] | None = None) -> list[str]:
    """The shipped mechanisms with several coordinates (of ``selected``, if given)."""
    return [n for n in (shipped() if selected is None else selected) if load(n).dof > 1]


@dataclass
class Mechanism:
    """One mechanism with n coordinates, its parameter sets and its driver being built."""

    name: str
    library: Library
    table: np.ndarray    # the parameter sets, a params_array
    build: driver.Build


def start_build(library: Library, folder: Path) -> driver.Build:
    """Start compiling multibody_bench.c with the library into ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    P = library.PREFIX
    include = [driver.GENERATED / P, driver.GENERATED / "runtime"]
    sources = [str(c) for f in include for c in sorted(f.glob("*.c"))]
    defines = [f"-DPREFIX={P}", f"-DPREFIX_UPPER={P.upper()}", f'-DBENCH_HEADER="{P}.h"']
    executable = folder / "multibody_bench"
    command = [driver.CC, *driver.CFLAGS, *defines, *(f"-I{f}" for f in include),
               str(BENCH_C), *sources, "-lm", "-o", str(executable)]
    return driver.Build(executable, subprocess.Popen(command, stdout=subprocess.DEVNULL,
                                                     stderr=subprocess.PIPE))


def prepare(name: str, table: np.ndarray, folder: Path) -> Mechanism:
    """The mechanism ``name`` with its sets ``table``, its driver compiling in ``folder``."""
    library = load(name)
    return Mechanism(name, library, table, start_build(library, folder / f"{name}-multibody"))


@dataclass(frozen=True)
class CFound:
    """What the C driver measured (ns) and what NAME_analyze found in each set."""

    timings: dict[str, Any]
    statuses: np.ndarray                 # per set
    equilibria: list[np.ndarray]         # per set: count x n
    lo: list[np.ndarray]
    hi: list[np.ndarray]
    omega_squared: list[np.ndarray]      # per set: count x n
    uncertain: list[tuple[np.ndarray, np.ndarray]]  # per set: (lo, hi), count x n each


def run_driver(m: Mechanism, repeats: int, min_seconds: float) -> CFound:
    """Run the built driver over the mechanism's sets (records: see multibody_bench.c)."""
    executable = m.build.wait()
    folder = executable.parent
    params, out = folder / "params.bin", folder / "analyses.bin"
    np.ascontiguousarray(m.table, dtype=m.library.PARAMS_DTYPE).tofile(params)
    done = subprocess.run([str(executable), str(params), str(len(m.table)), str(repeats),
                           repr(min_seconds), str(out)], capture_output=True, text=True,
                          check=True)
    sizes = m.library.SPEC["sizes"]
    n, most, unsure = sizes["N_DOF"], sizes["MAX_EQUILIBRIA"], sizes["MAX_UNCERTAIN"]
    widths = [1, 1, 1, most * n, most * n, most * n, most * n, most, unsure * n, unsure * n]
    records = np.fromfile(out, dtype=np.float64).reshape(len(m.table), sum(widths))
    parts = np.split(records, np.cumsum(widths)[:-1], axis=1)
    status, count, uncertain = (p[:, 0].astype(int) for p in parts[:3])
    theta, lo, hi, w2, _, u_lo, u_hi = parts[3:]

    def rows(x: np.ndarray, i: int, k: int) -> np.ndarray:
        return x[i, :k * n].reshape(k, n)

    sets = range(len(m.table))
    return CFound(json.loads(done.stdout), status,
                  [rows(theta, i, count[i]) for i in sets], [rows(lo, i, count[i]) for i in sets],
                  [rows(hi, i, count[i]) for i in sets], [rows(w2, i, count[i]) for i in sets],
                  [(rows(u_lo, i, uncertain[i]), rows(u_hi, i, uncertain[i])) for i in sets])


def centres(library: Library, values: dict[str, float]) -> np.ndarray:
    """Each coordinate's range centre: its expression in the parameters, evaluated."""
    return np.array([float(sp.sympify(e).evalf(subs=values)) for e in
                     library.SPEC["range_centre"]])


def wrap(x: np.ndarray) -> np.ndarray:
    """x into (-pi, pi] modulo 2 pi."""
    return x - 2 * math.pi * np.ceil((x - math.pi) / (2 * math.pi))


@dataclass(frozen=True)
class Problem:
    """One parameter set as the multistart sees it."""

    params: Any              # the library's Params
    centre: np.ndarray
    periodic: np.ndarray     # bool per coordinate


def difference(a: np.ndarray, b: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """a - b per coordinate, a periodic one's the shortest way round."""
    d = a - b
    return np.where(periodic, wrap(d), d)


def multistart(library: Library, p: Problem) -> tuple[list[np.ndarray], list[Any]]:
    """The scipy user's equilibria of one set (the deduplicated converged roots in the
    ranges) and ``scipy.linalg.eig(K, M)`` at each: (roots, eigen-decompositions)."""
    n = len(p.centre)

    def G(x: np.ndarray) -> np.ndarray:
        return library.generalised_force(p.params, x)

    def K(x: np.ndarray) -> np.ndarray:
        return library.stiffness_matrix(p.params, x).reshape(n, n)

    offsets = -math.pi + (np.arange(GRID) + 0.5) * (2 * math.pi / GRID)
    found: list[np.ndarray] = []
    for start in itertools.product(offsets, repeat=n):
        try:
            solution = scipy.optimize.root(G, p.centre + np.array(start), jac=K, method="hybr")
        except LibraryError:  # G or K failed at an iterate (a singular state)
            continue
        if not solution.success:
            continue
        x = p.centre + difference(solution.x, p.centre, p.periodic)
        if not np.all((x > p.centre - math.pi) & (x <= p.centre + math.pi)):
            continue
        if any(np.max(np.abs(difference(x, y, p.periodic))) <= DEDUPLICATE for y in found):
            continue
        found.append(x)
    modes = [scipy.linalg.eig(K(x), library.mass_matrix(p.params, x).reshape(n, n))
             for x in found]
    return found, modes


def compare(c: CFound, found: list[list[np.ndarray]], modes: list[list[Any]],
            problems: list[Problem]) -> dict[str, Any]:
    """The equilibria of the library and of the multistart, set by set."""
    missed = in_uncertain = not_reached = 0
    worst = apart = 0.0
    for i, (roots, decompositions, p) in enumerate(zip(found, modes, problems)):
        reached = np.zeros(len(c.equilibria[i]), dtype=bool)
        for x, (w2, _) in zip(roots, decompositions):
            inside = [r for r, theta in enumerate(c.equilibria[i])
                      if np.all(np.abs(difference(x, theta, p.periodic))
                                <= np.maximum(c.hi[i][r] - theta, theta - c.lo[i][r]) + MATCH)]
            if inside:
                r = inside[0]
                reached[r] = True
                apart = max(apart, float(np.max(np.abs(difference(x, c.equilibria[i][r],
                                                                   p.periodic)))))
                theirs = np.sort(w2.real)
                ours = c.omega_squared[i][r]
                worst = max(worst, float(np.max(np.abs(theirs - ours)) / np.max(np.abs(ours))))
            elif any(np.all((x >= lo - MATCH) & (x <= hi + MATCH)) for lo, hi in
                     zip(*c.uncertain[i])):
                in_uncertain += 1
            else:
                missed += 1
        not_reached += int((~reached).sum())
    return {"missed_by_library": missed, "in_uncertain_boxes": in_uncertain,
            "missed_by_multistart": not_reached, "theta_max_diff": apart,
            "omega_squared_max_rel_diff": worst}


def measure(m: Mechanism, repeats: int, min_seconds: float,
            median_seconds: Callable[[Callable[[], object], int], float]) -> dict[str, Any]:
    """Everything of this section for one mechanism."""
    c = run_driver(m, repeats, min_seconds)
    lib, n = m.library, m.library.dof
    problems = []
    for row in m.table:
        values = dict(zip(lib.PARAMETER_NAMES, map(float, row.tolist())))
        problems.append(Problem(lib.Params(**values), centres(lib, values),
                                np.array(lib.SPEC["periodic"], dtype=bool)))
    results: list[tuple[list[np.ndarray], list[Any]]] = []

    def work() -> None:
        results[:] = [multistart(lib, p) for p in problems]

    sets = len(m.table)
    multistart_us = median_seconds(work, repeats) / sets * 1e6
    found = [r[0] for r in results]
    analyze_us = c.timings["analyze_ns"] / 1e3
    speedup = report.ratio(multistart_us, analyze_us)
    modes_ns = c.timings.get("modes_ns")
    return {"sets": sets, "ok_sets": int((c.statuses == 0).sum()), "dof": n,
            "starts": GRID ** n, "c_analyze_us": analyze_us, "multistart_us": multistart_us,
            "speedup": speedup, "speedup_met": speedup is not None and speedup >= SPEEDUP_TARGET,
            "library_equilibria": int(sum(len(e) for e in c.equilibria)),
            "multistart_equilibria": int(sum(len(f) for f in found)),
            "uncertain_boxes": int(sum(len(u[0]) for u in c.uncertain)),
            **compare(c, found, [r[1] for r in results], problems),
            "modes_ns": modes_ns, "modes_max_ns": c.timings.get("modes_max_ns"),
            "mb_modes_ns": c.timings.get("mb_modes_ns"),
            "modes_met": modes_ns is not None and modes_ns < MODES_TARGET_NS,
            "modes_max_met": (c.timings.get("modes_max_ns") is not None
                              and c.timings["modes_max_ns"] < MODES_TARGET_NS)}


def config() -> dict[str, Any]:
    """This section's settings, for results.json."""
    return {"grid": GRID, "deduplicate": DEDUPLICATE, "match": MATCH,
            "speedup_target": SPEEDUP_TARGET, "modes_target_ns": MODES_TARGET_NS,
            "multistart_G": G_USED}


def main(argv: list[str] | None = None) -> int:
    """This section alone: prints its table (and writes its JSON with --json)."""
    import run  # the runner's sizes and draws (imported here: run imports this module)

    parser = argparse.ArgumentParser(description="Section 8 of make bench alone: "
                                     "mechanisms with n coordinates")
    parser.add_argument("--quick", action="store_true", help="a smoke run: few sets")
    parser.add_argument("--sets", type=int, help="parameter sets per mechanism")
    parser.add_argument("--repeats", type=int, help="samples per timing (the median is kept)")
    parser.add_argument("--mechanism", action="append", choices=names(),
                        help="only these (repeatable; default every one with n > 1)")
    parser.add_argument("--json", type=Path, help="also write the results here")
    args = parser.parse_args(argv)
    sizes = run.QUICK if args.quick else run.FULL
    sets = args.sets or sizes.multibody_sets
    repeats = args.repeats or sizes.repeats
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="mechvib-multibody-") as tmp:
        mechanisms = [prepare(name, run.parameter_sets(load(name), sets, run.rng_for(name)),
                              Path(tmp)) for name in args.mechanism or names()]
        for m in mechanisms:
            m.build.wait()
        results = {m.name: measure(m, repeats, sizes.min_seconds, run.median_seconds)
                   for m in mechanisms}
    load_after = os.getloadavg()
    text = report.multibody_table(results)
    print(f"{sets} parameter sets per mechanism, medians of {repeats} repeats, load "
          f"{' / '.join(f'{x:.2f}' for x in load_before)} before and "
          f"{' / '.join(f'{x:.2f}' for x in load_after)} after (1/5/15 min)\n\n{text}")
    if args.json:
        args.json.write_text(json.dumps(
            {"config": {**config(), "sets": sets, "repeats": repeats, "seed": run.SEED,
                        "spread": run.SPREAD},
             "load_before": load_before, "load_after": load_after, "mechanisms": results},
            indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
