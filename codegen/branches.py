"""Deprecated old path of ``codegen.runtime.branches`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.runtime.branches`` instead."""
from ._moved import alias
from .runtime import branches as _new

alias(__name__, _new)
