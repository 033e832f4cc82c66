"""The results of `make bench` as Markdown tables (benchmarks/results.md), and the machine."""
from __future__ import annotations

import datetime
import os
import platform
import subprocess
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy
import sympy

NA = "n/a"


def machine(root: Path, compiler: str) -> dict[str, Any]:
    """Where and when the benchmark ran (the load is added by the runner, before and after)."""
    return {
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "cpu": _cpu_model(), "cores": os.cpu_count(), "compiler": compiler,
        "python": platform.python_version(), "numpy": numpy.__version__,
        "sympy": sympy.__version__, "commit": _commit(root),
    }


def _cpu_model() -> str:
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        return platform.processor() or "unknown"
    return next((line.split(":", 1)[1].strip() for line in lines
                 if line.startswith("model name")), "unknown")


def _commit(root: Path) -> str:
    def git(*args: str) -> str:
        return subprocess.run(["git", *args], cwd=root, capture_output=True, text=True
                              ).stdout.strip()

    head = git("rev-parse", "--short=12", "HEAD") or "unknown"
    return head + (" (with uncommitted changes)" if git("status", "--porcelain") else "")


def num(x: float | None) -> str:
    """A measurement to about three significant digits, without exponents where avoidable."""
    if x is None:
        return NA
    if x >= 100:
        return f"{x:,.0f}".replace(",", " ")
    return f"{x:.1f}" if x >= 10 else f"{x:#.3g}"


def sci(x: float | None) -> str:
    return NA if x is None else f"{x:.1e}"


def ratio(a: float | None, b: float | None) -> float | None:
    return None if a is None or b is None or b == 0 else a / b


def table(headers: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows])


def analysis_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 1, the headline: the whole analysis per parameter set."""
    rows = []
    for name, r in results.items():
        a = r["analysis"]
        rows.append([f"`{name}`", str(a["sets"]), num(a["c_analyze_us"]), num(a["c_isolate_us"]),
                     num(a["python_w1_us"]), num(a["python_w2_us"]),
                     str(a["throughput_sets"]), num(a["w2_over_w1_throughput"]),
                     num(a["numpy_us"]) if a["numpy_us"] is not None else "n/a (no polynomial)",
                     num(a["numpy_over_c"]), num(a["numpy_over_python"]),
                     *target_cells(name, a),
                     num(a.get("certificate_us")),
                     f"{100 * a['certificate_share']:.0f} %" if a.get("certificate_share") is not None
                     else "n/a"])
    return table(["mechanism", "sets", "C `_analyze` [us/set]", "C `_isolate` [us/set]",
                  "Python workers=1 [us/set]", "Python workers=2 [us/set]",
                  "throughput sets", "workers=2 / workers=1 throughput",
                  "numpy pipeline [us/set]",
                  "numpy / C", "numpy / Python workers=1", "target (issue 29)", "met (C, Python)",
                  "certificate [us/set]", "certificate / C `_analyze`"], rows)


#: Issue 29's targets: the numpy pipeline / the library (C and Python workers=1), at least.
SPEED_TARGETS = {"doughty": 3.0, "slider_crank": 1.5, "four_bar": 1.0}


def target_cells(name: str, a: dict[str, Any]) -> list[str]:
    """The target of a mechanism's numpy / library ratio and whether C and Python meet it."""
    goal = SPEED_TARGETS.get(name)
    if goal is None or a["numpy_over_c"] is None:
        return ["n/a", "n/a"]
    met = ["met" if r is not None and r >= goal else "not met"
           for r in (a["numpy_over_c"], a["numpy_over_python"])]
    return [f">= {goal:g}", ", ".join(met)]


