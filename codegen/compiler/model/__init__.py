"""Mechanisms as data.

``SHIPPED`` names the mechanisms that come with the package; ``load`` builds one of them, or
a user's from a Python file that defines ``build() -> Mechanism``.
"""
from __future__ import annotations

import importlib
import importlib.util
import traceback
from pathlib import Path

from .checks import ModelError, check
from .mechanism import (TIME, Body, Coordinate, Damper, Mechanism, Parameter, PointForce,
                        Requirement, Sketch, Spring, Torque, distance, parameter)

SHIPPED = ("doughty", "slider_crank", "four_bar", "torsion_pendulum")
#: Shipped mechanisms with several independent coordinates (analysed over a box of them).
SHIPPED_MULTIBODY = ("double_pendulum", "flexible_doughty")


def load(name_or_path: str) -> Mechanism:
    """A shipped mechanism by name, or the mechanism a model file's build() returns, checked
    (checks.py): a ModelError names the first problem in one line."""
    if name_or_path in SHIPPED + SHIPPED_MULTIBODY:
        return importlib.import_module(f"{__name__}.{name_or_path}").build()
    path = Path(name_or_path)
    if not path.exists():
        raise ModelError(f"{path}: no such file")
    if path.suffix != ".py" or not path.is_file():
        raise ModelError(f"{path}: not a model file (a Python file, NAME.py, defining build())")
    spec = importlib.util.spec_from_file_location(f"codegen_user_model_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        build = getattr(module, "build", None)
        mechanism = build() if callable(build) else None
    except Exception as error:  # the user's code failed: where and what, no traceback
        raise ModelError(_failure(path, spec.origin, error)) from None
    except SystemExit as error:  # sys.exit() in a model file: say so, do not just end
        raise ModelError(f"{path}: the model file called sys.exit({error.code!r}) instead "
                         "of returning a Mechanism from build()") from None
    if not callable(build):
        raise ModelError(f"{path}: a model file defines build() -> Mechanism")
    if not isinstance(mechanism, Mechanism):
        raise ModelError(f"{path}: build() returned {type(mechanism).__name__}, not a Mechanism")
    check(mechanism, path)
    return mechanism


def _failure(path: Path, origin: str, error: Exception) -> str:
    """'PATH:LINE: Type: message', one line, for an error the model file (run as origin) raised."""
    lines = [n for frame, n in traceback.walk_tb(error.__traceback__)
             if frame.f_code.co_filename == origin]
    if isinstance(error, SyntaxError) and error.filename == origin:
        lines.append(error.lineno)
    message = (error.msg if isinstance(error, SyntaxError) else str(error)).strip()
    where = f"{path}:{lines[-1]}" if lines else str(path)
    return f"{where}: {type(error).__name__}" + (f": {message.splitlines()[0]}" if message else "")


__all__ = ["SHIPPED", "SHIPPED_MULTIBODY", "TIME", "Body", "check", "Coordinate", "Damper", "Mechanism", "ModelError",
           "Parameter", "PointForce", "Requirement", "Sketch", "Spring", "Torque", "distance", "load",
           "parameter"]
