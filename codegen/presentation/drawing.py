"""The drawing of a mechanism at one state (``mechvib draw``): a ``Geometry``
(``codegen.runtime.drawing``, where the points are computed) drawn with matplotlib, through
``figures``.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from . import figures
from ..runtime.drawing import Geometry


def _span(g: Geometry) -> float:
    xy = np.array([*g.points.values(), *g.centres.values()])
    return float(max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]), 1e-9))


def _spring(ax: Any, p: tuple[float, float], q: tuple[float, float], size: float) -> None:
    """A zig-zag from p to q, straight at both ends."""
    p_, q_ = np.array(p), np.array(q)
    d = q_ - p_
    length = float(np.hypot(*d))
    if length == 0:
        return
    along, normal = d / length, np.array([-d[1], d[0]]) / length
    s = np.linspace(0.2, 0.8, 13)
    offsets = size * np.array([0, *([1, -1] * 5), 1, 0])[: len(s)]
    zig = [p_ + along * length * t + normal * o for t, o in zip(s, offsets)]
    line = np.array([p_, *zig, q_])
    ax.plot(line[:, 0], line[:, 1], color="C2", lw=1.2, zorder=2)


def figure(g: Geometry) -> Any:
    """The drawing of ``g`` (a ``codegen.runtime.drawing.Geometry``): the bars, sliders and
    their guides, fixed points, springs, bodies' centres, named points and the sketch's angle,
    titled with the state drawn (one coordinate: theta; several: each independent one); a
    matplotlib Figure. Raises figures.PlotUnavailable without matplotlib."""
    plt = figures.pyplot()
    shapes = figures.patches()
    size = 0.04 * _span(g)
    fig, ax = plt.subplots(figsize=(6, 5))
    for name, (start, end) in ((s, (g.points[s[0]], g.points[s[1]])) for s in g.springs):
        _spring(ax, start, end, size)
    for link in g.links:
        xy = np.array([g.points[n] for n in link])
        ax.plot(xy[:, 0], xy[:, 1], color="C0", lw=3, solid_capstyle="round", zorder=3)
    for name, guide in g.sliders:
        x, y = g.points[name]
        u = np.array([math.cos(guide), math.sin(guide)])
        ax.plot(*np.array([(x, y) - 4 * size * u, (x, y) + 4 * size * u]).T, color="0.5",
                lw=1, ls="--", zorder=1)
        ax.add_patch(shapes.Rectangle((x - 1.2 * size, y - 0.7 * size), 2.4 * size,
                                      1.4 * size, angle=math.degrees(guide),
                                      rotation_point="center", facecolor="C1", edgecolor="k",
                                      zorder=4))
    for name in g.fixed:
        x, y = g.points[name]
        ax.plot([x - size, x + size], [y - 0.8 * size] * 2, color="k", lw=1.5, zorder=2)
        ax.plot([x, x], [y, y - 0.8 * size], color="k", lw=1, zorder=2)
    for name, (x, y) in g.centres.items():
        ax.plot(x, y, marker="o", color="C3", ms=4, zorder=5)
    for name, (x, y) in g.points.items():
        ax.plot(x, y, marker="o", color="k", ms=4, zorder=6)
        ax.annotate(name, (x, y), xytext=(5, 5), textcoords="offset points", fontsize=11)
    if g.angle:
        vertex, start, end = g.angle
        x, y = g.points[vertex]
        low, high = sorted((math.degrees(start), math.degrees(end)))
        radius = 3 * size
        ax.add_patch(shapes.Arc((x, y), 2 * radius, 2 * radius, theta1=low, theta2=high,
                                color="C4", lw=1.2, zorder=5))
        ax.plot(*np.array([(x, y), (x + 1.6 * radius * math.cos(start),
                                    y + 1.6 * radius * math.sin(start))]).T,
                color="C4", lw=0.8, ls=":", zorder=5)
        middle = math.radians((low + high) / 2)
        ax.annotate("θ",
                    (x + 1.25 * radius * math.cos(middle), y + 1.25 * radius * math.sin(middle)),
                    color="C4", fontsize=12, ha="center", va="center")
    ax.set_aspect("equal")
    ax.margins(0.12)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    at = (f"θ = {math.degrees(g.theta):.4g}°" if not isinstance(g.theta, tuple)
          else g.at(".4g", "°"))
    ax.set_title(f"{g.title}, {at}", fontsize=10)
    ax.grid(True, lw=0.3, alpha=0.5)
    return fig


def draw(g: Geometry, path: str | Path) -> Path:
    """``figure`` written to ``path`` (.svg or .png); the path. Raises ValueError for another
    extension, figures.PlotUnavailable without matplotlib."""
    path = figures.check_path(path)
    return figures.save(figure(g), path)
