"""Deprecated old path of ``codegen.runtime.folds`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.folds`` instead."""
from ._moved import alias
from .runtime import folds as _new

alias(__name__, _new)
