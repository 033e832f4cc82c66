"""Layer 7: the command line (``mechvib``, or ``python -m codegen`` in a checkout).

Each verb is one function taking the parsed arguments and returning an exit status: 0 on
success, 1 when a check fails, 2 for bad input. Errors are one line on stderr that names what
was wrong; no traceback reaches the user.
"""
from __future__ import annotations

import argparse
import difflib
import math
import os
import shutil
import sys
import time
from pathlib import Path
from typing import Any, TextIO

from tqdm import tqdm

from . import __version__, files
from .api import shipped
from .figures import PlotUnavailable

#: The mechanism a command works on when none is named: the paper's example.
DEFAULT_MECHANISM = "doughty"

DESCRIPTION = """\
Compile the symbolic mechanics of a planar mechanism into a verified C99 library for its
vibration analysis, and run that analysis: every equilibrium of one degree of freedom, its
stability, natural frequency and damping ratio. Angles are printed in degrees (the Python
API works in radians); everything else is SI."""

EXAMPLES = {
    None: """\
examples:
  {prog} analyze                              the paper's example (Table 3)
  {prog} analyze --set F=0 --set k=1000       the same with two parameters changed
  {prog} analyze --mechanism four_bar --json  another mechanism, as JSON
  {prog} list                                 the mechanisms this installation has
  {prog} sources --copy mylib/                the C sources, to build into a program
  {prog} generate --model my_model.py         a mechanism of your own, generated and built
  {prog} sweep --vary F=0:200:101 --out f.csv one row per equilibrium of 101 sets
  {prog} branches --vary F --from -200 --to 300 --plot f.png
                                              every equilibrium as F varies, folds located
  {prog} simulate --theta0 160 --to 2 --plot theta.png   the motion from 160 deg""",
    "analyze": """\
examples:
  {prog} analyze
  {prog} analyze --set F=0 --set b=0 --wide
  {prog} analyze --mechanism torsion_pendulum --json
  {prog} analyze --method isolate --sigma
  {prog} analyze --model my_model.py --out build/mine""",
    "generate": """\
examples:
  {prog} generate                             regenerate generated/ (in a checkout)
  {prog} generate --check                     exit 1 if generated/ is stale
  {prog} generate --mechanism slider_crank --out /tmp/gen
  {prog} generate --model my_model.py --out build/mine""",
    "sources": """\
examples:
  {prog} sources                              where the C files of the paper's example are
  {prog} sources --mechanism four_bar --copy vendor/four_bar
  cc -std=c99 -Ivendor/four_bar app.c vendor/four_bar/*.c -lm""",
    "list": """\
examples:
  {prog} list""",
    "branches": """\
examples:
  {prog} branches --vary F --from 0 --to 200
  {prog} branches --vary F --from -200 --to 300 --out f.csv --plot docs/branches_doughty_F.png
  {prog} branches --mechanism torsion_pendulum --vary k_t --from 0 --to 50 --out k.json
  {prog} branches --mechanism slider_crank --vary T --from -20 --to 20 --points 4001 --set b=0

The parameter runs over --points evenly spaced values from --from to --to (both included);
the others are the example's, or --set's. The equilibria of neighbouring values are joined
into branches, and every fold (two equilibria meet and vanish), pitchfork, branch end and
change of stability is located by bisection on the parameter. --out writes a row per point
of every branch (.csv, .json or .parquet), --plot the figure (.png or .svg; pip install
'mechvib[plot]'). Angles in degrees, the parameter in its unit, the rest SI.""",
    "sweep": """\
examples:
  {prog} sweep --vary F=0:200:101 --vary k=1000:3000:5 --out grid.csv
  {prog} sweep --sample 1000000 --vary F=0:200 --vary k=1000:3000 --seed 1 --out s.parquet
  {prog} sweep --vary F=0:200:201 --set b=0 --all-roots --workers 2 --out roots.csv
  {prog} sweep --sample 10000000 --vary F=0:200 --scheduler tcp://HOST:8786 --out big.parquet

--vary NAME=START:STOP:COUNT makes a grid axis of COUNT values from START to STOP (both
included); with --sample N, --vary NAME=LO:HI draws each set's NAME uniformly in [LO, HI).
The other parameters are the example's, or --set's. The file has one row per equilibrium
(per root with --all-roots), with the set's index, parameters and status; a set that fails
or has none has one row with an empty theta. Angles in radians there, the rest SI.""",
    "simulate": """\
examples:
  {prog} simulate --theta0 160 --to 2                      CSV on stdout
  {prog} simulate --theta0 160 --to 2 --linearised --plot theta.png --out theta.json
  {prog} simulate --mechanism four_bar --theta0 -30 --thetadot0 100 --to 5 --out m.csv
  {prog} simulate --set b=0 --theta0 170 --to 10 --points 5001 --rtol 1e-11 --plot m.svg

Integrates the reduced equation of motion thetaddot = f(theta, thetadot) in C (adaptive
Dormand-Prince 5(4)) from theta0 [deg] and thetadot0 [deg/s] at t = 0 to --to [s], and
writes theta and thetadot at --points evenly spaced times: CSV on stdout, or --out FILE.csv
or FILE.json (degrees and seconds), and with --plot a figure of both. --linearised adds the
response of the linearisation about the stable equilibrium nearest theta0 (its M, B, K
from the analysis) from the same state. rtol and atol bound each step's error (atol in rad
and rad/s).""",
}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: 'PROG: error: MESSAGE (see PROG --help)'."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _prog() -> str:
    """The name the user typed: the console command, or `python -m codegen`."""
    name = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else ""
    return "python -m codegen" if name in ("", "__main__.py", "-c") else name


