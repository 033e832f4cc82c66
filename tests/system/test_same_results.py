"""`make same-results` (benchmarks/same_results.py): two revisions' C libraries give the same
bytes, or the differences are reported -- on a few sets and builds, so that it runs fast.

Both ways are checked: HEAD's generated/ against an identical copy is reported identical
(exit 0), and a copy whose runtime computes one quantity differently (the damping ratio, by
a relative 5e-8) is reported differing (exit 1), with the field that differs."""
from __future__ import annotations

import io
import re
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "same_results.py"
#: The damping ratio's formula in the runtime, and the same perturbed.
ZETA = "b / (CODEGEN_R(2.0) * m * w)"
PERTURBED = "b / (CODEGEN_R(2.0000001) * m * w)"


@pytest.fixture(autouse=True)
def _need_gcc():
    if shutil.which("gcc") is None:
        pytest.skip("gcc is not installed")


def _run(*args: str, cache: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), "--cc", "gcc", "--jobs", "2",
                           "--cache", str(cache), *args],
                          capture_output=True, text=True, timeout=300)


def _rows(out: str) -> dict[tuple[str, str], tuple[int, int, int]]:
    """(mechanism, build) -> (sets, identical, differing), from the summary table."""
    rows = {}
    for m in re.finditer(r"^(\w+)\s+(double|float) (inline|programs)\s+(\d+)\s+(\d+)\s+(\d+)"
                         r"\s+[\d.]+\s+[12]$", out, re.M):
        rows[m[1], f"{m[2]} {m[3]}"] = (int(m[4]), int(m[5]), int(m[6]))
    return rows


def test_head_against_itself_is_identical_in_every_build(tmp_path):
    if shutil.which("git") is None or subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True).returncode:
        pytest.skip("not a git checkout")
    # The tree compared is HEAD's own generated/, so that uncommitted work does not count.
    tar = subprocess.run(["git", "-C", str(ROOT), "archive", "HEAD", "generated"],
                         capture_output=True, check=True).stdout
    with tarfile.open(fileobj=io.BytesIO(tar)) as archive:
        if hasattr(tarfile, "data_filter"):
            archive.extractall(tmp_path / "head", filter="data")
        else:
            archive.extractall(tmp_path / "head")
    done = _run("--base", "HEAD", "--tree", str(tmp_path / "head" / "generated"),
                "--sets", "20", "--mechanisms", "doughty", "torsion_pendulum",
                "--run-both", cache=tmp_path / "objects")
    assert done.returncode == 0, done.stdout + done.stderr
    rows = _rows(done.stdout)
    assert sorted(rows) == sorted((m, b) for m in ("doughty", "torsion_pendulum")
                                  for b in ("double inline", "double programs",
                                            "float inline", "float programs"))
    assert set(rows.values()) == {(20, 20, 0)}
    assert "0 differ, 0 only in BASE, 0 only in the tree" in done.stdout
    compared = re.search(r"^  doughty: compared (.*)$", done.stdout, re.M)
    assert compared, done.stdout
    for item in ("analyze", "isolate", "enclosure", "simulate", "kernel:sigma",
                 "kernel:equilibrium_state"):
        assert item in compared[1].split(", ")
    assert "every result identical, bit for bit" in done.stdout


def test_a_perturbed_runtime_is_reported_with_its_fields(tmp_path):
    shutil.copytree(ROOT / "generated", tmp_path / "base")
    shutil.copytree(ROOT / "generated", tmp_path / "tree")
    analysis = tmp_path / "tree" / "runtime" / "codegen_analysis.c"
    text = analysis.read_text()
    assert ZETA in text, "the damping ratio's formula moved: update ZETA to perturb it"
    analysis.write_text(text.replace(ZETA, PERTURBED))
    done = _run("--base-dir", str(tmp_path / "base"), "--tree", str(tmp_path / "tree"),
                "--sets", "10", "--mechanisms", "torsion_pendulum",
                "--builds", "double inline", "double programs", cache=tmp_path / "objects")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "differs: runtime/codegen_analysis.c" in done.stdout
    rows = _rows(done.stdout)
    # Every set of the torsion pendulum has an equilibrium with K > 0: its zeta moves.
    assert rows[("torsion_pendulum", "double inline")] == (10, 0, 10)
    assert rows[("torsion_pendulum", "double programs")] == (10, 0, 10)
    assert "(analyze in 10, isolate in 10)" in done.stdout
    assert re.search(r"result\.roots\[0\]\.zeta\[[01]\]: \S+ -> \S+", done.stdout)
    assert "set 0: l = 1.0, m = 1.0" in done.stdout  # the example first, its parameters shown
    assert "results DIFFER" in done.stdout
