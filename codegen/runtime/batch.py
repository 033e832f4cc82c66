"""The analysis of many parameter sets as numpy arrays, over threads.

``analyze_table(table, library)`` runs the C batch entry point of the chosen route over a
``params_array`` and returns one structured array row per root, with the index of its set:
no Python object is made per set or per root. The C results are read in place through a
numpy dtype laid out from cffi's description of the C structs. ``workers=N`` splits the
table into N contiguous chunks run on N threads: cffi releases the GIL around each C call and
the library has no shared state, so the chunks run in parallel and the result is the same
for any N. A mechanism with several coordinates runs the same way, its rows those of
``codegen.runtime.multibody`` (``form`` tells the two apart, once).
"""
from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from . import analysis, multibody
from .library import Library

#: One root of one parameter set. Angles [rad]; kind, stability and damping index
#: analysis.KINDS, STABILITY and DAMPING; omega_n and zeta complex where K < 0.
#: The stability and damping codes of a root that is no equilibrium (an extraneous root).
NOT_CLASSIFIED = -1
#: The mode of a root whose state the model's assembly-mode conditions place in no mode.
UNDECIDED_MODE = -1
#: The kind codes of an equilibrium of the declared assembly mode and of an extraneous root.
EQUILIBRIUM = analysis.KINDS.index("equilibrium")
EXTRANEOUS = analysis.KINDS.index(analysis.NOT_AN_EQUILIBRIUM)

ROOT_DTYPE = np.dtype([
    ("set", np.int64), ("theta", np.float64), ("theta_lo", np.float64),
    ("theta_hi", np.float64), ("certified", np.bool_), ("kind", np.int8), ("mode", np.int16),
    ("residual", np.float64), ("relative_residual", np.float64),
    ("M", np.float64), ("B", np.float64), ("K", np.float64),
    ("omega_n", np.complex128), ("zeta", np.complex128), ("eigenvalues", np.complex128, (2,)),
    ("stability", np.int8), ("damping", np.int8)])


@dataclass(frozen=True)
class Table:
    """The analysis of n parameter sets: ``roots`` (ROOT_DTYPE rows, ordered by set, then
    by angle; with several coordinates ``multibody.roots_dtype``'s, a row per proven
    equilibrium ordered by set, then by its coordinates), ``statuses`` (the C status of each
    set, 0 = OK; a failed set has no rows), ``counts`` (rows per set) and the route taken."""

    roots: np.ndarray
    statuses: np.ndarray
    counts: np.ndarray
    method: str
    #: With several coordinates, the number of boxes of each set that double precision could
    #: not decide (never rows: see codegen.runtime.multibody); None with one coordinate.
    uncertain: np.ndarray | None = None

    @property
    def equilibria(self) -> np.ndarray:
        """The rows that are equilibria of the declared assembly mode."""
        return self.roots[self.roots["kind"] == EQUILIBRIUM]


def _numpy_type(ffi, ctype) -> np.dtype:
    """The numpy dtype of a C type, laid out at cffi's offsets (structs nest)."""
    if ctype.kind == "array":
        return np.dtype((_numpy_type(ffi, ctype.item), (ctype.length,)))
    if ctype.kind == "struct":
        fields = ctype.fields
        return np.dtype({"names": [n for n, _ in fields],
                         "formats": [_numpy_type(ffi, f.type) for _, f in fields],
                         "offsets": [f.offset for _, f in fields],
                         "itemsize": ffi.sizeof(ctype)})
    if ctype.kind == "enum" or ctype.cname in ("int", "unsigned int"):
        return np.dtype(f"{'u' if ctype.cname == 'unsigned int' else 'i'}{ffi.sizeof(ctype)}")
    if ctype.cname == "double":
        return np.dtype(np.float64)
    raise TypeError(f"no numpy type for {ctype.cname}")


@lru_cache(maxsize=None)
def _analysis_dtype(library: Library) -> np.dtype:
    ffi = library.ffi
    return _numpy_type(ffi, ffi.typeof(f"{library.PREFIX}_analysis"))


#: Sets analysed per C call: the C results of a block (a few kB a set) are read into
#: rows and the buffer reused, so memory follows the number of roots, not of sets.
BLOCK = 1024