def _generator():
    try:  # the generator needs sympy and jinja2; analysis does not
        from . import generate
    except ImportError as error:
        raise ValueError(f"generate needs the generator's dependencies ({error.name} is "
                         "missing): pip install 'mechvib[generate]'") from None
    if not generate.TEMPLATES.is_dir():
        raise ValueError(f"no templates at {generate.TEMPLATES}: this installation is "
                         "incomplete")
    return generate


def _stage(stage: str) -> None:
    """A model's derivation and build can take minutes: each stage, one line on stderr."""
    print(stage, file=sys.stderr, flush=True)


def _checked_mechanism(name: str, known) -> str:
    """name, if it is one of the known mechanisms; else a ValueError that lists them and
    suggests the close ones."""
    if name in known:
        return name
    close = difflib.get_close_matches(name, known, n=3, cutoff=0.6)
    hint = f" (did you mean {' or '.join(close)}?)" if close else ""
    raise ValueError(f"--mechanism {name}: no such mechanism{hint}; this installation has "
                     f"{', '.join(known)} (a model file of your own: --model FILE)")


def _generate(args) -> int:
    generate = _generator()
    start = time.perf_counter()
    if args.model:
        from .user_model import library as user_library

        out = Path(args.out or "build/codegen")
        library = user_library(args.model, out, progress=_stage, rebuild=True)
        print(f"wrote and built {library.PREFIX} ({library.TITLE}) in {out} "
              f"in {time.perf_counter() - start:.1f} s")
        return 0
    out = Path(args.out) if args.out else generate.default_output()
    names = [_checked_mechanism(args.mechanism, generate.SHIPPED)] if args.mechanism else list(
        generate.SHIPPED)
    cache = None if args.no_cache else generate.default_cache()
    if args.check:
        diff = generate.stale(out, names, cache=cache)
        if diff:
            sys.stdout.write(diff)
            print(f"{out} is stale: regenerate it (`make generate` in a checkout) and commit "
                  "the result", file=sys.stderr)
            return 1
        print(f"{out} is up to date ({time.perf_counter() - start:.1f} s)")
        return 0
    files = generate.write(out, names, cache=cache)
    changed = ": " + ", ".join(files) if files else " (every file was already up to date)"
    print(f"wrote {len(files)} files to {out} in {time.perf_counter() - start:.1f} s{changed}")
    return 0


def _assignment(text: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    return name.strip(), value.strip()


def _number(name: str, text: str) -> float:
    """A number; a ValueError names the parameter (reported as one line)."""
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"{name}: {text!r} is not a number") from None


def _overrides(pairs: list[tuple[str, str]]) -> dict[str, float]:
    """Values as numbers; a ValueError names the parameter (reported as one line), or one
    given twice (the second would silently win)."""
    names = [name for name, _ in pairs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"--set {twice[0]} is given twice")
    return {name: _number(name, value) for name, value in pairs}


