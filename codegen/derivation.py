"""Deprecated old path of ``codegen.compiler.derivation`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.compiler.derivation`` instead."""
from ._moved import alias
from .compiler import derivation as _new

alias(__name__, _new)
