"""Memory safety and warnings: the sanitizer driver and the linters, run as tests.

Locally a missing tool skips its test; in CI (CI=true) a missing tool fails, because
.ci/run installs them.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _need(tool: str) -> None:
    if shutil.which(tool) is None:
        if os.environ.get("CI"):
            pytest.fail(f"{tool} is not installed; .ci/run should have installed it")
        pytest.skip(f"{tool} not installed")


def _make(target: str) -> str:
    result = subprocess.run(["make", "--no-print-directory", target], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result.stdout + result.stderr


def test_sanitizers_report_nothing():
    _need("gcc")
    out = _make("sanitize")
    assert "parameter sets, 0 failed" in out
    # every library's generic driver ran (tests/c/make_driver.py) and found nothing
    libraries = sorted(p.parent.name for p in (ROOT / "generated").glob("*/*_api.json"))
    assert len(libraries) >= 4
    for name in libraries:
        (line,) = [x for x in out.splitlines() if x.startswith(f"{name}: ")]
        assert line.endswith(", 0 failures") and " 0 calls OK" not in line, line
    assert "runtime error" not in out and "ERROR: AddressSanitizer" not in out


def test_gcc_clang_and_cppcheck_are_clean():
    for tool in ("gcc", "clang", "cppcheck"):
        _need(tool)
    out = _make("lint")
    assert "warning" not in out.lower().replace("-w", "").replace("--enable=warning", "")
