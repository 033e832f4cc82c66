"""Layer 6: the compiled libraries from Python.

``load(name)`` gives the ``Library`` of a shipped mechanism (built into the package as
``codegen._native_NAME``); ``load_from(folder, name)`` one a user generated and built with
``python -m codegen generate --model FILE --out FOLDER``. Several load side by side; each
loads once per process. A library remembers which of the two loaded it (``Library.origin``),
so its parameter sets and results pickle: another process loads it the same way again.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
from functools import lru_cache
from pathlib import Path

from .errors import LibraryError
from .functions import Argument, Function, LibraryFunction
from .library import Library, ParameterSet, ParamsLike

NATIVE = "_native_{}"


@lru_cache(maxsize=None)
def load(name: str) -> Library:
    """The Library of a shipped mechanism, by one of the names ``shipped()`` lists. Raises
    ValueError if this installation has no compiled library of that name."""
    try:
        module = importlib.import_module(f"{__package__}.{NATIVE.format(name)}")
    except ModuleNotFoundError:
        raise ValueError(f"no compiled library for {name!r} in this installation") from None
    return Library(module, origin=("load", name))


def shipped() -> list[str]:
    """Names of the mechanisms compiled into this installation (no import needed)."""
    prefix = NATIVE.format("")
    return sorted({p.name.split(".")[0][len(prefix):] for p in Path(__file__).parent.iterdir()
                   if p.name.startswith(prefix) and p.suffix in (".so", ".pyd")})


def load_from(folder: str | os.PathLike[str], name: str) -> Library:
    """The Library a user built into ``folder`` (see codegen.build_ext.build_into), e.g.
    ``load_from("build/mine", "spring_pendulum")``. The folder is taken as an absolute path,
    so the same library loads once whichever way the folder is written. Raises ValueError
    if the folder holds no compiled library of that name."""
    return _load_from(str(Path(folder).resolve()), name)


@lru_cache(maxsize=None)
def _load_from(folder: str, name: str) -> Library:
    module_name = NATIVE.format(name)
    candidates = sorted(Path(folder).glob(f"{module_name}.*.so")) + sorted(
        Path(folder).glob(f"{module_name}.*.pyd"))
    if not candidates:
        raise ValueError(f"no compiled library {module_name} in {folder}")
    spec = importlib.util.spec_from_file_location(module_name, candidates[0])
    if spec is None or spec.loader is None:
        raise ValueError(f"{candidates[0]} is not an extension module Python can load")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return Library(module, origin=("load_from", folder, name))


__all__ = ["Argument", "Function", "Library", "LibraryError", "LibraryFunction",
           "ParameterSet", "ParamsLike", "load", "load_from", "shipped"]
