"""Layer 6: the compiled libraries from Python.

``load(name)`` gives the ``Library`` of a shipped mechanism (built into the package as
``codegen._native_NAME``); ``load_from(folder, name)`` one a user generated and built with
``python -m codegen generate --model FILE --out FOLDER``. Several load side by side.
"""
from __future__ import annotations

import importlib
import importlib.util
from functools import lru_cache
from pathlib import Path

from .library import Function, Library, LibraryError

NATIVE = "_native_{}"


@lru_cache(maxsize=None)
def load(name: str) -> Library:
    """The Library of a shipped mechanism."""
    try:
        module = importlib.import_module(f"{__package__}.{NATIVE.format(name)}")
    except ModuleNotFoundError:
        raise ValueError(f"no compiled library for {name!r} in this installation") from None
    return Library(module)


def shipped() -> list[str]:
    """Names of the mechanisms compiled into this installation (no import needed)."""
    prefix = NATIVE.format("")
    return sorted({p.name.split(".")[0][len(prefix):] for p in Path(__file__).parent.iterdir()
                   if p.name.startswith(prefix) and p.suffix in (".so", ".pyd")})


@lru_cache(maxsize=None)
def load_from(folder: str | Path, name: str) -> Library:
    """The Library a user built into ``folder`` (see codegen.build_ext.build_into)."""
    module_name = NATIVE.format(name)
    candidates = sorted(Path(folder).glob(f"{module_name}.*.so")) + sorted(
        Path(folder).glob(f"{module_name}.*.pyd"))
    if not candidates:
        raise ValueError(f"no compiled library {module_name} in {folder}")
    spec = importlib.util.spec_from_file_location(module_name, candidates[0])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return Library(module)


__all__ = ["Function", "Library", "LibraryError", "load", "load_from", "shipped"]
