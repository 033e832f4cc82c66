"""Deprecated old path of ``codegen.runtime.analysis`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.analysis`` instead."""
from ._moved import alias
from .runtime import analysis as _new

alias(__name__, _new)
