"""The compiler: a mechanism model to generated, verified C and its Python extension.

model (mechanisms as data) -> derivation (every expression of the method) -> emission (the
plan and its C) -> verification (the C against the symbolic expressions) -> generate (the
files of generated/) and build (the cffi extension). It imports nothing of ``codegen.runtime``
or ``codegen.cli``; below it are only codegen's plumbing modules (errors, files, resources).
"""