def _library(args, build: str | None = None):
    """The library --mechanism or --model names; a model is generated and built into
    ``build`` (default: the per-user cache, codegen.user_model), or its build there reused."""
    from .api import load

    if getattr(args, "model", None):
        _generator()  # the generator's dependencies, or a one-line error naming them
        from .user_model import library as user_library

        return user_library(args.model, build, progress=_stage)
    return load(_checked_mechanism(args.mechanism or DEFAULT_MECHANISM, shipped()))


def _analyze(args) -> int:
    import json

    from .analysis import analyze
    from .report import paragraph, table

    library = _library(args, args.out)
    params = library.example_params(**_overrides(args.set))
    result = analyze(params, args.method)
    if args.json:
        print(json.dumps(result.to_dict(), indent=1))
    else:
        values = ", ".join(f"{k}={v:g}" for k, v in vars(params).items())
        print(paragraph(f"Vibration analysis of {library.TITLE}: {values}") + "\n")
        print(table(result, wide=args.wide, sigma=args.sigma))
    return 0


def _sources(args) -> int:
    """Where the C files of a shipped library are, or a copy of them in a folder."""
    from .resources import generated

    name = _checked_mechanism(args.mechanism or DEFAULT_MECHANISM, shipped())
    root = generated()
    folders = [root / name, root / "runtime"]
    if not folders[0].is_dir():
        have = ", ".join(sorted(p.name for p in root.iterdir() if p.is_dir() and
                                p.name != "runtime")) if root.is_dir() else "none"
        raise ValueError(f"{name}: no C sources in this installation (it has {have})")
    files = sorted(f for folder in folders for f in folder.iterdir()
                   if f.suffix in (".c", ".h"))
    if not args.copy:
        for folder in folders:
            print(folder)
        return 0
    out = Path(args.copy)
    out.mkdir(parents=True, exist_ok=True)
    for f in files:
        shutil.copyfile(f, out / f.name)
    print(f"copied {len(files)} files to {out}: " + ", ".join(f.name for f in files))
    return 0


def _list(args) -> int:
    from .api import load

    for name in shipped():
        library = load(name)
        route = "polynomial" if library.has_polynomial else "isolation"
        print(f"{name:<18} {library.TITLE} ({len(library.PARAMETER_NAMES)} parameters, "
              f"{route})")
    return 0


def _grid_axis(name: str, spec: str):
    """START:STOP:COUNT as COUNT values from START to STOP, both included."""
    import numpy as np

    parts = spec.split(":")
    if len(parts) != 3:
        raise ValueError(f"--vary {name}={spec}: a grid axis is NAME=START:STOP:COUNT (NAME=LO:HI "
                         "is for --sample)")
    count = parts[2].strip()
    if not count.isdigit() or int(count) < 1:
        raise ValueError(f"--vary {name}={spec}: COUNT must be a positive integer")
    return np.linspace(_number(name, parts[0]), _number(name, parts[1]), int(count))


def _sample_range(name: str, spec: str) -> tuple[float, float]:
    """LO:HI as a pair of numbers."""
    parts = spec.split(":")
    if len(parts) != 2:
        raise ValueError(f"--vary {name}={spec}: with --sample, a range is NAME=LO:HI")
    return _number(name, parts[0]), _number(name, parts[1])


def _sweep_sets(library, args):
    """The parameter sets --vary, --sample, --seed and --set describe (a params_array)."""
    from . import sweep

    base, names = _overrides(args.set), [name for name, _ in args.vary]
    for name in names:
        if names.count(name) > 1 or name in base:
            raise ValueError(f"{name}: given more than once (--vary, --set)")
    if args.sample is None:
        if args.seed is not None:
            raise ValueError("--seed is for --sample")
        return sweep.grid(library, {n: _grid_axis(n, spec) for n, spec in args.vary}, base)
    ranges = {name: _sample_range(name, spec) for name, spec in args.vary}
    return sweep.sample(library, args.sample, ranges, base, args.seed)


#: Seconds to wait for a scheduler to answer, and then for its first worker (the
#: environment's MECHVIB_WORKER_WAIT, if set).
WORKER_WAIT = 30


