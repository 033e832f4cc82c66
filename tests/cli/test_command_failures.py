"""Every failure a user can cause ends in one line on stderr and a non-zero status, never a
traceback (issue 27): an unwritable output, an interrupt, a repeated --set, a model file
that calls sys.exit, a grid too large for memory."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PROG = "python -m codegen"


def run(cwd: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": str(REPO)})


def one_line(done: subprocess.CompletedProcess, status: int = 2) -> str:
    assert done.returncode == status, (done.returncode, done.stderr)
    assert "Traceback" not in done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    return lines[0]


def test_an_output_that_cannot_be_written_is_one_line(tmp_path):
    (tmp_path / "taken.csv").mkdir()          # a folder where the file should go
    line = one_line(run(tmp_path, "simulate", "--theta0", "160", "--to", "0.1",
                        "--out", "taken.csv"))
    assert line.startswith(f"{PROG}: error: ") and "taken.csv" in line


def test_a_parameter_set_twice_is_refused(tmp_path):
    line = one_line(run(tmp_path, "analyze", "--set", "F=1", "--set", "F=2"))
    assert line == f"{PROG}: error: --set F is given twice"


def test_a_model_file_calling_sys_exit_is_named(tmp_path):
    (tmp_path / "quits.py").write_text("import sys\nsys.exit(3)\n")
    line = one_line(run(tmp_path, "analyze", "--model", "quits.py"))
    assert "quits.py: the model file called sys.exit(3)" in line


def test_a_grid_too_large_for_memory_is_one_line(tmp_path):
    line = one_line(run(tmp_path, "sweep", "--vary", "F=0:1:100000000000", "--out", "f.csv"))
    assert "not enough memory" in line
    assert list(tmp_path.iterdir()) == []


def test_an_interrupted_sweep_says_so_and_leaves_nothing(tmp_path):
    process = subprocess.Popen(
        [sys.executable, "-m", "codegen", "sweep", "--vary", "F=0:200:40001", "--vary",
         "k=1000:3000:5", "--out", "s.csv", "--workers", "1"], cwd=tmp_path,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)})
    time.sleep(2.0)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=120)
    if process.returncode == 0:
        pytest.skip("the sweep finished before the interrupt")
    assert process.returncode == 130 and err.strip().splitlines()[-1] == f"{PROG}: interrupted"
    assert "Traceback" not in err and list(tmp_path.iterdir()) == []


def _file_size_limit(size: int):
    """For a child process: files limited to ``size`` bytes, a longer write failing with
    EFBIG (SIGXFSZ, which would kill it, ignored as `ulimit -f` shells often do)."""
    import resource

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
    return limit


@pytest.mark.parametrize("arrow", [True, False])
@pytest.mark.parametrize("size", [4096, 50_000])   # in a write, or in the last flush (50 455 B)
def test_a_sweep_stopped_by_the_file_size_limit_leaves_nothing(tmp_path, arrow, size):
    """Issue 48: the temporary file goes on every error path, the stream's close failing
    again included; the error is one line."""
    prelude = "" if arrow else "from codegen.runtime import sweep; sweep._pyarrow = lambda: None\n"
    code = prelude + "from codegen.cli import main; raise SystemExit(main())"
    done = subprocess.run([sys.executable, "-c", code, "sweep", "--vary", "F=0:200:41",
                           "--out", "s.csv", "--workers", "1"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600,
                          preexec_fn=_file_size_limit(size),
                          env={**os.environ, "PYTHONPATH": str(REPO)})
    assert "File too large" in one_line(done)
    assert list(tmp_path.iterdir()) == []
