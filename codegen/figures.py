"""Deprecated old path of ``codegen.runtime.figures`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.figures`` instead."""
from ._moved import alias
from .runtime import figures as _new

alias(__name__, _new)