def _dask_client(address: str | None):
    """A context holding a dask.distributed Client of the scheduler at address (None: no
    address, no client)."""
    from contextlib import nullcontext

    if address is None:
        return nullcontext(None)
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("--scheduler needs dask.distributed: pip install 'mechvib[dask]'"
                         ) from None
    wait = float(os.environ.get("MECHVIB_WORKER_WAIT", WORKER_WAIT))
    try:
        client = Client(address, timeout=wait)
    except OSError as error:   # a refused or timed-out connection
        raise ValueError(f"--scheduler {address}: {error}") from None
    try:
        client.wait_for_workers(1, timeout=wait)
    except TimeoutError:  # a scheduler no worker has joined: tasks would wait forever
        client.close()
        raise ValueError(f"--scheduler {address}: no worker joined the scheduler within "
                         f"{wait:g} s") from None
    return client


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


def _sweep(args) -> int:
    """Analyse every set, writing the rows as they come; a summary on stdout."""
    from . import sweep

    library = _library(args)
    sets = _sweep_sets(library, args)
    roots = "all" if args.all_roots else "equilibria"
    start, tally = time.perf_counter(), _Tally(library)
    with _dask_client(args.scheduler) as client, sweep.Writer(args.out) as writer, \
            ProgressBar() as bar:
        for piece in sweep.stream(library, sets, method=args.method, workers=args.workers,
                                  chunk=args.chunk, client=client, progress=bar, roots=roots):
            writer.write(piece)
            tally.add(piece)
    where = (f"on the Dask cluster at {args.scheduler}" if args.scheduler else
             f"on {args.workers or os.cpu_count() or 1} threads")
    print(tally.summary(len(sets), time.perf_counter() - start, where, args.out))
    return 0


def _branches(args) -> int:
    """Follow every equilibrium as one parameter varies; a summary on stdout, the table
    and the figure to files."""
    from . import branch_figure, figures, sweep
    from .branches import branches, check_table_path
    from .report import branch_summary

    if args.plot:   # before the work: a bad path or no matplotlib fails at once
        figures.check_path(args.plot)
        figures.pyplot()
    if args.out:
        check_table_path(args.out)
    base = _overrides(args.set)
    if args.vary in base:
        raise ValueError(f"{args.vary}: given more than once (--vary, --set)")
    library = _library(args)
    with ProgressBar() as bar:
        result = branches(library, args.vary, args.start, args.stop, args.points, base=base,
                          method=args.method, workers=args.workers, progress=bar)
    print(branch_summary(result))
    if args.out:
        rows = result.write(args.out)
        print(f"Wrote {rows:,} rows to {args.out}.")
    if args.plot:
        branch_figure.plot(result, args.plot)
        print(f"Drew the figure to {args.plot}.")
    return 0


class _Tally:
    """What the summary of a sweep counts, piece by piece."""

    def __init__(self, library) -> None:
        from .analysis import KINDS, STABILITY

        self.library, self.rows, self.equilibria, self.stable = library, 0, 0, 0
        self.failed: dict[int, int] = {}
        self._equilibrium, self._stable = KINDS.index("equilibrium"), STABILITY.index("stable")

    def add(self, piece) -> None:
        import numpy as np

        self.rows += len(piece)
        genuine = piece["kind"] == self._equilibrium
        self.equilibria += int(np.count_nonzero(genuine))
        self.stable += int(np.count_nonzero(genuine & (piece["stability"] == self._stable)))
        for status, count in zip(*np.unique(piece["status"][piece["status"] != 0],
                                            return_counts=True)):
            self.failed[int(status)] = self.failed.get(int(status), 0) + int(count)

    def summary(self, sets: int, seconds: float, where: str, out: str) -> str:
        from .report import paragraph

        names = {v: k for k, v in self.library.STATUS.items()}
        failed = sum(self.failed.values())
        why = ", ".join(f"{names.get(s, s)}: {n:,}" for s, n in sorted(self.failed.items()))
        return paragraph(
            f"Swept {sets:,} parameter sets of {self.library.TITLE} in {seconds:.1f} s "
            f"{where} ({sets / max(seconds, 1e-9):,.0f} sets/s). {failed:,} sets failed"
            + (f" ({why})" if failed else "") + f"; {self.equilibria:,} equilibria found, "
            f"{self.stable:,} of them stable. Wrote {self.rows:,} rows to {out}.")


