"""`mechvib sweep`: a grid or a random sample of parameter sets analysed into a table,
locally or on a Dask cluster."""
from __future__ import annotations

import os
import time

from . import common

#: --chunk's default: codegen.runtime.sweep.CHUNK (written here so that building the parser
#: imports no runtime; tests/cli/test_lazy_imports.py holds the two equal).
CHUNK = 16384

EXAMPLES = """\
examples:
  {prog} sweep --vary F=0:200:101 --vary k=1000:3000:5 --out grid.csv
  {prog} sweep --sample 1000000 --vary F=0:200 --vary k=1000:3000 --seed 1 --out s.parquet
  {prog} sweep --vary F=0:200:201 --set b=0 --all-roots --workers 2 --out roots.csv
  {prog} sweep --sample 10000000 --vary F=0:200 --scheduler tcp://HOST:8786 --out big.parquet
  {prog} sweep --mechanism double_pendulum --vary k_1=5:40:8 --vary F_x=0:2:3 --out dp.csv
  {prog} sweep --model my_model.py --build build/mine --vary k=10:50:5 --out mine.csv

--vary NAME=START:STOP:COUNT makes a grid axis of COUNT values from START to STOP (both
included); with --sample N, --vary NAME=LO:HI draws each set's NAME uniformly in [LO, HI).
The other parameters are the example's, or --set's. The file has one row per equilibrium
(per root with --all-roots), with the set's index, parameters and status; a set that fails
or has none has one row with an empty theta_deg. Angles in degrees there (columns NAME_deg),
the rest SI; an angle parameter in --vary and --set is in degrees too (or 90deg, 1.5708rad).
With several coordinates a row has a column per coordinate (NAME_deg for an angle), each
mode's omega_n_J and zeta_J, and the number of boxes of its set left undecided."""


def _grid_axis(name: str, spec: str, unit: str | None = None):
    """START:STOP:COUNT as COUNT values from START to STOP, both included."""
    import numpy as np

    parts = spec.split(":")
    if len(parts) != 3:
        raise ValueError(f"--vary {name}={spec}: a grid axis is NAME=START:STOP:COUNT (NAME=LO:HI "
                         "is for --sample)")
    count = parts[2].strip()
    if not count.isdigit() or int(count) < 1:
        raise ValueError(f"--vary {name}={spec}: COUNT must be a positive integer")
    return np.linspace(common.number(name, parts[0], unit), common.number(name, parts[1], unit),
                       int(count))


def _sample_range(name: str, spec: str, unit: str | None = None) -> tuple[float, float]:
    """LO:HI as a pair of numbers."""
    parts = spec.split(":")
    if len(parts) != 2:
        raise ValueError(f"--vary {name}={spec}: with --sample, a range is NAME=LO:HI")
    return common.number(name, parts[0], unit), common.number(name, parts[1], unit)


def _sweep_sets(library, args):
    """The parameter sets --vary, --sample, --seed and --set describe (a params_array)."""
    from ..runtime import sweep

    units = library.UNITS
    base, names = common.overrides(args.set, units), [name for name, _ in args.vary]
    for name in names:
        if names.count(name) > 1 or name in base:
            raise ValueError(f"{name}: given more than once (--vary, --set)")
    if args.sample is None:
        if args.seed is not None:
            raise ValueError("--seed is for --sample")
        return sweep.grid(library, {n: _grid_axis(n, spec, units.get(n)) for n, spec in args.vary}, base)
    ranges = {name: _sample_range(name, spec, units.get(name)) for name, spec in args.vary}
    return sweep.sample(library, args.sample, ranges, base, args.seed)


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
    from ..runtime.sweep import worker_wait

    wait = worker_wait()   # for the scheduler to answer, then for its first worker
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


class _Tally:
    """What the summary of a sweep counts, piece by piece."""

    def __init__(self, library) -> None:
        from ..runtime.analysis import KINDS, STABILITY

        self.library, self.rows, self.equilibria, self.stable = library, 0, 0, 0
        self.failed: dict[int, int] = {}
        self._equilibrium, self._stable = KINDS.index("equilibrium"), STABILITY.index("stable")

    def add(self, piece) -> None:
        import numpy as np

        self.rows += len(piece)
        genuine = (piece["kind"] == self._equilibrium if "kind" in piece.dtype.names
                   else piece["stability"] >= 0)  # several coordinates: every row is proven
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


def run(args) -> int:
    """Analyse every set, writing the rows as they come; a summary on stdout."""
    from ..runtime import sweep

    if args.build and not args.model:
        raise ValueError("--build DIR is where --model FILE is built: give --model too")
    sweep.check_output(args.out)   # before a model is built, which can take minutes
    library = common.load_library(args, args.build)
    sets = _sweep_sets(library, args)
    roots = "all" if args.all_roots else "equilibria"
    start, tally = time.perf_counter(), _Tally(library)
    with _dask_client(args.scheduler) as client, sweep.Writer(args.out, angles=sweep.angle_columns(library)) as writer, \
            common.ProgressBar() as bar:
        for piece in sweep.stream(library, sets, method=args.method, workers=args.workers,
                                  chunk=args.chunk, client=client, progress=bar, roots=roots):
            writer.write(piece)
            tally.add(piece)
    where = (f"on the Dask cluster at {args.scheduler}" if args.scheduler else
             f"on {args.workers or os.cpu_count() or 1} threads")
    print(tally.summary(len(sets), time.perf_counter() - start, where, args.out))
    return 0


def add(verbs, prog: str) -> None:
    swp = common.verb(verbs, "sweep", "analyse a grid or a random sample of parameter sets "
                      "into a CSV or Parquet table", EXAMPLES, prog, run)
    common.mechanism_options(swp, None, build_help=(
        "with --model: where its library is generated and built (default: the per-user "
        "cache ~/.cache/mechvib; a build there or in DIR is reused while the file is "
        "unchanged)"))
    swp.add_argument("--vary", action="append", type=common.assignment, required=True,
                     metavar="NAME=START:STOP:COUNT",
                     help="a grid axis, COUNT values from START to STOP inclusive; with "
                          "--sample, NAME=LO:HI, a uniform range (repeatable)")
    swp.add_argument("--sample", type=common.positive, metavar="N",
                     help="N random sets instead of a grid")
    swp.add_argument("--seed", type=int, help="the random seed of --sample")
    common.set_option(swp, "a parameter held fixed at VALUE instead of the example's, in SI "
                           "units (repeatable)")
    swp.add_argument("--out", required=True, metavar="FILE",
                     help="the table to write: FILE.csv or FILE.parquet (Parquet needs "
                          "pyarrow: pip install 'mechvib[sweep]')")
    common.method_option(swp)
    swp.add_argument("--all-roots", action="store_true",
                     help="a row per classified root (other assembly modes and extraneous "
                          "roots too), not only per equilibrium")
    swp.add_argument("--workers", type=common.positive, metavar="N",
                     help="threads (default: every CPU; with --scheduler, per task: 1)")
    swp.add_argument("--chunk", type=common.positive, default=CHUNK, metavar="N",
                     help=f"sets per chunk: per task on Dask, per progress step (default {CHUNK})")
    swp.add_argument("--scheduler", metavar="ADDRESS",
                     help="run one task per chunk on this dask.distributed scheduler (e.g. "
                          "tcp://host:8786; pip install 'mechvib[dask]'; its workers need "
                          "mechvib installed)")