def kernels_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 2: thetaddot and sigma, the library against SymPy's ccode."""
    rows = []
    for name, r in results.items():
        k = r["kernels"]
        rows.append([f"`{name}`", f"`{k['thetaddot']}`", num(k["thetaddot_library_ns"]),
                     num(k["thetaddot_kernel_ns"]), num(k["thetaddot_naive_ns"]),
                     num(ratio(k["thetaddot_naive_ns"], k["thetaddot_kernel_ns"])),
                     num(ratio(k["thetaddot_naive_ns"], k["thetaddot_library_ns"])),
                     sci(k["thetaddot_max_rel_diff"]), num(k["sigma_library_ns"]),
                     num(k["sigma_kernel_ns"]), num(k.get("sigma_fast_ns")),
                     num(k["sigma_naive_ns"]),
                     num(ratio(k["sigma_naive_ns"], k.get("sigma_fast_ns"))),
                     num(ratio(k["sigma_naive_ns"], k["sigma_kernel_ns"])),
                     sci(k.get("sigma_fast_max_rel_diff")), sci(k["sigma_max_rel_diff"])])
    return table(["mechanism", "thetaddot function", "thetaddot checked [ns]",
                  "thetaddot kernel [ns]", "thetaddot naive [ns]", "naive / kernel",
                  "naive / checked", "max rel. difference", "sigma checked [ns]",
                  "sigma kernel [ns]", "sigma_fast kernel [ns]", "sigma naive [ns]",
                  "naive / sigma_fast", "naive / sigma kernel",
                  "sigma_fast: max difference / max abs(sigma_i)", "naive: the same"], rows)


def roots_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 3: the library's root finder against numpy.roots."""
    rows = []
    for name, r in results.items():
        x = r["roots"]
        if x is None:
            rows.append([f"`{name}`"] + ["n/a (no polynomial)"] + [NA] * 7)
            continue
        rows.append([f"`{name}`", str(x["degree"]), str(x["polynomials"]), num(x["c_us"]),
                     num(x["numpy_us"]), num(ratio(x["numpy_us"], x["c_us"])),
                     str(x["c_real_roots"]), str(x["numpy_real_roots"]), str(x["disagreements"])])
    return table(["mechanism", "degree", "polynomials", "C `_poly_real_roots` [us]",
                  "numpy.roots [us]", "numpy / C", "real roots (C)", "real roots (numpy)",
                  "polynomials whose counts differ"], rows)


def accuracy_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 4: genuine equilibria against 40 digits."""
    rows = []
    for name, r in results.items():
        x = r["accuracy"]
        if x is None:
            rows.append([f"`{name}`"] + ["n/a (no polynomial)"] + [NA] * 7)
            continue
        rows.append([f"`{name}`", str(x["sets"]), str(x["library_equilibria"]),
                     sci(x["library_max_rel_error"]), str(x["reference_failures"]),
                     str(x["numpy_equilibria"]), sci(x["numpy_max_rel_error"]),
                     str(x["numpy_missed"]), str(x["numpy_extra"])])
    return table(["mechanism", "sets", "equilibria (library)", "max rel. error (library)",
                  "findroot failures", "equilibria (numpy)", "max rel. error (numpy)",
                  "missed by numpy", "extra in numpy"], rows)


def generate_table(generate: dict[str, Any], results: dict[str, dict[str, Any]]) -> str:
    """Section 5: the command line's fresh derivation, and derive() per mechanism."""
    cli = generate["cli"]
    command = f"`{generate['command']}`"
    if cli is None:
        rows = [[command, "all", "skipped (--quick)", "included"]]
    else:
        state = {0: "generated/ current", 1: "generated/ stale"}.get(cli["exit"],
                                                                    f"exit {cli['exit']}")
        rows = [[command, "all", f"{cli['seconds']:.1f} ({state})", "included"]]
    rows += [["`derive()` in the benchmark's process, then `verify()`", f"`{name}`",
              f"{r['derive_seconds']:.1f}",
              f"{v['seconds']:.2f} ({v['sets']} parameter sets, {v['points']} angles, "
              f"sigma at {v['zeros']} zeros of G)"]
             for name, r in results.items() for v in [r["verify"]]]
    return table(["what", "mechanism", "wall time [s]", "verification [s]"], rows)


