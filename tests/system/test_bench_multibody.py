"""Section 8 of `make bench` (benchmarks/multibody.py) alone, in its quick mode: it runs, it
covers every shipped mechanism with several coordinates, the scipy multistart finds no
equilibrium the library misses, and every figure is a positive number. Nothing here times
anything: the figures are not compared with the targets."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

from codegen.api import load, shipped

SECTION = Path(__file__).resolve().parents[2] / "benchmarks" / "multibody.py"
FIGURES = ("c_analyze_us", "multistart_us", "speedup", "modes_ns", "modes_max_ns",
           "mb_modes_ns")


def test_quick_run_finds_nothing_the_library_misses(tmp_path):
    out = tmp_path / "multibody.json"
    done = subprocess.run([sys.executable, str(SECTION), "--quick", "--json", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    results = json.loads(out.read_text())
    several = {name for name in shipped() if load(name).dof > 1}
    assert several and set(results["mechanisms"]) == several
    rows = [line for line in done.stdout.splitlines() if line.startswith("| `")]
    for name, x in results["mechanisms"].items():
        assert sum(f"`{name}`" in row for row in rows) == 1, name
        assert x["sets"] == results["config"]["sets"] and x["ok_sets"] == x["sets"], name
        assert x["starts"] == results["config"]["grid"] ** x["dof"]
        assert x["missed_by_library"] == 0, name  # issue 31: nothing the library misses
        assert x["library_equilibria"] > 0 and x["multistart_equilibria"] > 0, name
        for key in FIGURES:
            assert isinstance(x[key], float) and math.isfinite(x[key]) and x[key] > 0, (
                name, key, x[key])
        assert x["omega_squared_max_rel_diff"] >= 0 and x["theta_max_diff"] >= 0
        assert isinstance(x["speedup_met"], bool) and isinstance(x["modes_met"], bool)
