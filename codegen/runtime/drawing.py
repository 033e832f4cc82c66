"""What a drawing of a mechanism at one angle shows, from its model's points (``mechvib draw``).

``geometry(mechanism, library, params, theta)`` places every point the model names (its
``points`` and its ``Sketch``'s) at the angle theta [rad]: the library's ``dependent_state``
gives every coordinate there (the declared assembly mode), and the model's expressions of
them give the points, so the drawing is of the same mechanism the library analyses. The
``Geometry`` is data; ``codegen.presentation.drawing`` draws it. A model without a
``Sketch`` is drawn as its points and its bodies' centres of mass.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass
class Geometry:
    """Where everything is drawn, in the model's units (m), at ``theta`` [rad]."""

    title: str
    theta: float
    points: dict[str, tuple[float, float]]         # every named point
    model_points: tuple[str, ...]                  # those the library computes (point_kinematics)
    links: list[list[str]] = field(default_factory=list)
    sliders: list[tuple[str, float]] = field(default_factory=list)   # (point, guide [rad])
    fixed: list[str] = field(default_factory=list)
    springs: list[tuple[str, str]] = field(default_factory=list)
    centres: dict[str, tuple[float, float]] = field(default_factory=dict)  # bodies' centres
    angle: tuple[str, float, float] | None = None  # (vertex, from [rad], to [rad])


def geometry(mechanism: Any, library: Any, params: Any, theta: float) -> Geometry:
    """The drawing of ``mechanism`` (a codegen.model Mechanism) at theta [rad], for the
    parameter set ``params`` of its compiled ``library``. ValueError where the mechanism
    cannot be assembled at theta."""
    import sympy as sp

    coords, _ = library.dependent_state(params, theta, 0.0)
    coords = np.asarray(coords, dtype=float)
    if not np.all(np.isfinite(coords)):
        raise ValueError(f"the mechanism cannot be assembled at theta = "
                         f"{math.degrees(theta):g} deg")
    values = {p.symbol: sp.Float(getattr(params, p.symbol.name)) for p in mechanism.parameters}
    values.update({c.function: sp.Float(float(v)) for c, v in zip(mechanism.coordinates, coords)})

    def number(expr: Any) -> float:
        return float(sp.sympify(expr).xreplace(values).evalf(17))

    def point(xy: tuple[Any, Any]) -> tuple[float, float]:
        return number(xy[0]), number(xy[1])

    sketch = mechanism.sketch
    named = {**(sketch.points if sketch else {}), **mechanism.points}
    drawn = Geometry(mechanism.title or mechanism.name, theta,
                     {name: point(xy) for name, xy in named.items()}, tuple(mechanism.points))
    drawn.centres = {b.name: point(b.centre) for b in mechanism.bodies}
    if sketch:
        drawn.links = [list(link) for link in sketch.links]
        drawn.sliders = [(name, number(direction)) for name, direction in sketch.sliders]
        drawn.fixed = list(sketch.fixed)
        drawn.springs = list(sketch.springs)
        if sketch.angle:
            vertex, start, end = sketch.angle
            drawn.angle = (vertex, number(start), number(end))
    return drawn