def branches_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 6: Library.branches over a range with folds."""
    rows = []
    for name, r in results.items():
        b = r["branches"]
        events = ", ".join(f"{kind} x{n}" for kind, n in b["events"].items()) or "none"
        rows.append([f"`{name}`", f"{b['parameter']} from {b['from']:g} to {b['to']:g} "
                     f"{b['unit']}", str(b["points"]), str(b["branches"]), events,
                     f"{b['bisection_width']:.0e} {b['unit']}", f"{b['w1_seconds']:.3f}",
                     f"{b['w2_seconds']:.3f}", f"{b['sampling_w2_seconds']:.3f}"])
    return table(["mechanism", "range", "values", "branches", "events", "bisection to",
                  "workers=1 [s]", "workers=2 [s]", "of which sampling, workers=2 [s]"],
                 rows)


def simulate_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 7: the time response, the library against scipy."""
    rows = []
    for name, r in results.items():
        x = r["simulate"]
        rows.append([f"`{name}`", f"{x['theta0_deg']:.2f}", f"{x['span_s']:g}",
                     num(x["library_ms"]),
                     f"{x['library_steps']} ({x['library_rejected']})",
                     str(x["library_evaluations"]), num(x["scipy_ms"]),
                     str(x["scipy_evaluations"]), num(x["speedup"]),
                     sci(x["library_error"][0]), sci(x["scipy_error"][0]),
                     sci(x["library_error"][1]), sci(x["scipy_error"][1])])
    return table(["mechanism", "theta0 [deg]", "span [s]", "library [ms]",
                  "library steps (rejected)", "library evaluations", "scipy RK45 [ms]",
                  "scipy evaluations", "scipy / library", "theta error library [rad]",
                  "theta error scipy [rad]", "thetadot error library [rel.]",
                  "thetadot error scipy [rel.]"], rows)


def met(flag: bool | None) -> str:
    return NA if flag is None else ("met" if flag else "not met")


def multibody_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 8: mechanisms with n coordinates, the C analysis against a scipy multistart,
    and the modal analysis at one equilibrium."""
    rows = []
    for name, x in results.items():
        rows.append([f"`{name}`", f"{x['sets']} ({x['ok_sets']})", str(x["starts"]),
                     num(x["c_analyze_us"]), num(x["multistart_us"]), num(x["speedup"]),
                     met(x["speedup_met"]), str(x["library_equilibria"]),
                     str(x["multistart_equilibria"]), str(x["missed_by_library"]),
                     str(x["in_uncertain_boxes"]), str(x["missed_by_multistart"]),
                     str(x["uncertain_boxes"]), sci(x["theta_max_diff"]),
                     sci(x["omega_squared_max_rel_diff"]),
                     num(x["modes_ns"]), num(x["modes_max_ns"]), num(x["mb_modes_ns"]),
                     met(x["modes_met"])])
    return table(["mechanism", "sets (analysed)", "starts per set", "C `_analyze` [us/set]",
                  "scipy multistart [us/set]", "multistart / C", "target >= 10",
                  "equilibria (library)", "equilibria (multistart)",
                  "multistart's outside the library's boxes (must be 0)",
                  "multistart's in undecided boxes", "library's missed by the multistart",
                  "undecided boxes", "theta: max difference", "omega^2: max rel. difference",
                  "C `_modes` [ns], mean", "C `_modes` [ns], slowest equilibrium",
                  "`codegen_mb_modes` on M, B, K [ns]", "target < 2 us (mean)"], rows)


def fmu_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 9: the FMU's Co-Simulation against `mechvib simulate`."""
    rows = [[f"`{name}`", str(x["points"]), num(x["fmu_command_ms"]), num(x["cli_command_ms"]),
             num(x["command_ratio"]), met(x["command_met"]), num(x["fmu_call_ms"]),
             num(x["library_call_ms"]), num(x["call_ratio"]), met(x["call_met"]),
             sci(x["theta_max_diff"])] for name, x in results.items()]
    return table(["mechanism", "output points", "fmpy CS, command [ms]",
                  "`mechvib simulate`, command [ms]", "ratio", "target <= 2x",
                  "fmpy CS, in process [ms]", "`Library.simulate` [ms]", "ratio",
                  "target <= 2x", "theta: max difference [rad]"], rows)


def sweep_table(results: dict[str, dict[str, Any]]) -> str:
    """Section 10: a sweep from the command line to Parquet."""
    rows = [[f"`{name}`", num(x["sets"]), str(x["workers"]), num(x["seconds"]),
             num(x["sets_per_second"]), num(x["rows"]), num(x["file_mb"]),
             "n/a (not 10^6 sets)" if x["met"] is None else met(x["met"])]
            for name, x in results.items()]
    return table(["mechanism", "sets", "workers", "wall time [s]", "sets/s", "rows written",
                  "file [MB]", "target < 10 s for 10^6 sets"], rows)


