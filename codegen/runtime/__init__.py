"""The runtime: what a user calls on a compiled library.

library and functions (one compiled library) -> analysis -> batch, folds, simulation, sweep ->
branches, response, multibody_motion, multibody_response, drawing -> api (``load``,
``load_from``: the entry point). joining is a helper. Its results are data (dataclasses, numpy
arrays); it draws nothing and imports no matplotlib (``codegen.presentation`` draws them), and
it imports nothing of ``codegen.compiler``, ``codegen.presentation`` or ``codegen.cli``.
"""
