"""The runtime: what a user calls on a compiled library.

library and functions (one compiled library) -> analysis -> batch, folds, simulation, sweep ->
branches -> branch_figure -> api (``load``, ``load_from``: the entry point). figures and joining
are its helpers. It imports nothing of ``codegen.compiler`` or ``codegen.cli``.
"""
