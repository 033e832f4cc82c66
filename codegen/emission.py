"""Deprecated old path of ``codegen.compiler.emission`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.compiler.emission`` instead."""
from ._moved import alias
from .compiler import emission as _new

alias(__name__, _new)
