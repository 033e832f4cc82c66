"""Section 9 of `make bench`: the FMU's Co-Simulation against `mechvib simulate`.

Issue 32's target: Co-Simulation of doughty for SPAN s at STEP s communication steps through
fmpy, within 2x of `mechvib simulate` on the same run (from THETA0 at rest, output at every
communication point). Measured two ways, in the same run:
- whole commands, as a user runs them: ``python -c "fmpy.simulate_fmu(...)"`` on the FMU
  against ``mechvib simulate --points N --out FILE.csv`` (each a new process; the median of
  ``repeats``);
- in one process: ``fmpy.simulate_fmu`` on the extracted FMU (its model description read
  once) against ``Library.simulate`` at the same times.
Both runs' theta are compared (they use the same integrator, so they agree to rounding).
"""
from __future__ import annotations

import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

SPAN, STEP = 2.0, 1e-3      # [s]
THETA0 = 2.8                # [rad]
TARGET = 2.0


def _median_seconds(command: list[str], repeats: int, cwd: Path) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True, cwd=cwd)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def measure(library: Any, repeats: int) -> dict[str, Any]:
    from fmpy import extract, read_model_description, simulate_fmu

    from codegen.fmu import write_fmu

    points = round(SPAN / STEP) + 1
    with tempfile.TemporaryDirectory(prefix="mechvib-fmu-") as tmp:
        folder = Path(tmp)
        fmu = write_fmu(library, folder / f"{library.PREFIX}.fmu")
        script = (f"from fmpy import simulate_fmu; simulate_fmu({str(fmu)!r}, "
                  f"fmi_type='CoSimulation', stop_time={SPAN!r}, output_interval={STEP!r}, "
                  f"start_values={{'theta': {THETA0!r}}}, output=['theta'])")
        fmu_command = _median_seconds([sys.executable, "-c", script], repeats, folder)
        cli = [sys.executable, "-m", "codegen", "simulate", "--mechanism", library.PREFIX,
               "--theta0", repr(math.degrees(THETA0)), "--to", repr(SPAN), "--points",
               str(points), "--out", "motion.csv"]
        cli_command = _median_seconds(cli, repeats, folder)
        unzipped = extract(str(fmu))
        description = read_model_description(unzipped)
        times = np.linspace(0.0, SPAN, points)
        fmu_calls, library_calls = [], []
        for _ in range(repeats):
            start = time.perf_counter()
            result = simulate_fmu(unzipped, model_description=description,
                                  fmi_type="CoSimulation", stop_time=SPAN, output_interval=STEP,
                                  start_values={"theta": THETA0}, output=["theta"])
            fmu_calls.append(time.perf_counter() - start)
            start = time.perf_counter()
            motion = library.simulate(None, THETA0, 0.0, times)
            library_calls.append(time.perf_counter() - start)
    in_process = statistics.median(fmu_calls) / statistics.median(library_calls)
    return {"span_s": SPAN, "step_s": STEP, "points": points,
            "fmu_command_ms": fmu_command * 1e3, "cli_command_ms": cli_command * 1e3,
            "command_ratio": fmu_command / cli_command,
            "command_met": fmu_command / cli_command <= TARGET,
            "fmu_call_ms": statistics.median(fmu_calls) * 1e3,
            "library_call_ms": statistics.median(library_calls) * 1e3,
            "call_ratio": in_process, "call_met": in_process <= TARGET,
            "theta_max_diff": float(np.abs(result["theta"] - motion.theta).max())}
