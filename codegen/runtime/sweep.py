"""Sweeps, the analysis of a grid or a random sample of parameter sets as one table.

``grid(library, axes)`` and ``sample(library, count, ranges)`` make the parameter sets (a
``params_array``); ``sweep(library, sets)`` analyses them chunk by chunk (``batch.analyze_blocks``
on threads, or one task per chunk on a Dask cluster) into one numpy structured array with a
row per root, the set's index and parameters repeated on it; ``write(table, path)`` writes
it as CSV or Parquet. ``stream`` gives the same table chunk by chunk, in order, so that a
sweep larger than memory can be written as it goes (``write(stream(...), path)``).

Every set has at least one row: a set that fails (``status`` != 0) or has no root kept has
one row with NaN ``theta``, so a table never loses a set. The rows are the same, bit for
bit, for any number of threads, any chunk size, and locally or on Dask: each chunk is
analysed by the same deterministic C, and its set indices are offset by where it starts.

A mechanism with several coordinates is swept the same way: its rows have a column per
coordinate, and each mode's omega_n and zeta (``codegen.runtime.multibody.sweep_fields``);
``_form`` is the one place here that tells the two apart.
"""
from __future__ import annotations

import math
import os
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Literal

import numpy as np

from . import analysis, batch, multibody
from .. import files
from .library import Library, ParamsLike

#: Which roots a sweep keeps: the declared mode's equilibria, or every classified root.
ROOTS = ("equilibria", "all")
Roots = Literal["equilibria", "all"]

#: Sets per chunk: a task on Dask, a progress step, a write. Small enough that a chunk's rows
#: (~15 MB at six roots a set) reuse the memory of the last chunk's rather than take fresh pages
#: from the system.
CHUNK = 16384

#: The code of kind, stability and damping on a row without a root (a text column's null).
NO_ROOT = -1

#: The columns after the parameters'. kind, stability and damping index analysis.KINDS,
#: STABILITY and DAMPING (NO_ROOT: no root); omega_n and zeta are real, NaN where the root has
#: no real natural frequency (K <= 0, M = 0, or no root). Angles [rad], the rest SI.
RESULT_FIELDS = [("status", np.int32), ("theta", np.float64), ("kind", np.int8),
                 ("certified", np.bool_), ("stability", np.int8), ("damping", np.int8),
                 ("omega_n", np.float64), ("zeta", np.float64), ("K", np.float64),
                 ("M", np.float64), ("B", np.float64)]

#: The columns of a table in radians, written to files in degrees as NAME_deg.
ANGLES = ("theta",)

#: The text of the coded columns, as written to files.
LABELS = {"kind": analysis.KINDS, "stability": analysis.STABILITY, "damping": analysis.DAMPING}

#: A progress callback: (sets done, sets in all), called as chunks finish.
Progress = Callable[[int, int], None]


# ------------------------------------------------------------------------ parameter sets

def _check_names(library: Library, names: Iterable[str]) -> None:
    unknown = [n for n in names if n not in library.PARAMETER_NAMES]
    if unknown:
        raise ValueError(f"unknown parameter(s): {', '.join(unknown)}; {library.PREFIX} has "
                         f"{', '.join(library.PARAMETER_NAMES)}")


def _filled(library: Library, base: ParamsLike | None, count: int) -> np.ndarray:
    """``count`` copies of ``base`` (a parameter set, or a mapping of some parameters over
    the example; default the example) as a params_array."""
    values = {} if base is None else dict(base if isinstance(base, Mapping) else vars(base))
    _check_names(library, values)
    table = np.empty(count, dtype=library.PARAMS_DTYPE)
    for name in library.PARAMETER_NAMES:
        table[name] = float(values.get(name, library.EXAMPLE[name]))
    return table


