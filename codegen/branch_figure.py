"""Deprecated old path of ``codegen.runtime.branch_figure`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.branch_figure`` instead."""
from ._moved import alias
from .runtime import branch_figure as _new

alias(__name__, _new)
