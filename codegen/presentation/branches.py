"""The figure of a ``Branches`` (``codegen.runtime.branches``): theta_E against the
parameter, stable branches solid and unstable dashed, the events marked; omega_n and zeta of
the stable branches below it. With n coordinates, a panel for each coordinate, and omega_n
and zeta of every mode (the lowest mode's line the thickest).

It reads the result as data (its points, events and library's SPEC) and draws it; matplotlib
comes through ``figures``. Angles in degrees on the figure; where the coordinate is periodic a
branch is drawn unwrapped, so one crossing +-180 deg stays one line.
"""
from __future__ import annotations

import os
import textwrap
from pathlib import Path
from typing import Any

import numpy as np

from . import figures
from ..runtime.analysis import STABILITY
from ..runtime.branches import EVENTS, POINTS, Branches

#: Line style of each stability (analysis.STABILITY order).
STYLES = {"stable": "-", "marginal": ":", "unstable": "--", "undecided": "-."}
#: Marker of each event kind.
MARKERS = {"fold": ("o", "fold"), "pitchfork": ("s", "pitchfork"), "end": ("x", "branch end"),
           "stability change": ("D", "stability change")}
#: Stabilities whose omega_n and zeta are drawn (a real natural frequency: K > 0; undecided:
#: where it is within rounding of 0, drawn where it is real).
VIBRATING = (STABILITY.index("stable"), STABILITY.index("marginal"),
             STABILITY.index("undecided"))


def _coordinates(result: Branches) -> list[tuple[str, str, bool, Any]]:
    """Each coordinate's axis label, unit, periodicity and range centre (a number or a
    parameter's name)."""
    spec = result.library.SPEC
    if result.library.dof == 1:
        return [(r"$\theta_E$", "rad", bool(spec["periodic"]), spec["range_centre"])]
    return [(c["name"], c["unit"], bool(p), centre) for c, p, centre in
            zip(spec["coordinates"], spec["periodic"], spec["range_centre"])]


def _centre(result: Branches, centre: Any) -> float:
    """The middle of a coordinate's range [rad] (a number or a parameter's name)."""
    values = vars(result.base)
    return float(values[centre]) if centre in values else float(centre)


def _angles(result: Branches, rows: np.ndarray) -> np.ndarray:
    """A branch's coordinates, a column each: angles [deg] unwrapped where periodic, in the
    turn holding most of it; lengths as they are."""
    theta = rows["theta"].reshape(len(rows), -1).copy()
    for k, (_, unit, periodic, centre) in enumerate(_coordinates(result)):
        if periodic and len(theta):
            column = np.unwrap(theta[:, k])
            middle = _centre(result, centre)
            theta[:, k] = column - 2 * np.pi * np.round((np.median(column) - middle) / (2 * np.pi))
        if unit == "rad":
            theta[:, k] = np.degrees(theta[:, k])
    return theta


def _runs(codes: np.ndarray) -> list[slice]:
    """The stretches of equal code, each reaching into the next one's first point, so the
    line stays joined where the style changes."""
    edges = np.flatnonzero(np.diff(codes)) + 1
    starts = np.concatenate([[0], edges])
    stops = np.concatenate([edges + 1, [len(codes)]])
    return [slice(int(a), int(min(b, len(codes)))) for a, b in zip(starts, stops)]


def _draw_branch(axes: Any, result: Branches, number: int, colour: str) -> None:
    rows = result.branch(number)
    value, angles = rows["value"], _angles(result, rows)
    *tops, frequency, damping = axes
    for top, angle in zip(tops, angles.T):
        for run in _runs(rows["stability"]):
            style = STYLES[STABILITY[rows["stability"][run.start]]]
            top.plot(value[run], angle[run], style, color=colour, linewidth=1.6)
        for kind in EVENTS:
            at = rows["point"] == POINTS.index(kind)
            if np.any(at):
                marker, _ = MARKERS[kind]
                top.plot(value[at], angle[at], marker, color="black", markersize=6,
                         markerfacecolor="none", zorder=3, clip_on=False)
    omega = rows["omega_n"].reshape(len(rows), -1)
    zeta = rows["zeta"].reshape(len(rows), -1)
    for j in range(omega.shape[1]):   # each mode; the lowest the thickest
        vibrating = np.isin(rows["stability"], VIBRATING) & np.isfinite(omega[:, j])
        shown = np.where(vibrating, 1.0, np.nan)   # gaps where the branch does not vibrate
        width = 1.6 if j == 0 else 1.0
        frequency.plot(value, omega[:, j] * shown, "-", color=colour, linewidth=width)
        damping.plot(value, zeta[:, j] * shown, "-", color=colour, linewidth=width)


def _legend(top: Any, result: Branches) -> None:
    """Line styles of the stabilities present, then markers of the events present."""
    handles = []
    for name, style in STYLES.items():
        if np.any(result.points["stability"] == STABILITY.index(name)):
            handles += top.plot([], [], style, color="dimgray", label=name)
    for kind in EVENTS:
        if any(e.kind == kind for e in result.events):
            marker, label = MARKERS[kind]
            handles += top.plot([], [], marker, color="black", markerfacecolor="none",
                                label=label)
    top.legend(handles=handles, loc="best", fontsize=8, framealpha=0.9)


def figure(result: Branches) -> Any:
    """theta_E [deg] against the parameter (each coordinate, for n), then omega_n [rad/s]
    and zeta of the branches where they vibrate (K > 0; each mode, for n); a matplotlib
    Figure. Raises figures.PlotUnavailable without matplotlib."""
    plt = figures.pyplot()
    coordinates = _coordinates(result)
    n = len(coordinates)
    heights = [2.2] if n == 1 else [1.5] * n
    fig, axes = plt.subplots(n + 2, 1, sharex=True, figsize=(7.5, 7.5 + 1.6 * (n - 1)),
                             gridspec_kw={"height_ratios": [*heights, 1, 1]})
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for number in range(result.count):
        _draw_branch(axes, result, number, colours[number % len(colours)])
    *tops, frequency, damping = axes
    top = tops[0]
    label = f"{result.parameter} [{result.unit}]"
    top.set_title(textwrap.fill(f"Equilibria of {result.library.TITLE} against "
                                f"{result.parameter}", 70), fontsize=11)
    for axis, (name, unit, _, _) in zip(tops, coordinates):
        axis.set_ylabel(f"{name} [{'deg' if unit == 'rad' else unit}]")
    frequency.set_ylabel(r"$\omega_n$ [rad/s]")
    damping.set_ylabel(r"$\zeta$ [-]")
    zeta = result.points["zeta"]
    if np.any(np.isfinite(zeta) & (zeta > 0)):
        damping.set_yscale("log")   # zeta -> infinity as K -> 0 at a fold
    damping.set_xlabel(label)
    others = "".join(f"and {name} " for name in ("marginal", "undecided")
                     if np.any(result.points["stability"] == STABILITY.index(name)))
    modes = " (every mode)" if n > 1 else ""
    frequency.set_title(f"stable {others}branches{modes}",
                        fontsize=9, loc="left")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    damping.set_xlim(result.values[0], result.values[-1])
    _legend(top, result)
    fig.align_ylabels(axes)
    return fig


def plot(result: Branches, path: str | os.PathLike[str]) -> Path:
    """``figure`` written to ``path`` (.png or .svg); the path. Raises ValueError for
    another extension, figures.PlotUnavailable without matplotlib."""
    path = figures.check_path(path)
    return figures.save(figure(result), path)
