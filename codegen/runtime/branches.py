"""Equilibrium branches, every equilibrium followed as one parameter varies.

``branches(library, "F", 0, 200)`` samples the parameter at ``points`` evenly spaced values
(the others from the example, or ``base``), analyses every sample in batch (``sweep.sweep``:
threads, a progress callback), joins the declared mode's equilibria of neighbouring samples
into branches by continuity (``codegen.runtime.joining``), and then refines every event by bisection
on the parameter, all open brackets analysed together in one batch per halving:

* where the number of equilibria changes between two samples, the bracket keeps at one end
  the larger count: it closes on the value where those equilibria last exist. Two that end
  there and whose gap has shrunk to nothing (it goes as the square root of the distance to
  the fold) merge: a **fold** (a double root of G, K_EQ -> 0), or a **pitchfork** when a
  continuing branch lies between them. A branch that ends without meeting another (a limit
  position, the end of the angle's range, a singular state) is an **end**. The count is
  only as sharp as the analysis separates a close pair, so each fold is then polished where
  G and G' vanish together (``codegen.runtime.folds``);
* where a branch's stability changes between two samples, the bracket closes on the value
  where it does (K_EQ crossing zero on the middle branch of a pitchfork, say).

The result (``Branches``) holds every point (a structured array, a row per equilibrium per
sample and per refined end of a bracket, with its branch), and the events. Angles in
radians, the parameter in its own unit, everything else SI. ``Branches.write`` makes a CSV,
Parquet or JSON file (angles in degrees there); ``codegen.presentation.branches`` draws
the figure.

A mechanism with n coordinates goes the same way, its equilibria points of the box of its
ranges (``codegen.runtime.multibody``): a point's ``theta`` holds its n coordinates, its
``omega_n`` and ``zeta`` each mode's, and ``K`` is det K (-> 0 at a fold); equilibria are
joined by the least movement in coordinate space, and a fold is polished where G = 0 and
det K = 0 together (``folds.polish_multibody``). The code differs for n in three places
only: the rows of a sample (``_equilibria``), the polishing of a fold, and the columns of
a file (``_coordinates``).
"""
from __future__ import annotations

import json
import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import analysis, folds, joining, sweep
from .. import files
from ..errors import real_number
from .library import Library, ParameterSet, ParamsLike, params_shown

#: What happens at an event (see the module's docstring).
EVENTS = ("fold", "pitchfork", "end", "stability change")
#: What a row of the points is: a sample, or the refined end of an event's bracket.
POINTS = ("sample", *EVENTS)
#: The file columns holding codes, and their text.
LABELS = {"point": POINTS, "stability": analysis.STABILITY, "damping": analysis.DAMPING}

#: Values sampled when none is said.
DEFAULT_POINTS = 1001
#: A pair of ending branches merges when its gap at the refined end of the bracket is below
#: this fraction of its gap at the sample: a fold's gap goes as sqrt(distance to the fold),
#: so bisection shrinks it by orders of magnitude, while an end's stays as it was.
MERGE = 0.1
#: Bisection stops at this fraction of the sampled range's magnitude (the default tolerance).
RELATIVE_TOLERANCE = 1e-12

#: One point of a branch. value: the varied parameter [its unit]; theta [rad]; stability
#: and damping index analysis.STABILITY and DAMPING, point indexes POINTS; omega_n and zeta
#: real, NaN where K <= 0 (no real natural frequency) or M = 0; K, M, B SI. With n
#: coordinates a point has branch, point, value, theta (n: the coordinates [rad or m]),
#: stability (undecided where it could not be decided), omega_n and zeta (n: each mode's, NaN where
#: omega^2 <= 0) and K (det K).
POINT_DTYPE = np.dtype([
    ("branch", np.int32), ("point", np.int8), ("value", np.float64), ("theta", np.float64),
    ("certified", np.bool_), ("stability", np.int8), ("damping", np.int8),
    ("omega_n", np.float64), ("zeta", np.float64), ("K", np.float64), ("M", np.float64),
    ("B", np.float64)])
_COPIED = ("theta", "certified", "stability", "damping", "omega_n", "zeta", "K", "M", "B")


