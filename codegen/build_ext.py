"""Deprecated old path of ``codegen.compiler.build`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.compiler.build`` instead."""
from ._moved import alias
from .compiler import build as _new

alias(__name__, _new)