def _simulate(args) -> int:
    """The motion from an initial state: CSV on stdout, or files and a summary."""
    import numpy as np

    from . import figures, simulation, sweep

    if args.plot:
        figures.check_path(args.plot)
        try:
            figures.pyplot()
        except figures.PlotUnavailable as error:
            raise ValueError(str(error)) from None
    if args.out and Path(args.out).suffix.lower() not in simulation.FORMATS:
        raise ValueError(f"--out {args.out}: the trajectory is written as "
                         f"{' or '.join(simulation.FORMATS)}")
    if not 0.0 < args.to < math.inf:
        raise ValueError(f"--to: the end time must be positive and finite, not {args.to!r}")
    if args.points < 2:
        raise ValueError("--points: at least 2 (the start and the end)")
    params = _library(args).example_params(**_overrides(args.set))
    start = time.perf_counter()
    try:
        with ProgressBar(unit="points") as bar:
            trajectory = simulation.simulate(
                params, math.radians(args.theta0), math.radians(args.thetadot0),
                np.linspace(0.0, args.to, args.points), rtol=args.rtol, atol=args.atol,
                max_steps=args.max_steps, progress=bar)
    except simulation.IntegrationError as error:
        # what was computed before the failure is still written, and the failure said
        written, _ = _write_trajectory(args, error.trajectory)
        where = f"; the {len(error.trajectory.t):,} points before it" if written else ""
        raise ValueError(f"{error}{where}{' written to ' if written else ''}"
                         f"{' and '.join(written)}") from None
    seconds = time.perf_counter() - start
    written, linear = _write_trajectory(args, trajectory)
    if written:
        print(_simulation_summary(trajectory, linear, seconds, written))
    return 0


def _write_trajectory(args, trajectory):
    """CSV on stdout (no file to name), or the --out and --plot files: the files' names,
    and the linearised response drawn beside (None unless --linearised)."""
    from . import simulation

    linear = simulation.linearised(trajectory) if args.linearised else None
    if not (args.out or args.plot):
        simulation.write_csv(sys.stdout, trajectory, linear)
        return [], linear
    written = [str(simulation.write(trajectory, args.out, linear))] if args.out else []
    written += [str(simulation.plot(trajectory, args.plot, linear))] if args.plot else []
    return written, linear


def _simulation_summary(trajectory, linear, seconds: float, written: list[str]) -> str:
    from .report import paragraph

    about = ""
    if linear is not None:
        e = linear.equilibrium
        about = (f" Linearised about theta_E = {math.degrees(linear.theta_e):.4f} deg "
                 f"({e.stability}, {e.damping}, zeta {e.zeta.real:.4g}).")
    return paragraph(
        f"Simulated {trajectory.t[-1]:g} s of {trajectory.library.TITLE} from theta0 = "
        f"{trajectory.theta_deg[0]:g} deg, thetadot0 = {trajectory.theta_d_deg[0]:g} deg/s: "
        f"{len(trajectory.t):,} points, {trajectory.steps:,} steps ({trajectory.rejected:,} "
        f"rejected), {trajectory.evaluations:,} evaluations of thetaddot, in "
        f"{seconds * 1e3:.1f} ms (rtol {trajectory.rtol:g}, atol {trajectory.atol:g}).{about} "
        f"Wrote {' and '.join(written)}.")


def _mechanism_options(verb: argparse.ArgumentParser, out_help: str | None,
                       model: bool = False) -> None:
    """--mechanism; --model with --out DIR (its help ``out_help``), or --model alone."""
    which = verb.add_mutually_exclusive_group()
    which.add_argument("--mechanism", metavar="NAME",
                       help=f"a shipped mechanism: {', '.join(shipped())} "
                            f"(default {DEFAULT_MECHANISM})")
    if out_help is None and not model:
        return
    which.add_argument("--model", metavar="FILE",
                       help="a model file of your own (Python, defining build() -> Mechanism)"
                            + ("" if out_help else "; built into the per-user cache "
                                                    "(~/.cache/mechvib), reused while the "
                                                    "file and mechvib are unchanged"))
    if out_help is not None:
        verb.add_argument("--out", metavar="DIR", help=out_help)


