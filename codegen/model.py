"""What a model file imports: ``codegen.model.mechanism`` (Body, Coordinate, Spring, ...).

A supported public name: this module *is* the package ``codegen.compiler.model`` (issue 28
moved it there), its submodules included, so a model file written either way works, without
a warning."""
from ._moved import alias
from .compiler import model as _new

alias(__name__, _new, deprecated=False)