def grid(library: Library, axes: Mapping[str, Sequence[float] | np.ndarray],
         base: ParamsLike | None = None) -> np.ndarray:
    """Every combination of the values of ``axes`` (parameter name -> 1-D values, SI units),
    the other parameters from ``base`` (a parameter set, or a mapping of some parameters;
    default: the example), as a params_array. The first axis varies slowest (C order of an
    ``indexing="ij"`` mesh). Raises ValueError naming an unknown parameter or an axis that
    is not 1-D."""
    _check_names(library, axes)
    values = [np.asarray(v, dtype=np.float64) for v in axes.values()]
    for name, v in zip(axes, values):
        if v.ndim != 1:
            raise ValueError(f"{name}: a grid axis is a 1-D array of values, not of shape "
                             f"{v.shape}")
    shape = tuple(len(v) for v in values)
    table = _filled(library, base, math.prod(shape))
    for name, mesh in zip(axes, np.meshgrid(*values, indexing="ij", sparse=True)):
        table[name] = np.broadcast_to(mesh, shape).ravel()
    return table


def sample(library: Library, count: int, ranges: Mapping[str, tuple[float, float]],
           base: ParamsLike | None = None, seed: int | None = None) -> np.ndarray:
    """``count`` sets drawn uniformly in [lo, hi) for each parameter ``ranges`` names
    (name -> (lo, hi), SI units; drawn in the mapping's order from
    ``numpy.random.default_rng(seed)``), the others from ``base`` (as for ``grid``), as a
    params_array. Raises ValueError naming an unknown parameter or a bad range."""
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 0:
        raise ValueError(f"count must be a non-negative integer, not {count!r}")
    _check_names(library, ranges)
    table = _filled(library, base, int(count))
    rng = np.random.default_rng(seed)
    for name, bounds in ranges.items():
        lo, hi = _range(name, bounds)
        table[name] = rng.uniform(lo, hi, int(count))
    return table


