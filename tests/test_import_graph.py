"""The package in layers (issue 28): every import in codegen/ goes down or sideways, never up,
and no modules import each other in a cycle.

Every Import and ImportFrom node of every module counts, wherever it is: at module level,
inside a function (a lazy import is still a dependency) and under ``if TYPE_CHECKING:``.
The one allowance: an import under ``if TYPE_CHECKING:`` never runs (its module has
``from __future__ import annotations``, checked here, so annotations stay strings), so it
is left out of the cycle check; it must still point down or sideways like any other.
``codegen.library`` and ``codegen.functions`` use this: the two are one layer, the compiled
library, and functions only names the Library type.

A submodule's import of its parent package (which Python runs first) is not counted: the
edges are what the source names. ``from X import name`` is an edge to ``X.name`` where that
is a module of codegen, else to ``X``. A new module has to be placed in ``LAYERS``.
"""
from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "codegen"

#: Bottom to top: a module may import from its own layer or one below, never from above.
#: A name ending in ".*" is every module of that subpackage.
LAYERS: list[tuple[str, ...]] = [
    # plumbing, standard library and numpy only (figures imports matplotlib when asked to)
    ("codegen", "codegen.errors", "codegen.files", "codegen.resources", "codegen.joining",
     "codegen.figures"),
    # the compiler side: model -> derivation -> C emission -> verification -> generation
    ("codegen.model.*",),
    ("codegen.derivation.*",),
    ("codegen.emission.*",),
    ("codegen.verification",),
    ("codegen.generate",),
    ("codegen.build_ext",),
    # the runtime side: one compiled library, then what is computed with it
    ("codegen.library", "codegen.functions"),
    ("codegen.analysis",),
    ("codegen.batch", "codegen.folds", "codegen.simulation", "codegen.sweep"),
    ("codegen.branches",),
    ("codegen.branch_figure", "codegen.report", "codegen.drawing"),
    ("codegen.api",),
    ("codegen.user_model",),
    ("codegen.cli.*",),   # the verbs and what they share; codegen.cli (__init__) too
    ("codegen.__main__",),
]


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES: dict[str, Path] = {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def layer_of(module: str) -> int:
    for index, names in enumerate(LAYERS):
        for name in names:
            if module == name or (name.endswith(".*") and (
                    module == name[:-2] or module.startswith(name[:-1]))):
                return index
    raise AssertionError(f"{module} is in no layer: place it in LAYERS")


def _type_checking_only(tree: ast.Module) -> set[ast.AST]:
    """The import nodes under an ``if TYPE_CHECKING:`` (or ``typing.TYPE_CHECKING``)."""
    found: set[ast.AST] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            found |= {n for child in node.body for n in ast.walk(child)
                      if isinstance(n, (ast.Import, ast.ImportFrom))}
    return found


def imports(module: str) -> list[tuple[str, bool]]:
    """(imported module of codegen, whether only under TYPE_CHECKING) for every import."""
    path = MODULES[module]
    tree = ast.parse(path.read_text(), str(path))
    typing_only = _type_checking_only(tree)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    edges = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[:len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in MODULES else base
                       for a in node.names]
        else:
            continue
        for target in targets:
            # `import codegen.x.y` names the module codegen.x.y; keep the longest known prefix
            while target and target not in MODULES:
                target = target.rpartition(".")[0]
            if target and target != module:
                edges.append((target, node in typing_only))
    return edges


def test_every_module_has_a_layer():
    for module in MODULES:
        layer_of(module)


def test_no_upward_import():
    upward = [f"{module} (layer {layer_of(module)}) imports {target} (layer {layer_of(target)})"
              for module in MODULES for target, _ in imports(module)
              if layer_of(target) > layer_of(module)]
    assert not upward, "imports from a higher layer:\n" + "\n".join(upward)


def test_type_checking_imports_are_annotations_only():
    for module, path in MODULES.items():
        if any(typing_only for _, typing_only in imports(module)):
            assert "from __future__ import annotations" in path.read_text(), module


def test_no_import_cycle():
    graph = {m: sorted({t for t, typing_only in imports(m) if not typing_only}) for m in MODULES}
    # depth-first search; a grey module met again closes a cycle
    state: dict[str, str] = {}
    stack: list[str] = []

    def visit(module: str) -> list[str] | None:
        state[module] = "grey"
        stack.append(module)
        for target in graph[module]:
            if state.get(target) == "grey":
                return stack[stack.index(target):] + [target]
            if target not in state and (cycle := visit(target)):
                return cycle
        stack.pop()
        state[module] = "black"
        return None

    for module in graph:
        if module not in state and (cycle := visit(module)):
            raise AssertionError("import cycle: " + " -> ".join(cycle))


def test_the_graph_is_read():
    """The parser finds what is known to be there: relative, lazy and TYPE_CHECKING imports."""
    assert ("codegen.library", False) in imports("codegen.analysis")
    assert ("codegen.generate", False) in imports("codegen.cli.common")   # inside a function
    assert ("codegen", False) in imports("codegen.emission.render")       # from .. import x
    assert ("codegen.model", False) in imports("codegen.derivation.dynamics")
    assert ("codegen.model.mechanism", False) in imports("codegen.derivation.dynamics")
    assert ("codegen.branches", True) in imports("codegen.report")
