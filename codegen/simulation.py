"""Deprecated old path of ``codegen.runtime.simulation`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.simulation`` instead."""
from ._moved import alias
from .runtime import simulation as _new

alias(__name__, _new)