def machine_table(info: dict[str, Any]) -> str:
    load = ", ".join(" / ".join(f"{x:.2f}" for x in info[k]) for k in ("load_before", "load_after"))
    rows = [["date", info["date"]], ["git commit", info["commit"]], ["CPU", info["cpu"]],
            ["cores", str(info["cores"])], ["load (1/5/15 min: before, after)", load],
            ["compiler", f"{info['compiler']}, `{info['cflags']}`"],
            ["Python extensions built from generated/ as it is",
             "yes" if not info["stale_extensions"] else
             "no: " + ", ".join(info["stale_extensions"]) + " (run `make build`)"],
            ["Python, numpy, SymPy", f"{info['python']}, {info['numpy']}, {info['sympy']}"]]
    return table(["", "value"], rows)


#: (title, what it measures) of each section, in order; results.md has one of each.
SECTIONS = (
    ("1. Whole analysis per parameter set",
     "Each mechanism's example with every parameter drawn within +-5 % (fixed seed). C: "
     "`PREFIX_analyze` (and `PREFIX_isolate`, the isolation route) in a loop in "
     "benchmarks/bench.c. Python: `lib.analyze_table(table, workers=N)` (the route `auto` "
     "takes). numpy: the pipeline of benchmarks/pipeline.py (lambdified sigma_i, batched "
     "companion-matrix eigvals, G lambdified to keep the genuine roots, M, B, K, omega_n, "
     "zeta lambdified; genuine where abs(G) <= {genuine_tolerance:g} of the sum of its "
     "contributions' magnitudes, a threshold set in numpy's favour), which neither "
     "polishes, nor certifies, nor labels other assembly modes. The throughput of two "
     "threads against one is measured apart, on the sets repeated to about "
     "{throughput_seconds:g} s of work for one thread (a batch of 200 sets is over before "
     "two threads have spread out); > 1: two threads do more. Issue 29's targets: numpy / "
     "library at least 3 (doughty), 1.5 (slider_crank), 1 (four_bar). The certificate: what "
     "the proof adds to `PREFIX_analyze`, its parts timed apart in bench.c: the bound on "
     "sigma's coefficients (the bounded double-double program less the plain one), the "
     "discs and spans of every root (`codegen_poly_root_spans`) less an uncertified "
     "real-root finder (`PREFIX_poly_real_roots`), and the enclosures of G that decide the "
     "spans (three on a root's own mode, one on each other, re-run at the analysis' "
     "intervals)."),
    ("2. thetaddot and sigma per call against naive SymPy C",
     "The library's functions against `sympy.ccode` of the same expressions after "
     "`sympy.cse` (double precision), compiled with the same flags and called in the same "
     "driver over the same inputs (states at random angles and rates). Checked: the public "
     "function, which validates every input on each call; kernel: the unchecked kernel "
     "behind it (`PREFIX_kernels.h`). sigma is computed in double-double, for the "
     "cancellation (the difference columns: how far double arithmetic is from it); "
     "`PREFIX_sigma_fast` is the same coefficients in double, which does what the naive "
     "code does. naive / kernel > 1: the library is faster."),
    ("3. Root finder against numpy.roots",
     "`PREFIX_poly_real_roots` and `numpy.roots` (one call per polynomial, a root counted "
     "real when abs(imag) <= 1e-8 abs(root)) on the same sigma vectors (the library's)."),
    ("4. Accuracy of the genuine equilibria",
     "Each equilibrium of the declared mode against `mpmath.findroot` on G (lambdified "
     "from the derivation, 40 digits) started at the library's root: max abs(theta - "
     "theta_ref) / abs(theta_ref). The numpy pipeline's genuine roots are matched to the "
     "references within 1e-4 rad."),
    ("5. Generation time",
     "The command line deriving every shipped mechanism afresh and comparing with "
     "generated/ without writing (start-up included; it verifies each plan against its "
     "model), the cold `derive()` of each mechanism inside the benchmark, and the "
     "verification alone (`codegen.compiler.verification.verify`: the plan's expressions against "
     "the model's numerics, which generate runs before writing a file). Target: the "
     "verification adds at most a few seconds to each mechanism's generation."),
    ("6. Branches against one parameter",
     "`lib.branches(NAME, FROM, TO, points=N, workers=W)`: the equilibria at N evenly spaced "
     "values analysed on W threads, joined into branches, every event (fold, pitchfork, "
     "branch end, stability change) refined by bisection on the parameter to the width "
     "shown, all open brackets analysed together in one batch per halving. Sampling: "
     "`sweep.sweep` of the same N sets on two threads, which the call spends first; the "
     "rest is joining and refinement. Target: 2 000 values with fold refinement in under "
     "1 s."),
    ("7. Time response",
     "Each example from rest {offset:g} rad off its least damped stable equilibrium, for "
     "{span:g} s with output at {points} times, rtol {rtol:g} and atol {atol:g}: "
     "`lib.simulate` (the C Dormand-Prince 5(4) of codegen_ode.c through the Python API) "
     "against `scipy.integrate.solve_ivp(method='RK45')` at the same tolerances on thetaddot "
     "lambdified from the derivation to Python's `math` module, timed in the same run; the "
     "errors are the largest against DOP853 at rtol 1e-13 on the same thetaddot (thetadot's "
     "relative to its largest value). Issue 13's target: scipy / library >= 100 on doughty."),
    ("8. Mechanisms with n coordinates",
     "Issue 31, for each shipped mechanism with several coordinates over {multibody_sets} "
     "parameter sets (drawn as above): `NAME_analyze` in C (benchmarks/multibody_bench.c; "
     "every equilibrium in the box of the ranges, each proven, with its modes) against a "
     "scipy multistart that proves nothing: `scipy.optimize.root(method='hybr')` on G from a "
     "{grid} x {grid} grid of starts spanning the range box, with {multistart_G}; the "
     "converged roots kept in the half-open ranges (a periodic coordinate wrapped into its "
     "range), deduplicated within {deduplicate:g}, then `scipy.linalg.eig(K, M)` at each. A "
     "root of the multistart is the library's equilibrium when within its proven box "
     "(+-{match:g}); their theta (max norm) and omega^2 (relative to the largest) are "
     "compared there. The modal analysis alone: `NAME_modes` (M, B, K at theta, then the "
     "modes) per call, the mean over every equilibrium found and at the slowest one, and "
     "`codegen_mb_modes` on M, B and K computed beforehand. Issue 31's targets: multistart "
     "/ C >= {speedup_target:g}, finding nothing the library misses; the modal analysis at "
     "one equilibrium under {modes_target_ns:g} ns."),
    ("9. The FMU",
     "`mechvib fmu`'s FMI 2.0 FMU of the example, Co-Simulation through fmpy for {fmu_span:g} s "
     "at {fmu_step:g} s communication steps from theta = {fmu_theta0:g} rad at rest, against "
     "`mechvib simulate` at the same output times: as whole commands (a new process each: "
     "`python -c \"fmpy.simulate_fmu(...)\"` and `mechvib simulate --out FILE.csv`), and "
     "in one process (`fmpy.simulate_fmu` on the extracted FMU against `Library.simulate`). "
     "Issue 32's target: the FMU within {fmu_target:g}x of `mechvib simulate`."),
    ("10. A sweep to Parquet",
     "`python -m codegen sweep --sample N {sweep_vary} --seed 1 --workers {sweep_workers} "
     "--out FILE.parquet` as a whole command (a new process each run: start-up, sampling, "
     "the analysis, the rows and the file), the median of the runs after one warm-up run. "
     "Issue 29's target: {sweep_target_sets} sets in under {sweep_target:g} s."),
    ("11. Machine", ""),
)


