"""The command line as the tests run it: ``python -m codegen`` of this interpreter in a
subprocess (figures through matplotlib's Agg backend), and matplotlib required where a test
draws (a skip locally, a failure where CI is set, as .ci/run sets it)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest


def in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def mechvib(*args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    env = dict(os.environ if env is None else env, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)


def need_matplotlib() -> None:
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        if in_ci():
            pytest.fail("matplotlib is needed (CI is set)")
        pytest.skip("matplotlib is not installed")
