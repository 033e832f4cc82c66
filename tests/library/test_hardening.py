"""Memory safety and warnings: the sanitizer driver and the linters, run as tests.

Locally a missing tool skips its test; in CI (the environment variable CI set, as .ci/run
does) a missing tool fails, because .ci/run installs them. Either way the message names the
missing tools and the command that installs them.
"""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _make(target: str) -> str:
    result = subprocess.run(["make", "--no-print-directory", target], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result.stdout + result.stderr


@pytest.mark.slow   # ~75 s: make test-all (CI) runs it
def test_sanitizers_report_nothing(need_tools):
    need_tools("gcc")
    out = _make("sanitize")
    assert "parameter sets, 0 failed" in out
    # every library's generic driver ran (tests/support/c/make_driver.py) and found nothing
    libraries = sorted(p.parent.name for p in (ROOT / "generated").glob("*/*_api.json"))
    assert len(libraries) >= 4
    for name in libraries:
        (line,) = [x for x in out.splitlines() if x.startswith(f"{name}: ")]
        assert line.endswith(", 0 failures") and " 0 calls OK" not in line, line
    assert "runtime error" not in out and "ERROR: AddressSanitizer" not in out


@pytest.mark.slow   # ~3 min: make test-all (CI) runs it
def test_gcc_clang_and_cppcheck_are_clean(need_tools):
    need_tools("gcc", "clang", "cppcheck")
    out = _make("lint")
    assert "warning" not in out.lower().replace("-w", "").replace("--enable=warning", "")


@pytest.mark.parametrize("ci", [None, "1", "true", "0", "false"])
def test_a_missing_tool_fails_in_ci_and_skips_otherwise(monkeypatch, ci, need_tools):
    """The message names the missing tools and their install command; CI=1 (what .ci/run
    exports) fails, no CI (or CI=0/false) skips."""
    present = {"gcc"}
    monkeypatch.setattr(shutil, "which", lambda tool: f"/usr/bin/{tool}" if tool in present
                        else None)
    if ci is None:
        monkeypatch.delenv("CI", raising=False)
    else:
        monkeypatch.setenv("CI", ci)
    expected = (pytest.fail.Exception if ci in ("1", "true") else pytest.skip.Exception)
    with pytest.raises(expected) as raised:
        need_tools("gcc", "clang", "cppcheck")
    message = str(raised.value)
    assert "clang, cppcheck are not installed" in message
    assert "`apt-get install clang cppcheck`" in message
    need_tools("gcc")  # present: neither fails nor skips
    with pytest.raises(expected) as raised:  # a tool whose package has another name
        need_tools("arm-none-eabi-gcc", packages={"arm-none-eabi-gcc": "gcc-arm-none-eabi"})
    assert "`apt-get install gcc-arm-none-eabi`" in str(raised.value)


def test_ci_script_sets_ci():
    assert "export CI=1" in (ROOT / ".ci" / "run").read_text()
