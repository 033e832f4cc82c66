"""Deprecated old path of ``codegen.runtime.batch`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.batch`` instead."""
from ._moved import alias
from .runtime import batch as _new

alias(__name__, _new)
