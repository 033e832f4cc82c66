"""`make bench` in its quick mode: it runs, and its results file has every section with one
line per shipped mechanism. Nothing here times anything: the figures are not checked."""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from codegen.api import load, shipped

RUNNER = Path(__file__).resolve().parents[2] / "benchmarks" / "run.py"
SECTIONS = 11
FMU = 9         # the FMU's section: the paper's example only
SWEEP = 10      # the command-line sweep's: the paper's example only
#: Section 8 times the mechanisms with several coordinates; sections 1-7 the others.
SEVERAL = 8


def _sections(text: str) -> dict[int, str]:
    """The body of each numbered '## N. title' section of results.md."""
    parts = re.split(r"^## (\d+)\. ", text, flags=re.MULTILINE)
    return {int(number): body for number, body in zip(parts[1::2], parts[2::2])}


@pytest.mark.slow  # the quick run still derives all four mechanisms: ~40 s
def test_quick_run_writes_every_section_with_every_mechanism(tmp_path):
    done = subprocess.run([sys.executable, str(RUNNER), "--quick", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    text = (tmp_path / "results.md").read_text()
    assert done.stdout.strip() == text.strip()  # the runner prints the tables it writes
    sections = _sections(text)
    assert sorted(sections) == list(range(1, SECTIONS + 1))
    one = [name for name in shipped() if load(name).dof == 1]
    several = [name for name in shipped() if load(name).dof > 1]
    for number in range(1, SECTIONS):
        rows = [line for line in sections[number].splitlines() if line.startswith("| ")]
        measured = (["doughty"] if number in (FMU, SWEEP) else several if number == SEVERAL
                    else one)
        for name in measured:
            assert sum(f"`{name}`" in row for row in rows) == 1, (number, name)
    assert "load" in sections[SECTIONS] and "-O2" in sections[SECTIONS]
    results = json.loads((tmp_path / "results.json").read_text())
    assert set(results["mechanisms"]) == set(one)
    assert set(results["multibody"]) == set(several)
    assert set(results["fmu"]) == {"doughty"} and results["fmu"]["doughty"]["theta_max_diff"] < 1e-9
    swept = results["sweep"]["doughty"]
    assert swept["sets"] == 10_000 and swept["rows"] >= swept["sets"] and swept["met"] is None
    for measured in results["mechanisms"].values():
        assert {"analysis", "kernels", "roots", "accuracy", "branches", "simulate"} <= set(measured)