@dataclass(frozen=True)
class Event:
    """Where branches end, or one changes stability, located by bisection (a fold then
    polished where G = G' = 0). ``theta`` [rad] (``theta_deg`` in degrees): the angle where
    the pair meets (a fold: the double root; a pitchfork: the middle of the pair just
    before it merges), where the branch ends, or where it changes stability; ``K`` [N m]
    (per rad) there: -> 0 at a fold or a pitchfork. With n coordinates ``theta`` holds each
    coordinate [rad or m] and ``K`` is det K."""

    kind: str                      # one of EVENTS
    value: float                   # the parameter's value there [its unit], in the bracket
    bracket: tuple[float, float]   # the event lies between these values [its unit]
    theta: float | tuple[float, ...]   # [rad]; n coordinates: each one's
    K: float                       # K_EQ [N m]; n coordinates: det K
    branches: tuple[int, ...]      # the branches ending there (fold: the pair), or changing
    side: str = ""                 # "below" or "above": where the ending branches exist
    stability: tuple[str, str] = ("", "")  # a stability change: (below, above) the value

    @property
    def theta_deg(self) -> float | tuple[float, ...]:
        """theta [deg] (each coordinate's in degrees, for n coordinates)."""
        if isinstance(self.theta, tuple):
            return tuple(math.degrees(t) for t in self.theta)
        return math.degrees(self.theta)


