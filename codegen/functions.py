"""Deprecated old path of ``codegen.runtime.functions`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.functions`` instead."""
from ._moved import alias
from .runtime import functions as _new

alias(__name__, _new)