def c_roots(library: Library, c: np.ndarray, statuses: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The roots of a block of C results as the C structs (a copy, in set order, then angle),
    the index of each one's set in the block, and the number of roots of each set (0 for a
    set that failed)."""
    counts = np.where(statuses == library.STATUS["OK"], c["n_roots"], 0)
    slots = c["roots"]
    mask = np.arange(slots.shape[1]) < counts[:, None]
    # Gathered as opaque records (one copy each), then seen as the C struct again: numpy
    # gathers a struct with padding field by field, five times slower.
    found = slots.view(np.dtype((np.void, slots.dtype.itemsize)))[mask].view(slots.dtype)
    return found, np.nonzero(mask)[0], counts


def _rows(library: Library, c: np.ndarray, statuses: np.ndarray, first: int
          ) -> tuple[np.ndarray, np.ndarray, None]:
    """The ROOT_DTYPE rows of a block of C results (sets first, first + 1, ...), the
    number of rows of each set, and None (no count of undecided intervals)."""
    found, sets, counts = c_roots(library, c, statuses)
    rows = np.empty(len(found), dtype=ROOT_DTYPE)
    rows["set"] = sets + first
    for name in ("theta", "theta_lo", "theta_hi", "residual", "M", "B", "K", "kind"):
        rows[name] = found[name]
    extraneous = found["kind"] == EXTRANEOUS
    for name in ("stability", "damping"):   # an extraneous root is no equilibrium: no code
        rows[name] = np.where(extraneous, NOT_CLASSIFIED, found[name])
    rows["certified"] = found["certified"] != 0
    rows["mode"] = np.where(found["mode"] < library.modes, found["mode"], UNDECIDED_MODE)
    scale = found["residual_scale"]
    with np.errstate(divide="ignore", invalid="ignore"):
        rows["relative_residual"] = np.where(scale != 0, np.abs(found["residual"]) / scale, 0.0)
    rows["omega_n"] = found["omega_n"][:, 0] + 1j * found["omega_n"][:, 1]
    rows["zeta"] = found["zeta"][:, 0] + 1j * found["zeta"][:, 1]
    rows["eigenvalues"] = found["eigen_re"] + 1j * found["eigen_im"]
    return rows, counts, None


@dataclass(frozen=True)
class Form:
    """How the sets of a library are analysed in batches, by its number of coordinates:
    ``route(library, method)`` (the route a method name takes, or ValueError), ``entry(
    library, route)`` (the C batch entry), ``rows(library, c, statuses, first)`` (a block of
    C results as ``analyze_table`` rows, their count per set, and per set the boxes not
    decided or None)."""

    route: Callable[[Library, str], str]
    entry: Callable[[Library, str], Any]
    rows: Callable[[Library, np.ndarray, np.ndarray, int],
                   tuple[np.ndarray, np.ndarray, np.ndarray | None]]


ONE_COORDINATE = Form(analysis.route, lambda library, route: analysis.entry(library, route, True),
                      _rows)
SEVERAL_COORDINATES = Form(analysis.route,
                           lambda library, route: analysis.entry(library, route, True),
                           multibody.table_rows)


def form(library: Library) -> Form:
    """The batch analysis of ``library``'s sets: the one place in this module where it
    depends on the number of coordinates."""
    return SEVERAL_COORDINATES if library.dof > 1 else ONE_COORDINATE


def route(library: Library, method: str = "auto") -> str:
    """The route ``method`` takes for ``library`` ("polynomial" or "isolate"); ValueError
    for an unknown method or one the library does not have."""
    return form(library).route(library, method)


#: What a block of C results becomes: (the block's C results as the analysis dtype, their
#: statuses, the index of the block's first set in the table) -> anything.
BlockRows = Callable[[np.ndarray, np.ndarray, int], Any]


def _analyze_range(library: Library, method: str, table: np.ndarray, statuses: np.ndarray,
                   start: int, stop: int, make: BlockRows) -> list[Any]:
    """Sets start..stop-1 in blocks through one reused C results buffer (one per thread),
    each block made into rows by ``make`` on this thread."""
    ffi, P = library.ffi, library.PREFIX
    entry = form(library).entry(library, method)
    results = ffi.new(f"{P}_analysis[]", min(BLOCK, max(stop - start, 1)))
    view = np.frombuffer(ffi.buffer(results), dtype=_analysis_dtype(library))
    c_params = ffi.from_buffer(f"{P}_params[]", table)
    c_statuses = ffi.from_buffer(f"{P}_status[]", statuses, require_writable=True)
    blocks = []
    for first in range(start, stop, BLOCK):
        n = min(BLOCK, stop - first)
        entry(n, c_params + first, results, c_statuses + first)
        blocks.append(make(view[:n], statuses[first:first + n], first))
    return blocks


def analyze_blocks(table: np.ndarray, library: Library, make: BlockRows, method: str = "auto",
                   workers: int = 1) -> tuple[list[Any], np.ndarray, str]:
    """The C analysis of every set of ``table`` (a params_array), by the route ``method``
    names, block by block (BLOCK sets), each block's results made into rows by ``make`` on
    the thread that analysed it: (the blocks' rows in table order, each set's status, the
    route taken). ``workers`` threads share the work, each a contiguous part of the table."""
    if not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer, not {workers!r}")
    taken = route(library, method)
    table = library.table(table)
    statuses = np.zeros(len(table), dtype=np.intc)
    bounds = np.linspace(0, len(table), min(workers, max(len(table), 1)) + 1).astype(int)
    parts = [(int(lo), int(hi)) for lo, hi in zip(bounds[:-1], bounds[1:])]

    def run(part: tuple[int, int]) -> list[Any]:
        return _analyze_range(library, taken, table, statuses, *part, make)

    if len(parts) == 1:
        blocks = run(parts[0])
    else:
        with ThreadPoolExecutor(len(parts)) as pool:
            blocks = [b for part in pool.map(run, parts) for b in part]
    return blocks, statuses, taken


def analyze_table(table: np.ndarray, library: Library, method: str = "auto",
                  workers: int = 1) -> Table:
    """Every root of every parameter set of ``table`` (a params_array), by the route
    ``method`` names, as numpy arrays (see Table); ``workers`` threads share the work, each
    a contiguous part of the table. With several coordinates, every proven equilibrium (one
    route, the isolation: "auto" or "isolate"), its coordinates in arrays of n."""
    shape = form(library)
    blocks, statuses, taken = analyze_blocks(
        table, library, lambda c, st, first: shape.rows(library, c, st, first), method, workers)
    if not blocks:   # no sets: the rows of an empty block, of the right types
        blocks = [shape.rows(library, np.empty(0, _analysis_dtype(library)),
                             np.empty(0, np.intc), 0)]
    rows, counts, uncertain = (list(part) for part in zip(*blocks))
    return Table(np.concatenate(rows), statuses, np.concatenate(counts).astype(np.int64),
                 taken, None if uncertain[0] is None
                 else np.concatenate(uncertain).astype(np.int64))
