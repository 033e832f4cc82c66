"""The command line (``mechvib``, or ``python -m codegen`` in a checkout).

One module per verb (analyze, generate, sources, list in ``listing``, params, sweep,
branches, simulate, frf, draw, fmu), each with ``add(verbs, prog)``, which declares its options, and ``run(args)``,
which carries it out and returns an exit status: 0 on success, 1 when a check fails, 2 for
bad input; ``common`` has what they share. Errors are one line on stderr that names what was
wrong; no traceback reaches the user.

The parser is cheap: the verbs' modules import only the standard library at module level,
and ``run`` imports what it computes with, so ``--help``, ``--version`` and a verb's
``--help`` load neither numpy nor the runtime nor the compiler (tests/cli/test_lazy_imports.py).
"""
from __future__ import annotations

import argparse
import os
import re
import sys
from pathlib import Path

from .. import __version__
from . import (analyze, branches, draw, fmu, frf, generate, listing, params, simulate, sources,
               sweep)

#: The verbs, in the order --help lists them.
VERBS = (analyze, generate, sources, listing, params, sweep, branches, simulate, frf, draw, fmu)

DESCRIPTION = """\
Compile the symbolic mechanics of a planar mechanism, with one coordinate or several, into a
verified C99 library for its vibration analysis, and run that analysis: every equilibrium,
its stability, natural frequencies and damping ratios. Angles are printed and read in
degrees (an angle parameter too, or with its unit: 90deg, 1.5708rad; the Python API works
in radians); everything else is SI."""

EXAMPLES = """\
examples:
  {prog} analyze                              the paper's example (Table 3)
  {prog} analyze --set F=0 --set k=1000       the same with two parameters changed
  {prog} analyze --mechanism four_bar --json  another mechanism, as JSON
  {prog} list                                 the mechanisms this installation has
  {prog} params --mechanism four_bar          its parameters: units, meanings, example values
  {prog} draw -o doughty.svg                  a drawing of the mechanism at an equilibrium
  {prog} sources --copy mylib/                the C sources, to build into a program
  {prog} generate --model my_model.py         a mechanism of your own, generated and built
  {prog} sweep --vary F=0:200:101 --out f.csv one row per equilibrium of 101 sets
  {prog} branches --vary F --from -200 --to 300 --plot f.png
                                              every equilibrium as F varies, folds located
  {prog} simulate --theta0 160 --to 2 --plot theta.png   the motion from 160 deg
  {prog} frf --equilibrium 6 --plot frf.png   the frequency response about an equilibrium
  {prog} fmu --out doughty.fmu                the mechanism as an FMU for simulators"""

#: A negative number as the command line writes one (-1e308, -.5, -inf, -90deg): a value,
#: where argparse's own pattern (-1, -0.5 only) takes -1e308 for an unknown option.
NEGATIVE_NUMBER = re.compile(r"^-(?:(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|inf(?:inity)?|nan)"
                             r"(?:deg|rad)?$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: 'PROG: error: MESSAGE (see PROG --help)', and
    negative numbers in any form read as values."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER   # no option looks like one

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _prog() -> str:
    """The name the user typed: the console command, or `python -m codegen`."""
    name = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else ""
    return "python -m codegen" if name in ("", "__main__.py", "-c") else name


def parser(prog: str | None = None) -> argparse.ArgumentParser:
    prog = prog or _prog()
    top = _Parser(prog=prog, description=DESCRIPTION, epilog=EXAMPLES.format(prog=prog),
                  formatter_class=argparse.RawDescriptionHelpFormatter)
    top.add_argument("--version", action="version", version=f"mechvib {__version__}")
    verbs = top.add_subparsers(dest="verb", metavar="COMMAND", parser_class=_Parser)
    for verb in VERBS:
        verb.add(verbs, prog)
    return top


def foreign_codegen() -> str | None:
    """The unrelated PyPI distribution `codegen`, when installed beside us: it owns the same
    import package, so whichever was installed last has overwritten files of the other."""
    from importlib import metadata

    try:
        other = metadata.distribution("codegen")
    except metadata.PackageNotFoundError:
        return None
    return f"{other.metadata['Name']} {other.version}"


def main(argv: list[str] | None = None) -> int:
    top = parser()
    args = top.parse_args(argv)  # --help and --version end here, having imported no more
    other = foreign_codegen()  # (importlib.metadata reads every installed distribution)
    if other:
        print(f"{top.prog}: warning: the unrelated distribution {other} is installed in this "
              "environment and shares the import name 'codegen'; use a separate virtual "
              "environment for mechvib", file=sys.stderr)
    from .. import files
    from ..presentation.figures import PlotUnavailable

    files.exit_on_signals()  # SIGTERM, SIGHUP: what is being written is removed, as on error
    if args.verb is None:
        top.print_help(sys.stderr)
        return 2
    try:
        status = args.run(args)
        sys.stdout.flush()
        return status
    except (ValueError, PlotUnavailable) as error:  # bad input (LibraryError, ModelError
        # included), or a figure without matplotlib: one line
        print(f"{top.prog}: error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader left (`| head`): stop quietly, as Unix tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so the interpreter's final flush succeeds
        return 141  # 128 + SIGPIPE, what a shell reports for a tool killed by the signal
    except OSError as error:  # a folder that cannot be written, a full disk: one line
        where = f"{error.filename}: " if error.filename else ""
        print(f"{top.prog}: error: {where}{error.strerror or error}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"{top.prog}: error: not enough memory for this run (fewer sets, or --sample "
              "with smaller pieces)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # what was being written has been removed
        print(f"{top.prog}: interrupted", file=sys.stderr)
        return 130