@dataclass(frozen=True)
class Branches:
    """The equilibria of the declared mode as ``parameter`` varies over ``values``, joined
    into branches. ``points``: POINT_DTYPE rows (with n coordinates, vectors: see its
    note), by branch then value (angles in radians);
    ``events``: by value; ``statuses``: the C status of each sample (0 = OK; a failed
    sample has no points and the branches are joined across it)."""

    library: Library
    parameter: str
    values: np.ndarray
    statuses: np.ndarray
    base: ParameterSet             # the other parameters (SI); its own ``parameter`` unused
    method: str                    # the route: "polynomial" or "isolate"
    points: np.ndarray
    events: tuple[Event, ...]
    tolerance: float               # the bisection's width [the parameter's unit]

    @property
    def unit(self) -> str:
        """The unit of the varied parameter."""
        return self.library.UNITS[self.parameter]

    @property
    def count(self) -> int:
        """The number of branches."""
        return int(self.points["branch"].max()) + 1 if len(self.points) else 0

    def branch(self, number: int) -> np.ndarray:
        """The points of one branch, by value."""
        return self.points[self.points["branch"] == number]

    @property
    def folds(self) -> tuple[Event, ...]:
        """The folds: where two equilibria meet and vanish (a double root of G)."""
        return tuple(e for e in self.events if e.kind == "fold")

    @property
    def failed(self) -> np.ndarray:
        """The sampled values whose analysis failed (``statuses`` says why)."""
        return self.values[self.statuses != 0]

    def table(self) -> np.ndarray:
        """The points as a file writes them: the parameter's column under its name (or
        param_NAME where that is another column's; an angle in degrees as NAME_deg, as every
        angle of a file), ``theta_deg`` in degrees. With n coordinates: each coordinate
        under its name (an angle as NAME_deg, in degrees), omega_n_j and zeta_j of each
        mode j, K det K."""
        columns: dict[str, np.ndarray] = {}
        for n in self.points.dtype.names:
            values = self.points[n]
            if n == "theta":
                columns.update(_coordinates(self.library, values))
            elif values.ndim == 2:   # each mode's
                columns.update({f"{n}_{j + 1}": values[:, j] for j in range(values.shape[1])})
            else:
                columns[n] = values
        angle = self.library.UNITS.get(self.parameter) == "rad"
        column = f"{self.parameter}_deg" if angle else self.parameter
        if column in (*self.points.dtype.names, *columns):
            column = f"param_{column}"
        value = self.points["value"]
        columns = {(column if n == "value" else n): (np.degrees(value) if angle and n == "value"
                                                     else v) for n, v in columns.items()}
        out = np.empty(len(self.points), np.dtype([(n, v.dtype) for n, v in columns.items()]))
        for name, values in columns.items():
            out[name] = values
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the setting, the branches, the events and every point; angles in
        degrees (keys ending in _deg), the parameter in its unit, the rest SI, NaN as null."""
        ranges = []
        for number in range(self.count):
            own = self.branch(number)
            ranges.append({"branch": number, "from": float(own["value"][0]),
                           "to": float(own["value"][-1]), "points": len(own),
                           "stability": [analysis.STABILITY[s] for s in np.unique(
                               own["stability"])]})
        names = {v: k for k, v in self.library.STATUS.items()}
        return {
            "mechanism": self.library.PREFIX, "title": self.library.TITLE,
            "parameter": self.parameter, "unit": self.unit, "method": self.method,
            "from": float(self.values[0]), "to": float(self.values[-1]),
            "samples": len(self.values), "tolerance": self.tolerance,
            "params": params_shown({k: v for k, v in vars(self.base).items()
                                    if k != self.parameter}, self.library.UNITS),
            "failed": [{"value": float(v), "status": names.get(int(s), int(s))}
                       for v, s in zip(self.values, self.statuses) if s != 0],
            "branches": ranges,
            "events": [{"kind": e.kind, "value": e.value, "bracket": list(e.bracket),
                        **{k: float(v[0]) for k, v in _coordinates(
                            self.library, np.array([e.theta])).items()},
                        "K": _finite(e.K),
                        "branches": list(e.branches), "side": e.side or None,
                        "stability": list(e.stability) if e.stability[0] else None}
                       for e in self.events],
            "rows": _records(self.table()),
        }

    def write(self, path: str | os.PathLike[str]) -> int:
        """Write the points to ``path``: .csv or .parquet (as ``sweep.write``: text labels,
        Parquet through pyarrow) or .json (``to_dict``). Returns the rows written. Raises
        ValueError for another extension or a missing folder."""
        path = check_table_path(path)
        if path.suffix.lower() != ".json":
            return sweep.write(self.table(), path, labels=LABELS)
        files.write_text(path, json.dumps(self.to_dict(), indent=1) + "\n")
        return len(self.points)


def check_table_path(path: str | os.PathLike[str]) -> Path:
    """``path`` as a Path if a table can be written there (.csv, .json or .parquet, in an
    existing folder); ValueError otherwise."""
    path = Path(path)
    if path.suffix.lower() not in (*sweep.FORMATS, ".json"):
        raise ValueError(f"{path}: the table is written as .csv, .json or .parquet")
    if not path.parent.is_dir():
        raise ValueError(f"{path}: no folder {path.parent}")
    return path


def _coordinates(library: Library, theta: np.ndarray) -> dict[str, np.ndarray]:
    """The columns of a file holding the coordinates of points (``theta``: one value a
    point, or n), angles in degrees: theta_deg for one coordinate; for n, each under its
    name (an angle as NAME_deg)."""
    if library.dof == 1:
        return {"theta_deg": np.degrees(theta)}
    return {(f"{c['name']}_deg" if c["unit"] == "rad" else c["name"]):
            (np.degrees(theta[:, k]) if c["unit"] == "rad" else theta[:, k])
            for k, c in enumerate(library.SPEC["coordinates"])}


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _records(table: np.ndarray) -> list[dict[str, Any]]:
    """Rows as dicts: codes as their text, NaN as None."""
    columns = {}
    for name in table.dtype.names:
        values = table[name].tolist()
        if name in LABELS:
            columns[name] = [LABELS[name][v] for v in values]
        elif table.dtype[name].kind == "f":
            columns[name] = [v if math.isfinite(v) else None for v in values]
        else:
            columns[name] = values
    return [dict(zip(columns, row)) for row in zip(*columns.values())]


# ------------------------------------------------------------------------ the samples

#: Two ending branches whose angles at the refined end are closer than this [rad] meet,
#: whatever their gap at the sample (the polynomial route separates roots ~2e-5 rad apart).
MEETING = 1e-4


@dataclass
class _Samples:
    """The successful samples' equilibria as flat arrays: ``rows`` (sweep rows, by sample
    then angle) and ``value`` (each row's parameter value); per successful sample, its
    value ``at``, its ``first`` row and its ``count`` of rows."""

    rows: np.ndarray
    value: np.ndarray
    at: np.ndarray
    first: np.ndarray
    count: np.ndarray


def _equilibria(library: Library, rows: np.ndarray) -> np.ndarray:
    """The sweep rows (``sweep.sweep``, ``sweep.analyze_chunk``) that are equilibria, as the
    branches take them: for one coordinate, the rows themselves; for n, rows of their set,
    status, coordinates (one vector theta), stability, each mode's omega_n and zeta (one
    vector each) and K = det K (the library's stiffness matrix there)."""
    if library.dof == 1:
        return rows[rows["kind"] != sweep.NO_ROOT]
    n = library.dof
    theta = np.stack([rows[c["name"]] for c in library.SPEC["coordinates"]], axis=-1)
    found = np.all(np.isfinite(theta), axis=1) & (rows["status"] == 0)
    rows, theta = rows[found], theta[found]
    out = np.empty(len(rows), np.dtype([
        ("set", np.int64), ("status", np.int32), ("theta", np.float64, (n,)),
        ("stability", np.int8), ("omega_n", np.float64, (n,)), ("zeta", np.float64, (n,)),
        ("K", np.float64)]))
    out["set"], out["status"], out["theta"] = rows["set"], rows["status"], theta
    out["stability"] = rows["stability"]
    for name in ("omega_n", "zeta"):
        out[name] = np.stack([rows[f"{name}_{j + 1}"] for j in range(n)], axis=-1)
    if len(rows):
        params = np.empty(len(rows), library.PARAMS_DTYPE)
        for name, column in zip(library.PARAMETER_NAMES, sweep.parameter_columns(library)):
            params[name] = rows[column]
        K = np.asarray(library.stiffness_matrix.batch(params, theta), dtype=np.float64)
        out["K"] = np.linalg.det(K.reshape(len(rows), n, n))
    return out


def _sample(library: Library, table: np.ndarray, values: np.ndarray,
            method: analysis.Method, workers: int | None,
            progress: sweep.Progress | None) -> tuple[_Samples, np.ndarray]:
    """Every sample analysed: (the successful samples, each sample's status)."""
    chunk = max(4096, -(-len(table) // 20))   # about 20 progress steps on long sweeps
    rows = sweep.sweep(library, table, method=method, workers=workers, chunk=chunk,
                       progress=progress)
    statuses = np.zeros(len(table), dtype=np.int32)
    statuses[rows["set"]] = rows["status"]
    ok = statuses == 0
    found = _equilibria(library, rows)
    found = found[ok[found["set"]]]
    count = np.bincount(found["set"], minlength=len(table))[ok]
    first = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64)
    return _Samples(found, values[found["set"]], values[ok], first, count), statuses


class _Analyser:
    """The declared mode's equilibria at given values of the parameter, the others fixed.
    One thread: a round of bisection is a handful of sets, fewer than a thread pool costs."""

    def __init__(self, library: Library, base: np.ndarray, parameter: str,
                 method: analysis.Method) -> None:
        self.library, self.base, self.parameter, self.method = library, base, parameter, method

    def __call__(self, values: list[float]) -> list[np.ndarray | None]:
        """Per value, its equilibria (``_equilibria`` rows, by angle), or None where it
        failed."""
        table = np.repeat(self.base, len(values))
        table[self.parameter] = values
        rows = sweep.analyze_chunk(self.library, table, 0, self.method, "equilibria")
        statuses = np.zeros(len(values), dtype=np.int32)
        statuses[rows["set"]] = rows["status"]
        found = _equilibria(self.library, rows)
        pieces = np.split(found, np.searchsorted(found["set"], np.arange(1, len(values))))
        return [None if status != 0 else piece for status, piece in zip(statuses, pieces)]


# ------------------------------------------------------------------------ joining

@dataclass
class _Change:
    """A step between samples k and k + 1 where the number of equilibria changes: the rows
    (of the sample with more) that end or begin there."""

    step: int
    ending: np.ndarray


def _link(samples: _Samples, periodic: joining.Periodic) -> tuple[np.ndarray, list[_Change]]:
    """(previous: for each row the row it continues, or -1; the count changes)."""
    theta, first, count = samples.rows["theta"], samples.first, samples.count
    previous = np.full(len(theta), -1, dtype=np.int64)
    left, right = count[:-1], count[1:]
    equal = (left == right) & (left > 0)
    for n in np.unique(left[equal]):   # steps alike in count at once
        steps = np.flatnonzero(equal & (left == n))
        j = np.arange(n)
        before = first[steps][:, None] + j
        after = first[steps + 1][:, None] + j
        index = joining.follow(theta[before], theta[after], periodic)
        previous[after] = first[steps][:, None] + index
    changes = []
    for k in np.flatnonzero(left != right):
        a = slice(first[k], first[k] + count[k])
        b = slice(first[k + 1], first[k + 1] + count[k + 1])
        link = joining.align(theta[a], theta[b], periodic)
        continuing = np.flatnonzero(link >= 0)
        previous[b.start + continuing] = a.start + link[continuing]
        if count[k] > count[k + 1]:
            ending = np.setdiff1d(np.arange(a.start, a.stop), a.start + link[continuing])
        else:
            ending = b.start + np.flatnonzero(link < 0)
        changes.append(_Change(int(k), ending))
    return previous, changes


# ------------------------------------------------------------------------ refinement

@dataclass
class _CountBracket:
    """Closes on where the equilibria at one end (``kept``, at the end ``keep_low`` names)
    stop being as many."""

    lo: float
    hi: float
    keep_low: bool
    kept: np.ndarray

    def settled(self, tolerance: float) -> bool:
        middle = (self.lo + self.hi) / 2
        return self.hi - self.lo <= tolerance or not self.lo < middle < self.hi

    def update(self, value: float, found: np.ndarray | None) -> None:
        same = found is not None and len(found) == len(self.kept)
        if same:
            self.kept = found
        if same == self.keep_low:
            self.lo = value
        else:
            self.hi = value

    @property
    def kept_value(self) -> float:
        return self.lo if self.keep_low else self.hi


@dataclass
class _StabilityBracket:
    """Closes on where one branch (``low`` at lo, ``high`` at hi: its points) changes
    stability, following it by angle."""

    lo: float
    hi: float
    low: np.void
    high: np.void
    periodic: joining.Periodic
    lost: bool = False   # a midpoint without equilibria: stop there

    def settled(self, tolerance: float) -> bool:
        middle = (self.lo + self.hi) / 2
        return self.lost or self.hi - self.lo <= tolerance or not self.lo < middle < self.hi

    def update(self, value: float, found: np.ndarray | None) -> None:
        if found is None or len(found) == 0:
            self.lost = True
            return
        near = joining.mean_angle(self.low["theta"], self.high["theta"], self.periodic)
        row = found[np.argmin(joining.distance(found["theta"], near, self.periodic))]
        if row["stability"] == self.low["stability"]:
            self.lo, self.low = value, row
        else:
            self.hi, self.high = value, row


def _refine(brackets: list[Any], analyse: _Analyser, tolerance: float) -> None:
    """Halve every open bracket until each is settled, all midpoints in one batch a round."""
    while True:
        open_ = [b for b in brackets if not b.settled(tolerance)]
        if not open_:
            return
        middles = [(b.lo + b.hi) / 2 for b in open_]
        for bracket, value, found in zip(open_, middles, analyse(middles)):
            bracket.update(value, found)


# ------------------------------------------------------------------------ events

def _points(rows: np.ndarray, value: np.ndarray | float, branch: np.ndarray | int,
            point: str) -> np.ndarray:
    """Points (POINT_DTYPE for one coordinate) from ``_equilibria`` rows."""
    copied = [name for name in _COPIED if name in rows.dtype.names]
    out = np.empty(len(rows), np.dtype([(name, POINT_DTYPE[name]) for name in
                                        ("branch", "point", "value")]
                                       + [(name, rows.dtype[name]) for name in copied]))
    out["branch"], out["point"], out["value"] = branch, POINTS.index(point), value
    for name in copied:
        out[name] = rows[name]
    return out


def _position(x: Any) -> float | tuple[float, ...]:
    """An equilibrium's position as an Event holds it: a float, or n floats."""
    x = np.asarray(x, dtype=np.float64)
    return float(x) if x.ndim == 0 else tuple(float(v) for v in x)


def _pairs(ends: list[int], theta_at: Callable[[int], Any],
           gap_before: Callable[[int, int], float], periodic: joining.Periodic
           ) -> list[tuple[int, int]]:
    """Ending equilibria that meet, in pairs, the closest first: their gap at the refined
    end is tiny, or small beside their gap at the sample. Each pair in the order of
    ``ends`` (by angle; on a circle, the one the other lies ahead of the short way)."""
    def gap(a: int, b: int) -> float:
        return float(joining.distance(theta_at(a), theta_at(b), periodic))

    meeting = []
    for i, a in enumerate(ends):
        for k in range(i + 1, len(ends)):
            apart = gap(a, ends[k])
            if apart <= MEETING or apart <= MERGE * gap_before(a, ends[k]):
                meeting.append((apart, i, k))
    meeting.sort()
    pairs: list[tuple[int, int]] = []
    taken: set[int] = set()
    for _, i, k in meeting:
        if i in taken or k in taken:
            continue
        taken |= {i, k}
        a, b = ends[i], ends[k]
        wraps = periodic is True and float(theta_at(b)) - float(theta_at(a)) > math.pi
        pairs.append((b, a) if wraps else (a, b))
    return pairs


#: Polishes a fold: (start, the pair's positions, direction, first step, reach) -> a Fold.
Polisher = Callable[[float, tuple[Any, Any], int, float, float], "folds.Fold | None"]


def _change_events(change: _Change, bracket: _CountBracket, samples: _Samples,
                   branch: np.ndarray, periodic: joining.Periodic, polish: Polisher
                   ) -> tuple[list[Event], list[np.ndarray]]:
    """The folds, pitchforks and ends of one change of count, and their refined points: the
    points where the pairs last exist, and each fold polished where G and G' vanish."""
    side = samples.first[change.step + (0 if bracket.keep_low else 1)]
    grid = samples.rows[side:side + len(bracket.kept)]
    # kept[i] is grid[i] followed to the refined end (equal counts: a one-to-one matching)
    kept = bracket.kept[joining.align(bracket.kept["theta"], grid["theta"], periodic)]
    ends = sorted(int(r - side) for r in change.ending)
    span = (bracket.lo, bracket.hi)
    where = "below" if bracket.keep_low else "above"
    events, points = [], []

    def gap_before(a: int, b: int) -> float:
        return float(joining.distance(grid["theta"][a], grid["theta"][b], periodic))

    pairs = _pairs(ends, lambda i: kept["theta"][i], gap_before, periodic)
    paired = {i for pair in pairs for i in pair}
    for a, b in pairs:
        ta, tb = kept["theta"][a], kept["theta"][b]
        inside = any(joining.between(kept["theta"][i], ta, tb, periodic)
                     for i in range(len(kept)) if i not in (a, b))
        kind = "pitchfork" if inside else "fold"
        numbers = tuple(sorted(int(branch[side + i]) for i in (a, b)))
        fold = None if inside else polish(
            bracket.kept_value, (ta, ta + 2 * (joining.mean_angle(ta, tb, periodic) - ta)),
            1 if bracket.keep_low else -1, span[1] - span[0],
            float(samples.at[change.step + 1] - samples.at[change.step]))
        if fold is None:   # a pitchfork, or polishing failed: the bisection's bracket
            events.append(Event(kind, sum(span) / 2, span,
                                _position(joining.mean_angle(ta, tb, periodic)),
                                float(kept["K"][a] + kept["K"][b]) / 2, numbers, where))
        else:
            events.append(Event(kind, fold.value, fold.bracket, fold.theta, fold.K, numbers,
                                where))
        points.append(_points(kept[[a, b]], bracket.kept_value,
                              branch[side + np.array([a, b])], kind))
    for i in (i for i in ends if i not in paired):
        events.append(Event("end", sum(span) / 2, span, _position(kept["theta"][i]),
                            float(kept["K"][i]), (int(branch[side + i]),), where))
        points.append(_points(kept[[i]], bracket.kept_value, branch[side + i], "end"))
    return events, points


def _stability_event(bracket: _StabilityBracket, number: int) -> tuple[Event, np.ndarray]:
    """A stability change of branch ``number`` and the points on either side of it."""
    low, high = bracket.low, bracket.high
    event = Event("stability change", (bracket.lo + bracket.hi) / 2, (bracket.lo, bracket.hi),
                  _position(joining.mean_angle(low["theta"], high["theta"], bracket.periodic)),
                  float(low["K"] + high["K"]) / 2, (number,),
                  stability=(analysis.STABILITY[low["stability"]],
                             analysis.STABILITY[high["stability"]]))
    rows = np.array([low, high], dtype=low.dtype)
    return event, _points(rows, np.array([bracket.lo, bracket.hi]), number, "stability change")


# ------------------------------------------------------------------------ the whole

def _check(library: Library, parameter: str, start: float, stop: float, points: int) -> None:
    if parameter not in library.PARAMETER_NAMES:
        raise ValueError(f"unknown parameter {parameter!r}; {library.PREFIX} has "
                         f"{', '.join(library.PARAMETER_NAMES)}")
    start, stop = real_number("from", start), real_number("to", stop)
    if not (math.isfinite(start) and math.isfinite(stop) and start < stop):
        raise ValueError(f"{parameter}: the range needs finite from < to, not from {start:g} "
                         f"to {stop:g}")
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or points < 2:
        raise ValueError(f"points must be an integer of at least 2, not {points!r}")


def _tolerance(tolerance: float | None, start: float, stop: float, points: int) -> float:
    """The bisection's width: the default, or one that is positive, finite and below the
    samples' spacing (a wider one would settle every bracket untouched: no event located)."""
    if tolerance is None:
        return RELATIVE_TOLERANCE * max(abs(start), abs(stop), stop - start)
    spacing = (stop - start) / (points - 1)
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float, np.floating)) \
            or not 0 < tolerance < spacing:
        raise ValueError(f"tolerance: must be positive and below the samples' spacing "
                         f"({spacing:g}), not {tolerance!r}")
    return float(tolerance)


