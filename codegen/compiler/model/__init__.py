"""Mechanisms as data.

``SHIPPED`` names the mechanisms that come with the package; ``load`` builds one of them, or
a user's from a Python file that defines ``build() -> Mechanism``. A model file imports
modules beside it as it would run as a script (its folder is on the import path meanwhile);
``load_with_sources`` also names those modules' files, what a build of it is made from.
"""
from __future__ import annotations

import importlib
import importlib.util
import site
import sys
import sysconfig
import traceback
from collections.abc import Iterator
from contextlib import contextmanager
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
    return load_with_sources(name_or_path)[0]


def load_with_sources(name_or_path: str) -> tuple[Mechanism, tuple[Path, ...]]:
    """``load``, and the files of the user's own modules the model file imported (neither
    Python's nor installed packages' nor this package's): what its build depends on besides
    the file itself. A shipped mechanism has none."""
    if name_or_path in SHIPPED + SHIPPED_MULTIBODY:
        return importlib.import_module(f"{__name__}.{name_or_path}").build(), ()
    path = Path(name_or_path)
    if not path.exists():
        raise ModelError(f"{path}: no such file")
    if path.suffix != ".py" or not path.is_file():
        raise ModelError(f"{path}: not a model file (a Python file, NAME.py, defining build())")
    spec = importlib.util.spec_from_file_location(f"codegen_user_model_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    try:
        with _imports_beside(path) as sources:
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
    return mechanism, tuple(sorted(sources))


@contextmanager
def _imports_beside(path: Path) -> Iterator[list[Path]]:
    """Run a model file with its folder first on the import path (a helper module beside it
    imports as it does when the file runs as a script). Yields a list that, on leaving,
    holds the files of the user's modules imported meanwhile; those leave sys.modules, so a
    later load in this process reads them afresh (they may have changed)."""
    folder = str(path.resolve().parent)
    before = set(sys.modules)
    sys.path.insert(0, folder)
    sources: list[Path] = []
    try:
        yield sources
    finally:
        if folder in sys.path:
            sys.path.remove(folder)
        for name in set(sys.modules) - before:
            file = getattr(sys.modules[name], "__file__", None)
            if file and _is_users(Path(file).resolve()):
                sources.append(Path(file).resolve())
                del sys.modules[name]


def _is_users(file: Path) -> bool:
    """Whether a module's file is the user's own: outside Python's installation (the standard
    library, site-packages, a virtual environment) and outside this package."""
    return not any(file.is_relative_to(folder) for folder in _installed_folders())


def _installed_folders() -> set[Path]:
    """Python's own folders and installed packages', and this package's."""
    paths = sysconfig.get_paths()
    folders = {sys.prefix, sys.base_prefix, sys.exec_prefix, sys.base_exec_prefix,
               *(paths[key] for key in ("stdlib", "platstdlib", "purelib", "platlib")),
               *site.getsitepackages(), site.getusersitepackages()}
    package = Path(__file__).resolve().parents[2]  # codegen/compiler/model -> codegen
    return {Path(folder).resolve() for folder in folders} | {package}


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
           "load_with_sources", "parameter"]