def _range(name: str, bounds: Any) -> tuple[float, float]:
    try:
        lo, hi = (float(b) for b in bounds)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: a range is a pair (lo, hi), not {bounds!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
        raise ValueError(f"{name}: a range needs finite lo <= hi, not ({lo:g}, {hi:g})")
    return lo, hi


def _as_table(library: Library, sets: Any) -> np.ndarray:
    """sets as a contiguous params_array: fields matched by name (numpy casts structured
    arrays by position), anything else through ``library.params_array``."""
    if not isinstance(sets, np.ndarray):
        return library.params_array(sets)
    names = sets.dtype.names or ()
    if sets.ndim != 1 or sorted(names) != sorted(library.PARAMETER_NAMES):
        raise ValueError(f"sets must be a 1-D structured array with one field per parameter "
                         f"of {library.PREFIX} ({', '.join(library.PARAMETER_NAMES)}), not "
                         f"{sets.ndim}-D with fields {', '.join(names) or 'none'}")
    if sets.dtype == library.PARAMS_DTYPE:
        return np.ascontiguousarray(sets)
    table = np.empty(len(sets), dtype=library.PARAMS_DTYPE)
    for name in library.PARAMETER_NAMES:
        table[name] = sets[name]
    return table


# --------------------------------------------------------------------------- the table

#: The value of a column on a row without a root, by its numpy kind: NaN, NO_ROOT, False.
_NO_ROOT_VALUE = {"f": np.nan, "i": NO_ROOT, "b": False}

#: What a block of C results puts in a sweep's rows: (the columns of each set of the block,
#: the index of each root's set in the block, the columns of each root).
Found = tuple[dict[str, np.ndarray], np.ndarray, dict[str, np.ndarray]]


def _one_coordinate_roots(library: Library, c: np.ndarray, statuses: np.ndarray,
                          every_root: bool) -> Found:
    """The roots of a block of a one-coordinate library's C results (RESULT_FIELDS),
    straight from the C structs: every classified root, or (not ``every_root``) the declared
    mode's equilibria."""
    found, sets, _ = batch.c_roots(library, c, statuses)
    if not every_root:
        keep = found["kind"] == batch.EQUILIBRIUM
        found, sets = found[keep], sets[keep]
    extraneous = found["kind"] == batch.EXTRANEOUS   # not an equilibrium: null in the file
    omega, zeta = found["omega_n"], found["zeta"]    # (re, im) pairs
    real = (omega[:, 1] == 0) & (omega[:, 0] > 0)
    columns = {name: found[name] for name in ("theta", "kind", "K", "M", "B")}
    columns.update(
        certified=found["certified"] != 0,
        stability=np.where(extraneous, NO_ROOT, found["stability"]),
        damping=np.where(extraneous, NO_ROOT, found["damping"]),
        omega_n=np.where(real, omega[:, 0], np.nan), zeta=np.where(real, zeta[:, 0], np.nan))
    return {"status": statuses}, sets, columns


@dataclass(frozen=True)
class _Form:
    """A sweep's rows for a number of coordinates: ``fields(library)``, the columns after
    the parameters'; ``coordinates(library)``, the columns of the coordinates with their
    units; ``roots(library, c, statuses, every_root)``, what a block of C results puts in
    the rows (``Found``)."""

    fields: Callable[[Library], list[tuple[str, Any]]]
    coordinates: Callable[[Library], tuple[tuple[str, str], ...]]
    roots: Callable[[Library, np.ndarray, np.ndarray, bool], Found]


_ONE_COORDINATE = _Form(lambda library: RESULT_FIELDS,
                        lambda library: tuple((name, "rad") for name in ANGLES),
                        _one_coordinate_roots)
_SEVERAL_COORDINATES = _Form(
    multibody.sweep_fields,
    lambda library: tuple((c["name"], c["unit"]) for c in library.SPEC["coordinates"]),
    multibody.sweep_roots)


def _form(library: Library) -> _Form:
    """The rows of a sweep of ``library``: the one place here that depends on its number of
    coordinates."""
    return _SEVERAL_COORDINATES if library.dof > 1 else _ONE_COORDINATE


def parameter_columns(library: Library) -> tuple[str, ...]:
    """The column of each parameter: its name, or ``param_NAME`` where a result column
    has that name (a model's parameter called K, say)."""
    taken = {"set", *(name for name, _ in _form(library).fields(library))}
    return tuple(f"param_{n}" if n in taken else n for n in library.PARAMETER_NAMES)


@lru_cache(maxsize=None)
def dtype(library: Library) -> np.dtype:
    """The dtype of a sweep's rows: ``set`` (the set's index), one float64 column per
    parameter (``parameter_columns``), then RESULT_FIELDS (with several coordinates,
    ``codegen.runtime.multibody.sweep_fields``)."""
    return np.dtype([("set", np.int64)] + [(c, np.float64) for c in parameter_columns(library)]
                    + _form(library).fields(library))


def _rows(library: Library, table: np.ndarray, offset: int, roots: Found) -> np.ndarray:
    """The rows of consecutive sets (``table``), the first of them set ``offset`` of the
    sweep: each set's roots (``roots``: the columns of each set, the index of each root's
    set in ``table``, the columns of each root), or one rootless row."""
    per_set_columns, sets, columns = roots
    kept = np.bincount(sets, minlength=len(table))
    per_set = np.maximum(kept, 1)
    which = np.repeat(np.arange(len(table)), per_set)
    rows = np.empty(len(which), dtype=dtype(library))
    rows["set"] = which + offset
    source = _parameters_of(table, library.PARAMETER_NAMES)
    target = _parameters_of(rows, parameter_columns(library))
    if source is not None and target is not None:
        target[:] = source[which]
    else:
        for name, column in zip(library.PARAMETER_NAMES, parameter_columns(library)):
            rows[column] = table[name][which]
    for name, values in per_set_columns.items():
        rows[name] = values[which]
    if len(sets) == len(rows):   # every set has roots (usually): its rows are its roots
        at: slice | np.ndarray = slice(None)
    else:                        # and the rest, one rootless row each
        for name in columns:
            rows[name] = _NO_ROOT_VALUE[rows.dtype[name].kind]
        at = np.repeat(kept > 0, per_set)
    for name, values in columns.items():
        rows[name][at] = values
    return rows


def _block_rows(library: Library, table: np.ndarray, offset: int, every_root: bool
                ) -> batch.BlockRows:
    """What a block of C results becomes in a sweep whose chunk ``table`` starts at set
    ``offset``: its sets' rows, made on the thread that analysed them, straight from the C
    structs (no Table between)."""
    roots = _form(library).roots

    def make(c: np.ndarray, statuses: np.ndarray, first: int) -> np.ndarray:
        return _rows(library, table[first:first + len(c)], offset + first,
                     roots(library, c, statuses, every_root))
    return make


def _analyzed_rows(library: Library, table: np.ndarray, offset: int, method: analysis.Method,
                   every_root: bool, workers: int) -> np.ndarray:
    """The sweep rows of a chunk of sets (a params_array)."""
    blocks, _, _ = batch.analyze_blocks(table, library,
                                        _block_rows(library, table, offset, every_root),
                                        method, workers)
    return np.concatenate(blocks) if blocks else np.empty(0, dtype(library))


def _parameters_of(rows: np.ndarray, names: Sequence[str]) -> np.ndarray | None:
    """The fields ``names`` of a structured array as one (rows, fields) float64 view where
    they are consecutive float64 fields (a params_array's parameters, and a sweep's parameter
    columns, are), so that a chunk's rows take every parameter in one gather; else None."""
    fields = [rows.dtype.fields[n] for n in names]
    first = fields[0][1]
    if not rows.flags.c_contiguous or any(
            t != np.float64 or at != first + 8 * i for i, (t, at) in enumerate(fields)):
        return None
    return np.ndarray((len(rows), len(names)), np.float64, buffer=rows, offset=first,
                      strides=(rows.dtype.itemsize, 8))


def analyze_chunk(library: Library, table: np.ndarray, offset: int = 0,
                  method: analysis.Method = "auto", roots: Roots = "equilibria",
                  workers: int = 1) -> np.ndarray:
    """The sweep rows of one chunk of sets, whose first set is set ``offset`` of the
    sweep: what each local step and each Dask task runs (a Library pickles by its origin,
    so a worker process loads it again)."""
    table = _as_table(library, table)
    return _analyzed_rows(library, table, offset, method, roots == "all", workers)


# --------------------------------------------------------------------------- running

def _is_dask(sets: Any) -> bool:
    return type(sets).__module__.startswith("dask.array")


def _parts(library: Library, sets: Any, chunk: int) -> tuple[int, list[tuple[int, Any]]]:
    """(sets in all, [(offset, part)]): slices of ``chunk`` sets, or a dask array's blocks
    (as dask.delayed objects)."""
    if _is_dask(sets):
        sizes = sets.chunks[0]
        if sets.ndim != 1 or any(math.isnan(s) for s in sizes):
            raise ValueError("a dask array of sets must be 1-D with known chunk sizes")
        offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
        return int(sets.shape[0]), list(zip(offsets.tolist(), sets.to_delayed().ravel()))
    table = _as_table(library, sets)
    starts = range(0, max(len(table), 1), chunk)   # an empty sweep is one empty chunk
    return len(table), [(s, table[s:s + chunk]) for s in starts]


def _local(library: Library, parts: list[tuple[int, Any]], method: analysis.Method,
           roots: Roots, workers: int) -> Iterator[np.ndarray]:
    """Each part's rows in order. The C of the next parts runs (on threads, without the GIL)
    while this thread hands one part's rows to the caller, who writes them. With parts
    enough for every thread, each part runs on one thread, ``workers`` parts at once (no
    thread then waits at the end of a part for the other's half of it); else each part is
    split over the ``workers`` threads."""
    whole_parts = len(parts) >= 2 * workers
    threads, per_part = (workers, 1) if whole_parts else (1, workers)

    def analyze(offset: int, table: np.ndarray) -> np.ndarray:
        return _analyzed_rows(library, table, offset, method, roots == "all", per_part)

    with ThreadPoolExecutor(threads) as ahead:
        pending: deque[Future[np.ndarray]] = deque()
        for offset, part in parts:
            table = _as_table(library, part if isinstance(part, np.ndarray) else part.compute())
            pending.append(ahead.submit(analyze, offset, table))
            if len(pending) > threads:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()


def _distributed(client: Any, parts: list[tuple[int, Any]], arguments: tuple[Any, ...]
                 ) -> Iterator[np.ndarray]:
    """One analyze_chunk task per part on a dask.distributed cluster, gathered in order.
    ``arguments``: (library, method, roots, workers), passed by position (``workers`` is
    also a keyword of Client.submit)."""
    library, *options = arguments
    if parts and isinstance(parts[0][1], np.ndarray):
        # Each chunk travels inside its task, not scattered ahead: data scattered to one
        # worker dies with it, while a task that holds its data is run again elsewhere.
        futures = [client.submit(analyze_chunk, library, table, offset, *options, pure=False)
                   for offset, table in parts]
    else:
        import dask

        task = dask.delayed(analyze_chunk, pure=False)
        futures = client.compute([task(library, part, offset, *options)
                                  for offset, part in parts])
    order = {future.key: i for i, future in enumerate(futures)}
    done: dict[int, np.ndarray] = {}
    ready = 0
    for future in _finished(client, futures):
        done[order[future.key]] = future.result()
        future.release()
        while ready in done:
            yield done.pop(ready)
            ready += 1


#: Seconds a cluster may be without any worker before a sweep on it fails (the environment's
#: MECHVIB_WORKER_WAIT, if set); the command line waits as long for a scheduler to answer.
WORKER_WAIT = 30.0


def worker_wait() -> float:
    """Seconds a Dask sweep waits for a worker (MECHVIB_WORKER_WAIT, else WORKER_WAIT)."""
    return float(os.environ.get("MECHVIB_WORKER_WAIT", WORKER_WAIT))


def _finished(client: Any, futures: list[Any]) -> Iterator[Any]:
    """The futures as they finish. TimeoutError once the cluster has had no worker for
    ``worker_wait()`` seconds: its tasks would wait, silently, for one that may never come."""
    from distributed import as_completed

    pending, watch = as_completed(futures), _WorkerWatch(client, worker_wait())
    while not pending.is_empty():
        batch = pending.next_batch(block=False)
        if batch:
            yield from batch
        elif watch.deserted():
            client.cancel(futures)
            raise TimeoutError(f"no worker is left on the Dask cluster (none for "
                               f"{watch.wait:g} s): its tasks would wait forever")
        else:
            time.sleep(0.02)   # none finished yet: look again soon (as as_completed does)


class _WorkerWatch:
    """Whether a cluster has been without any worker for ``wait`` seconds, asked at most
    every second (each look is a call to the scheduler)."""

    def __init__(self, client: Any, wait: float) -> None:
        self.client, self.wait = client, wait
        self.looked = -math.inf
        self.alone_since: float | None = None

    def deserted(self) -> bool:
        now = time.monotonic()
        if now - self.looked >= min(1.0, self.wait / 4):
            self.looked = now
            if self.client.nthreads():
                self.alone_since = None
            elif self.alone_since is None:
                self.alone_since = now
        return self.alone_since is not None and now - self.alone_since >= self.wait


def _default_client() -> Any:
    """The Dask client this process made, if any (what dask.compute would use)."""
    try:
        from distributed import default_client
        return default_client()
    except (ImportError, ValueError):
        return None


def _positive(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be a positive integer, not {value!r}")
    return int(value)


def stream(library: Library, sets: Any, *, method: analysis.Method = "auto",
           workers: int | None = None, chunk: int = CHUNK, client: Any = None,
           progress: Progress | None = None, roots: Roots = "equilibria"
           ) -> Iterator[np.ndarray]:
    """``sweep``'s table in consecutive pieces (one per chunk, in order, at least one),
    for writing a sweep as it runs: ``write(stream(lib, sets), "out.parquet")``. The
    arguments are ``sweep``'s; they are checked before the first piece is asked for."""
    batch.route(library, method)   # an unknown or unavailable route fails now
    if roots not in ROOTS:
        raise ValueError(f"roots must be one of {', '.join(ROOTS)}, not {roots!r}")
    chunk = _positive("chunk", chunk)
    if workers is not None:
        workers = _positive("workers", workers)
    if client is None and _is_dask(sets):
        client = _default_client()
    total, parts = _parts(library, sets, chunk)
    if client is None:
        pieces = _local(library, parts, method, roots, workers or os.cpu_count() or 1)
    else:
        pieces = _distributed(client, parts, (library, method, roots, workers or 1))
    return _counted(pieces, total, progress)


def _counted(pieces: Iterator[np.ndarray], total: int, progress: Progress | None
             ) -> Iterator[np.ndarray]:
    """The pieces, reporting the sets done after each (each set of a piece has a row)."""
    if progress is not None:
        progress(0, total)
    done = 0
    for piece in pieces:
        done += int(piece["set"][-1] - piece["set"][0]) + 1 if len(piece) else 0
        if progress is not None:
            progress(done, total)
        yield piece


def sweep(library: Library, sets: Any, *, method: analysis.Method = "auto",
          workers: int | None = None, chunk: int = CHUNK, client: Any = None,
          progress: Progress | None = None, roots: Roots = "equilibria") -> np.ndarray:
    """Every set of ``sets`` analysed, as one structured array (``dtype(library)``) with a
    row per root kept, ordered by set, then by angle.

    ``sets``: a params_array (``grid``, ``sample``, ``library.params_array``), anything
    ``params_array`` takes, or a dask array of its records (one task per block). ``roots``:
    "equilibria" (the declared mode's) or "all" (every classified root). A failed set
    (``status`` != 0: ``library.error(status, params)`` explains it) or one without a root
    kept has one row with NaN theta and ``NO_ROOT`` codes. ``method``: the route (see
    ``codegen.runtime.analysis``; several coordinates have one, the isolation, and a row
    per proven equilibrium: ``codegen.runtime.multibody.sweep_fields``). Locally, chunks of ``chunk`` sets run one after another, each on
    ``workers`` threads (default: every CPU); with a ``dask.distributed.Client`` (or a dask
    array and a default client), one task per chunk runs on the cluster, on ``workers``
    threads each (default 1). ``progress(done, total)`` is called as chunks finish (the
    CLI draws a progress bar with it). The result does not depend on ``workers``, ``chunk`` or ``client``.
    """
    return np.concatenate(list(stream(library, sets, method=method, workers=workers,
                                      chunk=chunk, client=client, progress=progress,
                                      roots=roots)))


# --------------------------------------------------------------------------- files

FORMATS = (".csv", ".parquet")
EXTRA = "pip install 'mechvib[sweep]'"


def _pyarrow() -> Any:
    """pyarrow with its csv and parquet modules, or None where it is not installed."""
    try:
        import pyarrow
        import pyarrow.csv
        import pyarrow.parquet  # noqa: F401 (imported for pyarrow.parquet below)
    except ImportError:
        return None
    return pyarrow


def check_output(path: str | os.PathLike[str]) -> Any:
    """Raise ValueError unless a table can be written to ``path``: it ends in .csv or
    .parquet, its folder exists, and for Parquet pyarrow is installed. Returns pyarrow, or
    None where it is not installed."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise ValueError(f"{path}: the output must end in .csv or .parquet")
    arrow = _pyarrow()
    if arrow is None and path.suffix.lower() == ".parquet":
        raise ValueError(f"{path}: writing Parquet needs pyarrow: {EXTRA} (or write .csv)")
    if not path.parent.is_dir():
        raise ValueError(f"{path}: no folder {path.parent}")
    return arrow


class Writer:
    """Rows written to a .csv or .parquet file piece by piece (``write(rows)``), into a
    hidden partial file that replaces ``path`` only when the writer closes without an
    error. Opening checks the extension, the folder and, for Parquet, that pyarrow is
    installed. ``labels``: the coded columns and their text (default: a sweep's).
    ``angles``: the columns in radians, written in degrees as NAME_deg (default: theta;
    ``angle_columns(library)`` adds a mechanism's angle parameters). CSV floats are written
    shortest round-trip (0.03, not 0.029999999999999999), with or without pyarrow."""

    def __init__(self, path: str | os.PathLike[str],
                 labels: Mapping[str, Sequence[str]] = LABELS,
                 angles: Sequence[str] = ANGLES) -> None:
        self.path = Path(path)
        self.labels = labels
        self.angles = tuple(angles)
        self.format = self.path.suffix.lower()
        self.arrow = check_output(self.path)
        files.remove_orphans(self.path)
        self.partial = files.temporary(self.path, ".partial")  # this writer's alone
        self.rows = 0
        self._sink: Any = None

    def write(self, rows: np.ndarray) -> None:
        """Append sweep rows (a ``stream`` piece or a whole ``sweep`` table)."""
        columns = _file_columns(rows, self.angles)
        rootless = _rootless(rows)
        if self.arrow is None or self.format == ".csv":
            self._write_text(columns, rootless)
        else:
            self._write_arrow(columns, rootless)
        self.rows += len(rows)

    def _write_arrow(self, columns: dict[str, np.ndarray], rootless: np.ndarray) -> None:
        table = _arrow_table(self.arrow, columns, rootless, self.labels)
        if self._sink is None:
            if self.format == ".csv":
                self._sink = self.arrow.csv.CSVWriter(str(self.partial), table.schema)
            else:   # dictionaries for the text columns alone: the numbers rarely repeat, and
                # trying them costs half the write
                self._sink = self.arrow.parquet.ParquetWriter(
                    str(self.partial), table.schema,
                    use_dictionary=[n for n in columns if n in self.labels])
        self._sink.write_table(table)

    def _write_text(self, columns: dict[str, np.ndarray], rootless: np.ndarray) -> None:
        """CSV without pyarrow, in pyarrow's form (quoted text, true/false, empty nulls)."""
        if self._sink is None:
            self._sink = open(self.partial, "w", newline="")
            self._sink.write(",".join(f'"{name}"' for name in columns) + "\n")
        fields = [_text_column(values, name, rootless, self.labels)
                  for name, values in columns.items()]
        self._sink.writelines(",".join(row) + "\n" for row in zip(*fields))

    def close(self, error: bool = False) -> None:
        """Finish the file and move it into place; after an error, or when finishing it
        fails (a full disk, the file-size limit), remove it."""
        placed = False
        try:
            self._close_sink(quiet=error)
            if not error:
                if self._sink is None:
                    raise ValueError(f"{self.path}: no rows were given to write")
                os.replace(self.partial, self.path)
                placed = True
        finally:
            if not placed:
                self.partial.unlink(missing_ok=True)

    def _close_sink(self, quiet: bool) -> None:
        """Close the stream; ``quiet``: after an error, which its own failure (flushing
        what the error left, into the same full disk) would only hide."""
        if self._sink is None:
            return
        try:
            self._sink.close()
        except Exception:
            if not quiet:
                raise

    def __enter__(self) -> Writer:
        return self

    def __exit__(self, kind: type[BaseException] | None, *exc: object) -> None:
        self.close(error=kind is not None)


def angle_columns(library: Library) -> tuple[str, ...]:
    """The columns of a sweep of ``library`` in radians: theta (each angle coordinate's) and
    each angle parameter's."""
    coordinates = tuple(name for name, unit in _form(library).coordinates(library)
                        if unit == "rad")
    return coordinates + tuple(column for name, column in zip(library.PARAMETER_NAMES,
                                                         parameter_columns(library))
                          if library.UNITS.get(name) == "rad")


def in_degrees(rows: np.ndarray, angles: Sequence[str]) -> np.ndarray:
    """rows with each column of ``angles`` it has in degrees, renamed NAME_deg (the form of
    every angle in a file, as the writer takes its columns: _file_columns)."""
    if not any(name in angles for name in rows.dtype.names or ()):
        return rows
    columns = _file_columns(rows, angles)
    out = np.empty(len(rows), np.dtype([(name, values.dtype, values.shape[1:])
                                        for name, values in columns.items()]))
    for name, values in columns.items():
        out[name] = values
    return out


def _file_columns(rows: np.ndarray, angles: Sequence[str]) -> dict[str, np.ndarray]:
    """Each column of rows as a file has it: contiguous, the columns of ``angles`` in
    degrees as NAME_deg (the form of every angle in a file)."""
    columns = {}
    for name in rows.dtype.names:
        if name in angles:
            columns[f"{name}_deg"] = np.degrees(rows[name])
        else:
            columns[name] = np.ascontiguousarray(rows[name])
    return columns


def _rootless(rows: np.ndarray) -> np.ndarray:
    """The rows without a root (a sweep's failed or empty sets)."""
    if "kind" not in rows.dtype.names:
        return np.zeros(len(rows), dtype=bool)
    return rows["kind"] == NO_ROOT


def _arrow_table(pa: Any, columns: dict[str, np.ndarray], rootless: np.ndarray,
                 labels: Mapping[str, Sequence[str]]) -> Any:
    """File columns as a pyarrow table: coded columns as dictionary text, and where a row has
    no root (``rootless``), its kind, stability, damping and certified null."""
    arrays = {}
    for name, values in columns.items():
        if name in labels:
            codes = pa.array(values, mask=values == NO_ROOT, type=pa.int8())
            arrays[name] = pa.DictionaryArray.from_arrays(codes, pa.array(labels[name]))
        else:
            arrays[name] = pa.array(values, mask=rootless if name == "certified" else None)
    return pa.table(arrays)


def _text_column(values: np.ndarray, name: str, rootless: np.ndarray,
                 labels: Mapping[str, Sequence[str]]) -> np.ndarray:
    """One column's CSV fields (shortest round-trip floats)."""
    if name in labels:
        return np.array([f'"{label}"' for label in labels[name]] + [""])[values]
    if name == "certified":
        return np.where(rootless, "", np.where(values, "true", "false"))
    return values.astype(str)


def write(rows: np.ndarray | Iterable[np.ndarray], path: str | os.PathLike[str],
          labels: Mapping[str, Sequence[str]] = LABELS, angles: Sequence[str] = ANGLES) -> int:
    """Write a sweep's table (or the pieces of ``stream``) to ``path``: Parquet (``.parquet``,
    through pyarrow: ``pip install 'mechvib[sweep]'``) or CSV (``.csv``; through pyarrow
    where installed, else Python's own formatting). kind, stability and damping are written
    as text; on a row without a root they and certified are null (empty in CSV). Returns
    the number of rows written. Raises ValueError for another extension, a missing folder,
    or Parquet without pyarrow; the file appears only once it is complete. ``labels``: the
    coded columns and their text, for a table other than a sweep's (``codegen.runtime.branches``).
    The file's angles are in degrees: ``theta`` [rad] of the table is its ``theta_deg``, as
    is each column of ``angles`` (``angle_columns(library)``: theta and the angle parameters).
    CSV floats are shortest round-trip."""
    with Writer(path, labels, angles) as writer:
        for piece in [rows] if isinstance(rows, np.ndarray) else rows:
            writer.write(piece)
    return writer.rows