def markdown(results: dict[str, dict[str, Any]], generate: dict[str, Any],
             info: dict[str, Any], config: dict[str, Any],
             multibody: dict[str, dict[str, Any]], fmu: dict[str, dict[str, Any]],
             sweep: dict[str, dict[str, Any]]) -> str:
    """The whole of results.md (``multibody``: section 8's results, ``fmu`` section 9's,
    ``sweep`` section 10's)."""
    tables = (analysis_table(results), kernels_table(results), roots_table(results),
              accuracy_table(results), generate_table(generate, results),
              branches_table(results),
              simulate_table(results), multibody_table(multibody), fmu_table(fmu),
              sweep_table(sweep), machine_table(info))
    head = ("# `make bench` results\n\n"
            "Written by `benchmarks/run.py` (`make bench`); do not edit: run it again. "
            f"{config['sets']} parameter sets per mechanism, medians of {config['repeats']} "
            f"repeats, C compiled with `{info['cflags']}`, load {info['load_before'][0]:.2f} "
            f"before and {info['load_after'][0]:.2f} after (1 min){config['note']}.\n")
    body = ["\n\n".join(part for part in (f"## {title}", text.format(**config), t) if part)
            + "\n"
            for (title, text), t in zip(SECTIONS, tables)]
    return "\n".join([head, *body])
