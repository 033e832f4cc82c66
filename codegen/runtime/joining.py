"""Joining the equilibria of neighbouring parameter values into branches (pure numpy).

Equilibria of one degree of freedom are points on the coordinate's line (or circle, where
the coordinate is periodic), and as a parameter moves they move continuously and do not
cross (two branches meet only where both end: a fold, or a pitchfork on a third). So the
equilibria of two neighbouring samples, each sorted by angle, correspond in order: where the
counts are equal, one to one (on a circle, up to a rotation, for a branch crossing the seam
at +-pi); where they differ, the longer list loses the roots whose removal lets the rest
move least. Every function here takes angles in radians.
"""
from __future__ import annotations

import math

import numpy as np


def distance(a: np.ndarray | float, b: np.ndarray | float, periodic: bool) -> np.ndarray:
    """|a - b| [rad], the short way round the circle where the coordinate is periodic."""
    d = np.asarray(a, dtype=np.float64) - b
    if periodic:
        d = np.remainder(d + math.pi, 2 * math.pi) - math.pi
    return np.abs(d)


def mean_angle(a: float, b: float, periodic: bool) -> float:
    """The angle halfway between a and b [rad] (on the short arc where periodic), in a's
    turn."""
    d = float(b - a)
    if periodic:
        d = math.remainder(d, 2 * math.pi)
    return a + d / 2


def between(x: float, a: float, b: float, periodic: bool) -> bool:
    """Whether x lies strictly inside the short arc (or the interval) from a to b."""
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


def align(before: np.ndarray, after: np.ndarray, periodic: bool) -> np.ndarray:
    """For each angle of ``after`` (sorted), the index of the angle of ``before`` (sorted)
    it continues, or -1 where it begins. Every angle of the shorter list is matched, in
    order (cyclic order where periodic), to the longer one, choosing the matching with the
    least total movement; the longer list's unmatched angles end (or begin) there."""
    result = np.full(len(after), -1, dtype=np.int64)
    if len(before) == 0 or len(after) == 0:
        return result
    swapped = len(before) < len(after)
    longer, shorter = (after, before) if swapped else (before, after)
    best = (math.inf, [])
    for r in range(len(longer)) if periodic else [0]:
        order = np.roll(np.arange(len(longer)), -r)
        cost, pairs = _in_order(longer[order], shorter, periodic)
        if cost < best[0]:
            best = (cost, [(int(order[i]), j) for i, j in pairs])
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
