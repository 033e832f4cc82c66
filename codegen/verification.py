"""Deprecated old path of ``codegen.compiler.verification`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.compiler.verification`` instead."""
from ._moved import alias
from .compiler import verification as _new

alias(__name__, _new)
