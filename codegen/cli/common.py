"""What the verbs of the command line share: the mechanism options, parsing of
values, loading the library, the progress bar.

Building the parser (every verb's ``add``) needs only this module and the standard library:
``mechvib --help`` and ``--version`` load neither numpy nor the runtime nor the compiler.
What a verb computes with is imported inside the functions that run it.
"""
from __future__ import annotations

import argparse
import difflib
import math
import sys
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from ..resources import compiled

if TYPE_CHECKING:
    from tqdm import tqdm

#: The mechanism a command works on when none is named: the paper's example.
DEFAULT_MECHANISM = "doughty"


@cache
def shipped() -> tuple[str, ...]:
    """The mechanisms compiled into this installation (``codegen.runtime.api.shipped``), read
    once per process from the package folder's file names: nothing is imported."""
    return tuple(compiled())


def generator():
    try:  # the generator needs sympy and jinja2; analysis does not
        from ..compiler import generate
    except ImportError as error:
        raise ValueError(f"generate needs the generator's dependencies ({error.name} is "
                         "missing): pip install 'mechvib[generate]'") from None
    if not generate.TEMPLATES.is_dir():
        raise ValueError(f"no templates at {generate.TEMPLATES}: this installation is "
                         "incomplete")
    return generate


def stage(text: str) -> None:
    """A model's derivation and build can take minutes: each stage, one line on stderr."""
    print(text, file=sys.stderr, flush=True)


def checked_mechanism(name: str, known) -> str:
    """name, if it is one of the known mechanisms; else a ValueError that lists them and
    suggests the close ones."""
    if name in known:
        return name
    close = difflib.get_close_matches(name, known, n=3, cutoff=0.6)
    hint = f" (did you mean {' or '.join(close)}?)" if close else ""
    raise ValueError(f"--mechanism {name}: no such mechanism{hint}; this installation has "
                     f"{', '.join(known)} (a model file of your own: --model FILE)")