def branches(library: Library, parameter: str, start: float, stop: float,
             points: int = DEFAULT_POINTS, *, base: ParamsLike | None = None,
             method: analysis.Method = "auto", workers: int | None = None,
             progress: sweep.Progress | None = None, tolerance: float | None = None
             ) -> Branches:
    """The declared mode's equilibria as ``parameter`` runs from ``start`` to ``stop`` (its
    unit) over ``points`` evenly spaced values, joined into branches, with every fold,
    pitchfork, branch end and stability change located to ``tolerance`` in the parameter
    (default 1e-12 of the range's magnitude) by bisection. Other parameters: ``base`` (a
    parameter set, or a mapping of some over the example; default the example). ``method``:
    the analysis route; ``workers``: threads (default every CPU); ``progress(done, total)``
    is called as the samples are analysed (the CLI draws a progress bar with it). Angles in radians.

    Raises ValueError for an unknown parameter or method, a range with from >= to, fewer
    than 2 points, or when every sample fails (the LibraryError of the first).
    """
    _check(library, parameter, start, stop, points)
    taken = analysis.route(library, method)
    values = np.linspace(start, stop, points)
    table = sweep.grid(library, {parameter: values}, base)
    samples, statuses = _sample(library, table, values, taken, workers, progress)
    if not np.any(statuses == 0):
        library.check(int(statuses[0]), dict(zip(library.PARAMETER_NAMES, table[0].tolist())))
    periodic = joining.periodicity(library.SPEC["periodic"])
    previous, changes = _link(samples, periodic)
    branch = joining.labels(previous)
    tolerance = _tolerance(tolerance, start, stop, points)
    changes_at = [_count_bracket(samples, c) for c in changes]
    rows = samples.rows
    turned = np.flatnonzero((previous >= 0) & (rows["stability"] != rows["stability"][previous]))
    turns = [_StabilityBracket(float(samples.value[previous[r]]), float(samples.value[r]),
                               rows[previous[r]], rows[r], periodic) for r in turned]
    analyse = _Analyser(library, table[:1], parameter, taken)
    _refine([*changes_at, *turns], analyse, tolerance)
    events, extra = [], [_points(rows, samples.value, branch, "sample")]
    base_values = dict(zip(library.PARAMETER_NAMES, table[0].tolist()))

    polisher = folds.polish if library.dof == 1 else folds.polish_multibody

    def polish(start: float, pair: tuple[Any, Any], direction: int, first: float,
               reach: float) -> folds.Fold | None:
        return polisher(library, base_values, parameter, start, pair, direction, first,
                        reach, tolerance)

    for change, bracket in zip(changes, changes_at):
        found, refined = _change_events(change, bracket, samples, branch, periodic, polish)
        events += found
        extra += refined
    for r, bracket in zip(turned, turns):
        event, refined = _stability_event(bracket, int(branch[r]))
        events.append(event)
        extra.append(refined)
    every = np.concatenate(extra)
    every = every[np.lexsort((every["value"], every["branch"]))]
    return Branches(library, parameter, values, statuses, library.Params(**base_values), taken,
                    every, tuple(sorted(events, key=lambda e: (e.value, e.branches))),
                    tolerance)


def _count_bracket(samples: _Samples, change: _Change) -> _CountBracket:
    """The bracket of a change of count, keeping the end with more equilibria."""
    k = change.step
    keep_low = bool(samples.count[k] > samples.count[k + 1])
    side = k if keep_low else k + 1
    first = samples.first[side]
    kept = samples.rows[first:first + samples.count[side]]
    return _CountBracket(float(samples.at[k]), float(samples.at[k + 1]), keep_low, kept)
