"""Layer 1: mechanisms as data.

``SHIPPED`` names the mechanisms that come with the package; ``load`` builds one of them, or
a user's from a Python file that defines ``build() -> Mechanism``.
"""
from __future__ import annotations

import importlib
import importlib.util
from pathlib import Path

from .mechanism import (TIME, Body, Coordinate, Damper, Mechanism, Parameter, PointForce,
                        Requirement, Spring, Torque, distance, parameter)

SHIPPED = ("doughty", "slider_crank", "four_bar", "torsion_pendulum")


def load(name_or_path: str) -> Mechanism:
    """A shipped mechanism by name, or the mechanism a model file's build() returns."""
    if name_or_path in SHIPPED:
        return importlib.import_module(f"{__name__}.{name_or_path}").build()
    path = Path(name_or_path)
    if path.suffix != ".py" or not path.is_file():
        raise ValueError(f"{name_or_path!r} is neither a shipped mechanism "
                         f"({', '.join(SHIPPED)}) nor a model file (.py)")
    spec = importlib.util.spec_from_file_location(f"codegen_user_model_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.build()


__all__ = ["SHIPPED", "TIME", "Body", "Coordinate", "Damper", "Mechanism", "Parameter",
           "PointForce", "Requirement", "Spring", "Torque", "distance", "load", "parameter"]
