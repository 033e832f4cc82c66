"""Deprecated old path of ``codegen.cli.report`` (moved in issue 28): the same module, with a
DeprecationWarning. Import ``codegen.cli.report`` instead."""
from ._moved import alias
from .cli import report as _new

alias(__name__, _new)
