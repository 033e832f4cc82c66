"""Deprecated old path of ``codegen.runtime.joining`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.joining`` instead."""
from ._moved import alias
from .runtime import joining as _new

alias(__name__, _new)
