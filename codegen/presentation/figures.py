"""Figures (the optional ``plot`` extra): matplotlib, headless, to PNG or SVG.

Only this module imports matplotlib, and only when a figure is asked for, so the analysis
and the command line work without it; a missing matplotlib is one clear error that says how
to install it. The other modules of ``codegen.presentation`` draw through ``pyplot`` and
``save``; nothing below this layer (the runtime, the compiler) draws.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

from .. import files

#: The file types a figure can be written as (by the path's suffix).
FORMATS = (".png", ".svg")

INSTALL_HINT = "figures need matplotlib: pip install 'mechvib[plot]'"


class PlotUnavailable(RuntimeError):
    """matplotlib is not installed (the ``plot`` extra)."""


def pyplot() -> Any:
    """matplotlib.pyplot on the non-interactive Agg backend (no screen needed)."""
    try:
        import matplotlib
    except ImportError as error:
        raise PlotUnavailable(INSTALL_HINT) from error
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def patches() -> Any:
    """matplotlib.patches (Arc, Rectangle, ...), on the same terms as ``pyplot``."""
    pyplot()
    import matplotlib.patches
    return matplotlib.patches


def check_path(path: str | Path) -> Path:
    """``path`` as a Path, if its suffix is a format we write; ValueError otherwise."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise ValueError(f"{path}: a figure is written as {' or '.join(FORMATS)}")
    return path


def save(figure: Any, path: str | Path) -> Path:
    """Write ``figure`` to ``path`` (.png at 150 dpi, or .svg) and close it."""
    path = check_path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with files.replacing(path, suffix=path.suffix) as scratch:
            figure.savefig(scratch, dpi=150, bbox_inches="tight", format=path.suffix[1:].lower())
    finally:
        pyplot().close(figure)
    return path


# --------------------------------------------------------------------------- units
# A figure shows each quantity in one unit per axis: coordinates of several units (an angle
# and a length) go on panels of their own. Angles are shown in degrees, as everywhere the
# command line prints them.

def shown_unit(unit: str) -> str:
    """A coordinate's SI unit as a figure shows it: rad as deg, the rest as it is."""
    return "deg" if unit == "rad" else unit


def shown_values(values: Any, unit: str) -> Any:
    """Values in ``unit`` (a coordinate's SI unit) as a figure shows them: radians in
    degrees."""
    import numpy as np

    return np.degrees(values) if unit == "rad" else values


def load_unit(unit: str) -> str:
    """The unit of the generalised force on a coordinate of ``unit``: its work is in J, so a
    torque [N m] on an angle, a force [N] on a length."""
    return {"rad": "N m", "m": "N"}.get(unit, f"J/{unit}")


def per(unit: str, load: str) -> str:
    """``unit`` per ``load``: deg/(N m), m/N."""
    return f"{unit}/({load})" if " " in load or "/" in load else f"{unit}/{load}"


def by_unit(coordinates: list[dict[str, Any]]) -> list[tuple[str, list[int]]]:
    """The coordinates (a library's SPEC["coordinates"], each with its name and SI unit)
    grouped by unit, in the order each unit first appears: (unit, their indices) each."""
    groups: dict[str, list[int]] = {}
    for i, coordinate in enumerate(coordinates):
        groups.setdefault(coordinate["unit"], []).append(i)
    return list(groups.items())
