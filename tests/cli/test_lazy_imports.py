"""The command line is lazy: ``--help``, ``--version`` and each verb's ``--help`` load neither
numpy nor SymPy, cffi, Jinja2 or tqdm, nor anything of codegen's runtime or compiler; a verb
imports what it computes with only when it runs. What is checked is the modules loaded,
not a time.

The parser needs a few numbers that the runtime defines (the defaults of --points and
--chunk, the FMI versions) and the list of mechanisms; the command line keeps its own copies
of the numbers and reads the list from the package folder's file names, and this holds
them equal to the runtime's.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

#: Top-level packages the parser must not load.
HEAVY = ("numpy", "sympy", "cffi", "jinja2", "tqdm", "mpmath", "matplotlib", "scipy")
#: Modules of codegen the parser must not load (a prefix matches the package and below).
HEAVY_OURS = ("codegen.runtime", "codegen.compiler", "codegen.model", "codegen.api",
              "codegen.fmu", "codegen.user_model", "codegen.files", "codegen.errors",
              "codegen.cli.report", "codegen.presentation")

VERBS = ("analyze", "generate", "sources", "list", "params", "sweep", "branches", "simulate",
         "frf", "draw", "fmu")


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return env


def _heavy(modules) -> list[str]:
    return sorted(m for m in modules if m.split(".")[0] in HEAVY
                  or any(m == p or m.startswith(p + ".") for p in HEAVY_OURS))


def _imported(*args: str) -> tuple[subprocess.CompletedProcess, list[str]]:
    """``python -X importtime -m codegen ARGS``: the run and every module it imported."""
    run = subprocess.run([sys.executable, "-X", "importtime", "-m", "codegen", *args],
                         cwd=REPO, env=_env(), capture_output=True, text=True, timeout=60)
    modules = [line.rpartition("|")[2].strip() for line in run.stderr.splitlines()
               if line.startswith("import time:") and "|" in line]
    return run, [m for m in modules if m != "imported package"]   # the header's last column


def test_version_and_help_import_nothing_heavy():
    for args in (["--version"], ["--help"]):
        run, modules = _imported(*args)
        assert run.returncode == 0, run.stderr[-2000:]
        assert "codegen.cli" in modules and "argparse" in modules, modules  # read right
        assert not _heavy(modules), (args, _heavy(modules))
    version, _ = _imported("--version")
    assert version.stdout.startswith("mechvib ")


def test_every_verbs_help_imports_nothing_heavy():
    """Each verb's --help, in one process per verb (its parser built, its help printed)."""
    code = ("import json, sys, contextlib, io\n"
            "from codegen.cli import main\n"
            "out = io.StringIO()\n"
            "try:\n"
            "    with contextlib.redirect_stdout(out):\n"
            "        main([sys.argv[1], '--help'])\n"
            "except SystemExit as stop:\n"
            "    status = stop.code\n"
            "print(json.dumps([status, out.getvalue(), sorted(sys.modules)]))")
    for verb in VERBS:
        run = subprocess.run([sys.executable, "-c", code, verb], cwd=REPO, env=_env(),
                             capture_output=True, text=True, timeout=60)
        assert run.returncode == 0, run.stderr[-2000:]
        status, text, modules = json.loads(run.stdout)
        assert status == 0 and text.startswith("usage: ") and f" {verb} " in text, (verb, text)
        assert not _heavy(modules), (verb, _heavy(modules))


def test_the_parsers_copies_are_the_runtimes():
    from codegen import fmu
    from codegen.cli import branches as cli_branches
    from codegen.cli import common
    from codegen.cli import fmu as cli_fmu
    from codegen.cli import frf as cli_frf
    from codegen.cli import sweep as cli_sweep
    from codegen.runtime import api, branches, response, sweep

    assert cli_branches.DEFAULT_POINTS == branches.DEFAULT_POINTS
    assert cli_sweep.CHUNK == sweep.CHUNK
    assert cli_frf.POINTS == response.POINTS
    assert cli_fmu.VERSIONS == fmu.VERSIONS
    assert list(common.shipped()) == api.shipped() and "doughty" in api.shipped()
    assert common.DEFAULT_MECHANISM in api.shipped()


def test_the_defaults_reach_the_parser():
    from codegen.cli import parser

    top = parser("mechvib")
    assert top.parse_args(["branches", "--vary", "F", "--from", "0", "--to", "1"]).points == 1001
    assert top.parse_args(["frf"]).points == 801
    assert top.parse_args(["sweep", "--vary", "F=0:1:2", "--out", "x.csv"]).chunk == 16384
    assert top.parse_args(["fmu", "--out", "x.fmu"]).fmi == "2.0"