def _set_option(verb: argparse.ArgumentParser,
                help: str = "override a parameter of the example, in SI units (repeatable)"
                ) -> None:
    verb.add_argument("--set", action="append", type=_assignment, default=[],
                      metavar="NAME=VALUE", help=help)


def _method_option(verb: argparse.ArgumentParser) -> None:
    verb.add_argument("--method", choices=("auto", "polynomial", "isolate"), default="auto",
                      help="polynomial: the roots of sigma, classified by branch; isolate: the "
                           "zeros of G itself, each proven in an interval, with what double "
                           "precision cannot decide listed as uncertain; auto (default): "
                           "polynomial where G is algebraic, else isolate")


def _positive(text: str) -> int:
    """An argparse type: a positive integer."""
    if not text.strip().isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return int(text)


def _verb(verbs, name: str, summary: str, prog: str, run) -> argparse.ArgumentParser:
    verb = verbs.add_parser(name, help=summary, description=summary,
                            epilog=EXAMPLES[name].format(prog=prog),
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    verb.set_defaults(run=run)
    return verb


def parser(prog: str | None = None) -> argparse.ArgumentParser:
    prog = prog or _prog()
    top = _Parser(prog=prog, description=DESCRIPTION, epilog=EXAMPLES[None].format(prog=prog),
                  formatter_class=argparse.RawDescriptionHelpFormatter)
    top.add_argument("--version", action="version", version=f"mechvib {__version__}")
    verbs = top.add_subparsers(dest="verb", metavar="COMMAND", parser_class=_Parser)

    ana = _verb(verbs, "analyze", "every equilibrium and its vibration (the paper's Table 3)",
                prog, _analyze)
    _mechanism_options(ana, "with --model: where its library is generated and built "
                            "(default: the per-user cache ~/.cache/mechvib; a "
                            "build there or in DIR is reused while the file is unchanged)")
    _set_option(ana)
    ana.add_argument("--json", action="store_true",
                     help="print one JSON object (angles in degrees) instead of the table")
    ana.add_argument("--wide", action="store_true",
                     help="every column: M_EQ, B_EQ and the eigenvalues too")
    ana.add_argument("--sigma", action="store_true",
                     help="also print the polynomial's coefficients sigma_i")
    _method_option(ana)

    gen = _verb(verbs, "generate", "derive the mechanics and write the C library", prog,
                _generate)
    _mechanism_options(gen, "output folder (default: the checkout's generated/, or ./generated "
                            "when installed; build/codegen for --model, where the library is "
                            "also built)")
    gen.add_argument("--check", action="store_true",
                     help="only compare the folder with what would be written; exit 1 if stale")
    gen.add_argument("--no-cache", action="store_true",
                     help="derive every mechanism again, even where nothing it is made from "
                          "changed since the last run in this checkout (build/generate-cache)")

    src = _verb(verbs, "sources", "print the folders of a library's C sources, or copy them",
                prog, _sources)
    _mechanism_options(src, None)
    src.add_argument("--copy", metavar="DIR",
                     help="copy the .c and .h files (library and runtime) into DIR")

    _verb(verbs, "list", "the mechanisms this installation has compiled", prog, _list)

    from .branches import DEFAULT_POINTS
    from .sweep import CHUNK

    swp = _verb(verbs, "sweep", "analyse a grid or a random sample of parameter sets into a "
                "CSV or Parquet table", prog, _sweep)
    _mechanism_options(swp, None)
    swp.add_argument("--vary", action="append", type=_assignment, required=True,
                     metavar="NAME=START:STOP:COUNT",
                     help="a grid axis, COUNT values from START to STOP inclusive; with "
                          "--sample, NAME=LO:HI, a uniform range (repeatable)")
    swp.add_argument("--sample", type=_positive, metavar="N",
                     help="N random sets instead of a grid")
    swp.add_argument("--seed", type=int, help="the random seed of --sample")
    _set_option(swp, "a parameter held fixed at VALUE instead of the example's, in SI units "
                     "(repeatable)")
    swp.add_argument("--out", required=True, metavar="FILE",
                     help="the table to write: FILE.csv or FILE.parquet (Parquet needs "
                          "pyarrow: pip install 'mechvib[sweep]')")
    _method_option(swp)
    swp.add_argument("--all-roots", action="store_true",
                     help="a row per classified root (other assembly modes and extraneous "
                          "roots too), not only per equilibrium")
    swp.add_argument("--workers", type=_positive, metavar="N",
                     help="threads (default: every CPU; with --scheduler, per task: 1)")
    swp.add_argument("--chunk", type=_positive, default=CHUNK, metavar="N",
                     help=f"sets per chunk: per task on Dask, per progress step (default {CHUNK})")
    swp.add_argument("--scheduler", metavar="ADDRESS",
                     help="run one task per chunk on this dask.distributed scheduler (e.g. "
                          "tcp://host:8786; pip install 'mechvib[dask]'; its workers need "
                          "mechvib installed)")

    brn = _verb(verbs, "branches", "every equilibrium as one parameter varies: branches, folds "
                "and stability, as a table and a figure", prog, _branches)
    _mechanism_options(brn, None, model=True)
    brn.add_argument("--vary", required=True, metavar="NAME", help="the parameter to vary")
    brn.add_argument("--from", dest="start", type=float, required=True, metavar="VALUE",
                     help="its first value, in its unit")
    brn.add_argument("--to", dest="stop", type=float, required=True, metavar="VALUE",
                     help="its last value, in its unit (above --from)")
    brn.add_argument("--points", type=_positive, default=DEFAULT_POINTS, metavar="N",
                     help=f"values sampled, evenly spaced, ends included (default "
                          f"{DEFAULT_POINTS})")
    brn.add_argument("--set", action="append", type=_assignment, default=[],
                     metavar="NAME=VALUE",
                     help="another parameter held at VALUE instead of the example's, in SI "
                          "units (repeatable)")
    brn.add_argument("--out", metavar="FILE",
                     help="write every point of every branch: FILE.csv, FILE.json or "
                          "FILE.parquet (angles in degrees)")
    brn.add_argument("--plot", metavar="FILE",
                     help="draw the figure: FILE.png or FILE.svg (pip install 'mechvib[plot]')")
    _method_option(brn)
    brn.add_argument("--workers", type=_positive, metavar="N",
                     help="threads for the samples (default: every CPU)")

    sim = _verb(verbs, "simulate", "the motion from an initial state: theta(t) and thetadot(t) "
                "as CSV or JSON, and a figure", prog, _simulate)
    _mechanism_options(sim, None, model=True)
    _set_option(sim)
    sim.add_argument("--theta0", type=float, required=True, metavar="DEG",
                     help="the initial angle [deg]")
    sim.add_argument("--thetadot0", type=float, default=0.0, metavar="DEG/S",
                     help="the initial rate [deg/s] (default 0)")
    sim.add_argument("--to", type=float, required=True, metavar="T",
                     help="the end time [s] (the motion starts at t = 0)")
    sim.add_argument("--points", type=_positive, default=1001, metavar="N",
                     help="output times, evenly spaced from 0 to T (default 1001)")
    sim.add_argument("--rtol", type=float, metavar="R",
                     help="relative tolerance per step (default 1e-9)")
    sim.add_argument("--atol", type=float, metavar="A",
                     help="absolute tolerance per step, in rad and rad/s (default 1e-12)")
    sim.add_argument("--max-steps", type=_positive, metavar="N",
                     help="the integrator's step budget (default 1000000)")
    sim.add_argument("--linearised", action="store_true",
                     help="also the linearised response about the stable equilibrium nearest "
                          "theta0")
    sim.add_argument("--out", metavar="FILE",
                     help="write FILE.csv or FILE.json instead of CSV on stdout")
    sim.add_argument("--plot", metavar="FILE",
                     help="draw theta(t) and thetadot(t) to FILE.png or FILE.svg (needs "
                          "matplotlib: pip install 'mechvib[plot]')")
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
    other = foreign_codegen()
    if other:
        print(f"{top.prog}: warning: the unrelated distribution {other} is installed in this "
              "environment and shares the import name 'codegen'; use a separate virtual "
              "environment for mechvib", file=sys.stderr)
    args = top.parse_args(argv)
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
