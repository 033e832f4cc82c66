"""What a drawing of a mechanism at one state shows, from its model's points (``mechvib draw``).

``geometry(mechanism, library, params, theta)`` places every point the model names (its
``points`` and its ``Sketch``'s) at the independent coordinates ``theta``: for one
coordinate, an angle [rad], where the library's ``dependent_state`` gives every coordinate
(the declared assembly mode); for n, a sequence of the n independent coordinates [rad or m],
where the library's ``positions`` gives them. The model's expressions of the coordinates then
give the points, so the drawing is of the same mechanism the library analyses. The
``Geometry`` is data; ``codegen.presentation.drawing`` draws it. A model without a
``Sketch`` is drawn as its points and its bodies' centres of mass.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np


#: The library's statuses that say the mechanism does not close at the coordinates given (a
#: dyad whose bars cannot meet, a dead point where no assembly mode is decided).
UNASSEMBLED = ("ERR_SINGULAR_STATE", "ERR_MODE_UNDECIDED")


@dataclass
class Geometry:
    """Where everything is drawn, in the model's units (m), at the independent coordinates
    ``theta``: for one coordinate its angle [rad], a float; for several, a tuple of their
    values [rad or m] in the order of ``coordinates`` (each one's name and unit)."""

    title: str
    theta: float | tuple[float, ...]
    points: dict[str, tuple[float, float]]         # every named point
    model_points: tuple[str, ...]   # those the library computes (point_kinematics; n: points)
    links: list[list[str]] = field(default_factory=list)
    sliders: list[tuple[str, float]] = field(default_factory=list)   # (point, guide [rad])
    fixed: list[str] = field(default_factory=list)
    springs: list[tuple[str, str]] = field(default_factory=list)
    centres: dict[str, tuple[float, float]] = field(default_factory=dict)  # bodies' centres
    angle: tuple[str, float, float] | None = None  # (vertex, from [rad], to [rad])
    coordinates: tuple[tuple[str, str], ...] = (("theta", "rad"),)  # (name, unit) of each

    @property
    def values(self) -> tuple[float, ...]:
        """The independent coordinates [rad or m], one for each of ``coordinates``."""
        return self.theta if isinstance(self.theta, tuple) else (self.theta,)

    def at(self, spec: str = ".4f", degree: str = " deg") -> str:
        """Where it is drawn, as text: ``theta_1 = 75.8605 deg, delta = -11.8024 deg``; angles
        in degrees (followed by ``degree``), lengths in their unit, each number formatted
        with ``spec``."""
        return shown(self.coordinates, self.values, spec, degree)


def shown(coordinates: tuple[tuple[str, str], ...], values: Any, spec: str = ".4f",
          degree: str = " deg") -> str:
    """``name = value unit, ...`` of coordinates (name, unit) at ``values`` (SI units):
    angles in degrees, each number formatted with ``spec``."""
    return ", ".join(
        f"{name} = {format(math.degrees(v), spec)}{degree}" if unit == "rad"
        else f"{name} = {format(v, spec)}{'' if unit == '1' else ' ' + unit}"
        for (name, unit), v in zip(coordinates, values))


def independent_coordinates(mechanism: Any) -> tuple[tuple[str, str], ...]:
    """The (name, unit) of each of ``mechanism``'s independent coordinates, in its order."""
    units = {c.name: c.unit for c in mechanism.coordinates}
    return tuple((name, units[name]) for name in mechanism.independents)


def geometry(mechanism: Any, library: Any, params: Any, theta: Any) -> Geometry:
    """The drawing of ``mechanism`` (a codegen.model Mechanism) at the independent
    coordinates ``theta``, for the parameter set ``params`` of its compiled ``library``: one
    coordinate, its angle [rad]; several, a sequence of one value per independent coordinate,
    in the model's order [rad or m]. ValueError where the mechanism cannot be assembled
    there, or ``theta`` has the wrong number of values or one not finite."""
    import sympy as sp

    from ..errors import LibraryError

    coordinates = independent_coordinates(mechanism)
    several = len(coordinates) > 1
    values = tuple(float(v) for v in np.ravel(np.asarray(theta, dtype=float)))
    if len(values) != len(coordinates):
        names = ", ".join(name for name, _ in coordinates)
        raise ValueError(f"{mechanism.name} has {len(coordinates)} independent coordinate"
                         f"{'s' if several else ''} ({names}): one value each, not "
                         f"{len(values)}")
    where = shown(coordinates, values, "g")
    if not all(map(math.isfinite, values)):
        raise ValueError(f"{where}: not a finite state")
    try:
        if several:
            coords = np.asarray(library.positions(params, values), dtype=float)
            order = [c["name"] for c in library.SPEC["all_coordinates"]]
        else:
            coords = np.asarray(library.dependent_state(params, values[0], 0.0)[0], dtype=float)
            order = [c.name for c in mechanism.coordinates]
    except LibraryError as error:
        if error.code not in UNASSEMBLED:
            raise
        raise ValueError(f"the mechanism cannot be assembled at {where} "
                         f"({error.reason})") from None
    if not np.all(np.isfinite(coords)):
        raise ValueError(f"the mechanism cannot be assembled at {where}")
    by_name = dict(zip(order, coords))
    values_of = {p.symbol: sp.Float(getattr(params, p.symbol.name)) for p in mechanism.parameters}
    values_of.update({c.function: sp.Float(float(by_name[c.name]))
                      for c in mechanism.coordinates})

    def number(expr: Any) -> float:
        return float(sp.sympify(expr).xreplace(values_of).evalf(17))

    def point(xy: tuple[Any, Any]) -> tuple[float, float]:
        return number(xy[0]), number(xy[1])

    sketch = mechanism.sketch
    named = {**(sketch.points if sketch else {}), **mechanism.points}
    drawn = Geometry(mechanism.title or mechanism.name, values if several else values[0],
                     {name: point(xy) for name, xy in named.items()}, tuple(mechanism.points),
                     coordinates=coordinates)
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


def range_centre(mechanism: Any, params: Any) -> tuple[float, ...]:
    """The centre of each independent coordinate's range at ``params`` [rad or m]: where
    ``mechvib draw`` draws a mechanism without an equilibrium."""
    import sympy as sp

    values = {p.symbol: sp.Float(getattr(params, p.symbol.name)) for p in mechanism.parameters}
    return tuple(float(sp.sympify(c).xreplace(values).evalf(17)) for c in mechanism.centres)
