"""The old module paths of issue 28's layout, kept working.

Each module that moved (``codegen.analysis`` is now ``codegen.runtime.analysis``, ...) leaves a
small module at its old path that calls ``alias``: the old name then *is* the new module in
``sys.modules`` (with every submodule of a moved package), so ``from codegen.analysis import
analyze``, ``codegen.sweep.grid`` and monkeypatching through either name all reach one object.
A deprecated path warns once, naming the new one; ``codegen.api`` and ``codegen.model`` stay
supported public names and do not warn. Nothing inside codegen imports an old path (the
import graph test and ``python -W error::DeprecationWarning`` hold it).
"""
from __future__ import annotations

import importlib
import pkgutil
import sys
import warnings
from types import ModuleType


def alias(old: str, new: ModuleType, deprecated: bool = True) -> None:
    """Make ``old`` (and ``old.SUB`` for every submodule of a package) name ``new``."""
    if deprecated:
        # stacklevel 3: past this function and the old module, to the line importing it
        # (the import machinery's own frames are skipped by warnings)
        warnings.warn(f"{old} has moved to {new.__name__}; import it from there "
                      f"(the old path will be removed)", DeprecationWarning, stacklevel=3)
    if hasattr(new, "__path__"):
        for info in pkgutil.walk_packages(new.__path__, new.__name__ + "."):
            importlib.import_module(info.name)
    for name, module in list(sys.modules.items()):
        if name == new.__name__ or name.startswith(new.__name__ + "."):
            sys.modules[old + name[len(new.__name__):]] = module
