"""The compiled libraries from Python: ``load``, ``load_from``, ``shipped``, ``Library``.

A supported public name: this module *is* ``codegen.runtime.api`` (issue 28 moved it there;
see docs/python.md, "Moved modules"), so both paths give the same objects, without a warning."""
from ._moved import alias
from .runtime import api as _new

alias(__name__, _new, deprecated=False)
