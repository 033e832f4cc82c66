"""Joining the equilibria of neighbouring parameter values into branches (pure numpy).

Equilibria of one degree of freedom are points on the coordinate's line (or circle, where
the coordinate is periodic), and as a parameter moves they move continuously and do not
cross (two branches meet only where both end: a fold, or a pitchfork on a third). So the
equilibria of two neighbouring samples, each sorted by angle, correspond in order: where the
counts are equal, one to one (on a circle, up to a rotation, for a branch crossing the seam
at +-pi); where they differ, the longer list loses the roots whose removal lets the rest
move least. Every function here takes angles in radians.

Equilibria of n coordinates are points of the box of their ranges (a torus in the periodic
ones), and have no order: there each is matched to the one it continues by the least total
movement (an assignment), distances being Euclidean over the coordinates, each periodic one
the short way round. Which of the two a function works on its ``periodic`` says: a bool for
one coordinate (positions are numbers), a tuple of one bool per coordinate for several
(positions are arrays whose last axis holds the coordinates; ``periodicity`` makes it from
a library's SPEC).
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np


#: A coordinate's periodicity (bool), or each coordinate's (a tuple): see the docstring.
Periodic = bool | tuple[bool, ...]


def periodicity(spec: Any) -> Periodic:
    """A library's SPEC["periodic"] as the functions here take it: a bool for one coordinate,
    a tuple of bools for several (SPEC has a list)."""
    return tuple(bool(p) for p in spec) if isinstance(spec, (list, tuple)) else bool(spec)


def _difference(a: Any, b: Any, periodic: Periodic) -> np.ndarray:
    """a - b, each periodic coordinate the short way round."""
    d = np.asarray(a, dtype=np.float64) - b
    wrap = np.asarray(periodic, dtype=bool)
    if np.any(wrap):
        d = np.where(wrap, np.remainder(d + math.pi, 2 * math.pi) - math.pi, d)
    return d


def distance(a: Any, b: Any, periodic: Periodic) -> np.ndarray:
    """|a - b| [rad], the short way round the circle where the coordinate is periodic; for
    several coordinates the Euclidean norm over the last axis."""
    d = np.abs(_difference(a, b, periodic))
    return d if isinstance(periodic, bool) else np.sqrt(np.sum(d * d, axis=-1))


def mean_angle(a: Any, b: Any, periodic: Periodic) -> Any:
    """The angle halfway between a and b [rad] (on the short arc where periodic), in a's
    turn; for several coordinates the midpoint (an array), coordinate by coordinate."""
    if not isinstance(periodic, bool):
        a = np.asarray(a, dtype=np.float64)
        return a + _difference(b, a, periodic) / 2
    d = float(b - a)
    if periodic:
        d = math.remainder(d, 2 * math.pi)
    return a + d / 2


def between(x: Any, a: Any, b: Any, periodic: Periodic) -> bool:
    """Whether x lies strictly inside the short arc (or the interval) from a to b; for
    several coordinates, strictly inside the ball whose diameter is a-b (on a line, the
    same as the interval)."""
    if not isinstance(periodic, bool):
        middle = mean_angle(a, b, periodic)
        return bool(distance(x, middle, periodic) < distance(a, b, periodic) / 2)
    if not periodic:
        return min(a, b) < x < max(a, b)
    span = float(distance(a, b, True))
    return 0 < float(distance(x, a, True)) < span and float(distance(x, b, True)) < span


def rotations(before: np.ndarray, after: np.ndarray, periodic: bool) -> np.ndarray:
    """For steps with equal counts: ``before`` and ``after`` are (steps, n) sorted angles;
    returns the rotation s of each step such that after[:, j] continues before[:, (j + s) %
    n] with the least total movement (always 0 where the coordinate is not periodic, as
    order is kept)."""
    steps, n = before.shape
    if not periodic or n < 2:
        return np.zeros(steps, dtype=np.int64)
    cost = np.stack([distance(np.roll(before, -s, axis=1), after, True).sum(axis=1)
                     for s in range(n)], axis=1)
    return np.argmin(cost, axis=1)


def follow(before: np.ndarray, after: np.ndarray, periodic: Periodic) -> np.ndarray:
    """For steps with equal counts: ``before`` and ``after`` are (steps, count) sorted
    angles, or (steps, count, n) positions; returns (steps, count) indices, after[s, j]
    continuing before[s, index[s, j]]: a rotation of the order for one coordinate
    (``rotations``), the least total movement for several."""
    steps, count = before.shape[:2]
    if isinstance(periodic, bool):
        shift = rotations(before, after, periodic)
        return (np.arange(count) + shift[:, None]) % count
    d = distance(after[:, :, None, :], before[:, None, :, :], periodic)
    index = np.argmin(d, axis=2)
    # where each nearest one is another's, the sum of the least distances is the least sum
    unique = np.all(np.sort(index, axis=1) == np.arange(count), axis=1)
    for s in np.flatnonzero(~unique):
        index[s] = _assignment(d[s])
    return index


def align(before: np.ndarray, after: np.ndarray, periodic: Periodic) -> np.ndarray:
    """For each angle of ``after`` (sorted), the index of the angle of ``before`` (sorted)
    it continues, or -1 where it begins. Every angle of the shorter list is matched, in
    order (cyclic order where periodic), to the longer one, choosing the matching with the
    least total movement; the longer list's unmatched angles end (or begin) there. For
    several coordinates (positions (count, n)), the matching is any with the least total
    movement."""
    result = np.full(len(after), -1, dtype=np.int64)
    if len(before) == 0 or len(after) == 0:
        return result
    swapped = len(before) < len(after)
    longer, shorter = (after, before) if swapped else (before, after)
    if isinstance(periodic, bool):
        best: tuple[float, list[tuple[int, int]]] = (math.inf, [])
        for r in range(len(longer)) if periodic else [0]:
            order = np.roll(np.arange(len(longer)), -r)
            cost, pairs = _in_order(longer[order], shorter, periodic)
            if cost < best[0]:
                best = (cost, [(int(order[i]), j) for i, j in pairs])
    else:
        chosen = _assignment(distance(shorter[:, None, :], longer[None, :, :], periodic))
        best = (0.0, [(int(i), j) for j, i in enumerate(chosen)])
    for i, j in best[1]:   # i indexes longer, j shorter
        if swapped:
            result[i] = j
        else:
            result[j] = i
    return result


def _in_order(longer: np.ndarray, shorter: np.ndarray, periodic: bool
              ) -> tuple[float, list[tuple[int, int]]]:
    """The order-keeping matching of every ``shorter`` angle to a ``longer`` one with the
    least total movement (dynamic programming, skipping longer's extra angles): (cost,
    [(index in longer, index in shorter)])."""
    m, n = len(longer), len(shorter)
    d = distance(longer[:, None], shorter[None, :], periodic)
    cost = np.full((m + 1, n + 1), math.inf)
    cost[:, 0] = 0.0
    for i in range(1, m + 1):
        for j in range(1, min(i, n) + 1):
            cost[i, j] = min(cost[i - 1, j], cost[i - 1, j - 1] + d[i - 1, j - 1])
    pairs, i, j = [], m, n
    while j > 0:
        if cost[i, j] == cost[i - 1, j]:
            i -= 1
        else:
            pairs.append((i - 1, j - 1))
            i, j = i - 1, j - 1
    return float(cost[m, n]), pairs[::-1]


def _assignment(cost: np.ndarray) -> np.ndarray:
    """For each row of ``cost`` (rows <= columns), its column, distinct, with the least total
    cost: the Hungarian method with potentials, O(rows^2 columns)."""
    rows, columns = cost.shape
    c = cost.tolist()
    u, v = [0.0] * (rows + 1), [0.0] * (columns + 1)
    owner, way = [0] * (columns + 1), [0] * (columns + 1)   # owner[j]: row (1-based) of column j
    for i in range(1, rows + 1):
        owner[0], j0 = i, 0
        least, used = [math.inf] * (columns + 1), [False] * (columns + 1)
        while True:
            used[j0] = True
            i0, delta, j1 = owner[j0], math.inf, 0
            for j in range(1, columns + 1):
                if not used[j]:
                    reduced = c[i0 - 1][j - 1] - u[i0] - v[j]
                    if reduced < least[j]:
                        least[j], way[j] = reduced, j0
                    if least[j] < delta:
                        delta, j1 = least[j], j
            for j in range(columns + 1):
                if used[j]:
                    u[owner[j]] += delta
                    v[j] -= delta
                else:
                    least[j] -= delta
            j0 = j1
            if owner[j0] == 0:
                break
        while j0:   # the augmenting path, back to its start
            j1 = way[j0]
            owner[j0] = owner[j1]
            j0 = j1
    result = np.full(rows, -1, dtype=np.int64)
    for j in range(1, columns + 1):
        if owner[j]:
            result[owner[j] - 1] = j - 1
    return result


def labels(previous: np.ndarray) -> np.ndarray:
    """Branch numbers from links: ``previous[r]`` is the row that row r continues (an
    earlier row) or -1 where a branch begins. Branches are numbered 0, 1, ... in the order
    of their first rows."""
    head = np.where(previous < 0, np.arange(len(previous)), previous)
    while True:   # pointer jumping: every row reaches its branch's first row in log steps
        further = head[head]
        if np.array_equal(further, head):
            break
        head = further
    _, number = np.unique(head, return_inverse=True)
    return number.astype(np.int32)