def assignment(text: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    return name.strip(), value.strip()


#: How an angle parameter (unit rad) is written on the command line: degrees, like every
#: other angle the command line speaks, or with an explicit unit suffix.
ANGLE_HELP = "an angle parameter (unit rad) in degrees, or with its unit: 90deg, 1.5708rad"


def number(name: str, text: str, unit: str | None = None) -> float:
    """A number in ``unit`` (a parameter's SI unit); a ValueError names the parameter
    (reported as one line). Where the unit is rad, the number is in degrees, as every angle
    of the command line is, unless it ends in ``deg`` or ``rad``; the value returned is in
    radians."""
    value, scale = text.strip(), 1.0
    if unit == "rad":
        scale = math.pi / 180.0
        for suffix, factor in (("deg", math.pi / 180.0), ("rad", 1.0)):
            if value.lower().endswith(suffix):
                value, scale = value[: -len(suffix)].strip(), factor
                break
    try:
        number = float(value)
    except ValueError:
        what = " (an angle: degrees, or 90deg, 1.5708rad)" if unit == "rad" else ""
        raise ValueError(f"{name}: {text!r} is not a number{what}") from None
    return number * scale if scale != 1.0 else number


def shown(value: float, unit: str | None) -> str:
    """A parameter's value as ``number`` reads it back: an angle (unit rad) with its unit, in
    degrees (90deg) unless only radians say it in as few digits (1rad, not 57.2958deg, which
    reads back as another angle); anything else as it is."""
    if unit != "rad":
        return f"{value:g}"
    degrees = f"{math.degrees(value):g}"
    if math.radians(float(degrees)) == value or float(f"{value:g}") != value:
        return f"{degrees}deg"
    return f"{value:g}rad"


def params_line(values: dict[str, float], units: dict[str, str]) -> str:
    """NAME=VALUE, ... of a parameter set, each value as --set reads it back."""
    return ", ".join(f"{name}={shown(value, units.get(name))}" for name, value in values.items())


def overrides(pairs: list[tuple[str, str]], units: dict[str, str] | None = None
              ) -> dict[str, float]:
    """Values as numbers in SI units (``units``: each parameter's unit, so that an angle is
    read in degrees; see ``number``); a ValueError names the parameter (reported as one
    line), or one given twice (the second would silently win)."""
    names = [name for name, _ in pairs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"--set {twice[0]} is given twice")
    units = units or {}
    return {name: number(name, value, units.get(name)) for name, value in pairs}


def load_library(args, build: str | None = None):
    """The library --mechanism or --model names; a model is generated and built into
    ``build`` (default: the per-user cache, codegen.user_model), or its build there reused."""
    from ..runtime.api import load

    if getattr(args, "model", None):
        generator()  # the generator's dependencies, or a one-line error naming them
        from ..user_model import library as user_library

        return user_library(args.model, build, progress=stage)
    return load(checked_mechanism(args.mechanism or DEFAULT_MECHANISM, shipped()))


class ProgressBar:
    """The ``progress(done, total)`` callback of a sweep, branches or simulation as a tqdm bar
    on ``stream`` (default stderr), counting ``unit``, only where the stream is a terminal
    (nothing in a pipe or a file); the line is cleared on ``close()`` or leaving a ``with``.
    ``options`` go to tqdm."""

    def __init__(self, stream: TextIO | None = None, unit: str = "sets", **options: Any) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.unit, self.options = unit, options
        self._bar: tqdm | None = None

    def __call__(self, done: int, total: int) -> None:
        if self._bar is None:   # the total is known at the first call
            from tqdm import tqdm

            self._bar = tqdm(total=total, unit=self.unit, file=self.stream, disable=None,
                             leave=False, **self.options)
        self._bar.total = total
        self._bar.update(done - self._bar.n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def mechanism_options(verb: argparse.ArgumentParser, out_help: str | None,
                       model: bool = False, build_help: str | None = None) -> None:
    """--mechanism; --model with --out DIR (its help ``out_help``), or with --build DIR (its
    help ``build_help``: a verb whose --out is a file), or --model alone."""
    which = verb.add_mutually_exclusive_group()
    which.add_argument("--mechanism", metavar="NAME",
                       help=f"a shipped mechanism: {', '.join(shipped())} "
                            f"(default {DEFAULT_MECHANISM})")
    if out_help is None and build_help is None and not model:
        return
    which.add_argument("--model", metavar="FILE",
                       help="a model file of your own (Python, defining build() -> Mechanism)"
                            + ("" if out_help or build_help else
                               "; built into the per-user cache (~/.cache/mechvib), reused "
                               "while the file and mechvib are unchanged"))
    if out_help is not None:
        verb.add_argument("--out", metavar="DIR", help=out_help)
    if build_help is not None:
        verb.add_argument("--build", metavar="DIR", help=build_help)


def set_option(verb: argparse.ArgumentParser,
                help: str = "override a parameter of the example, in SI units (repeatable)"
                ) -> None:
    verb.add_argument("--set", action="append", type=assignment, default=[],
                      metavar="NAME=VALUE", help=f"{help}; {ANGLE_HELP}")


def method_option(verb: argparse.ArgumentParser) -> None:
    verb.add_argument("--method", choices=("auto", "polynomial", "isolate"), default="auto",
                      help="polynomial: the roots of sigma, classified by branch; isolate: the "
                           "zeros of G itself, each proven in an interval, with what double "
                           "precision cannot decide listed as uncertain; auto (default): "
                           "polynomial where G is algebraic, else isolate (with several "
                           "coordinates: always isolate, in boxes)")


def check_outputs(args, formats: tuple[str, ...], what: str) -> None:
    """Before any work: a --plot path we draw to (and matplotlib there to draw it), and an
    --out FILE of one of ``formats`` (``what`` is written as those); ValueError otherwise."""
    from ..presentation import figures

    if args.plot:
        figures.check_path(args.plot)
        try:
            figures.pyplot()
        except figures.PlotUnavailable as error:
            raise ValueError(str(error)) from None
    if args.out and Path(args.out).suffix.lower() not in formats:
        raise ValueError(f"--out {args.out}: {what} is written as {' or '.join(formats)}")


def positive(text: str) -> int:
    """An argparse type: a positive integer."""
    if not text.strip().isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return int(text)


#: How --equilibrium counts, as `mechvib analyze` lists the equilibria (draw's, frf's and
#: fmu's help).
EQUILIBRIUM_NUMBERING = (
    "numbered from 1 as `mechvib analyze` lists them: its # column with several "
    "coordinates; with one, its rows of kind 'equilibrium' in order of angle (extraneous "
    "roots and another assembly mode's not counted)")


def equilibrium_index(number: int, count: int, prefix: str,
                      where: str = "at these parameters") -> int:
    """--equilibrium ``number`` (from 1, as `mechvib analyze` lists them) as an index into the
    analysis' ``count`` equilibria; a ValueError (one line, naming how many there are) for 0,
    a negative number or one past the last."""
    if 1 <= number <= count:
        return number - 1
    if count == 0:
        raise ValueError(f"--equilibrium {number}: {prefix} has no equilibrium {where}")
    raise ValueError(f"--equilibrium {number}: {prefix} has {count} "
                     f"equilibri{'um' if count == 1 else 'a'} {where} (numbered 1 to {count} "
                     "as `mechvib analyze` lists them)")


def verb(verbs, name: str, summary: str, examples: str, prog: str, run
         ) -> argparse.ArgumentParser:
    """The subcommand ``name``, which ``run(args)`` carries out; ``examples`` is its epilog,
    where {prog} stands for the command's name."""
    verb = verbs.add_parser(name, help=summary, description=summary,
                            epilog=examples.format(prog=prog),
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    verb.set_defaults(run=run)
    return verb
