"""Deprecated old path of ``codegen.compiler.generate`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.compiler.generate`` instead."""
from ._moved import alias
from .compiler import generate as _new

alias(__name__, _new)
