"""The compiled libraries from Python: ``load``, ``load_from``, ``shipped``, ``Library``.

The public name of the Python API (docs/python.md); the implementation is
``codegen.runtime.api``, whose objects these are.
"""
from __future__ import annotations

from .runtime.api import (Argument, Function, Library, LibraryError, LibraryFunction,
                          ParameterSet, ParamsLike, load, load_from, shipped)

__all__ = ["Argument", "Function", "Library", "LibraryError", "LibraryFunction",
           "ParameterSet", "ParamsLike", "load", "load_from", "shipped"]
