"""Deprecated old path of ``codegen.runtime.library`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.library`` instead."""
from ._moved import alias
from .runtime import library as _new

alias(__name__, _new)
