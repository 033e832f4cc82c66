"""Deprecated old path of ``codegen.runtime.sweep`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.sweep`` instead."""
from ._moved import alias
from .runtime import sweep as _new

alias(__name__, _new)
