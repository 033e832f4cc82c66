"""The package in layers (issue 28): every import in codegen/ goes down or sideways, never up,
and no modules import each other in a cycle.

Every Import and ImportFrom node of every module counts, wherever it is: at module level,
inside a function (a lazy import is still a dependency) and under ``if TYPE_CHECKING:``.
The one allowance: an import under ``if TYPE_CHECKING:`` never runs (its module has
``from __future__ import annotations``, checked here, so annotations stay strings), so it
is left out of the cycle check; it must still point down or sideways like any other.
``codegen.runtime.library`` and ``codegen.runtime.functions`` use this: the two are one layer,
the compiled library, and functions only names the Library type.

The modules that moved (issue 28) keep their old paths as aliases (``codegen/_moved.py``):
``test_old_paths`` checks that each is the new module itself, that the deprecated ones warn
and that nothing inside codegen reaches one.

The runtime computes and codegen.presentation draws (issue 49): only
codegen.presentation.figures imports matplotlib, and no module sets another's attributes at
import (``Branches.plot`` once drew through a function that codegen.runtime.api patched in).

A submodule's import of its parent package (which Python runs first) is not counted: the
edges are what the source names. ``from X import name`` is an edge to ``X.name`` where that
is a module of codegen, else to ``X``. A new module has to be placed in ``LAYERS``.
"""
from __future__ import annotations

import ast
import json
import subprocess
import sys
import warnings
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "codegen"

#: Bottom to top: a module may import from its own layer or one below, never from above.
#: A name ending in ".*" is every module of that subpackage.
LAYERS: list[tuple[str, ...]] = [
    # plumbing, standard library and numpy only, used by both sides; codegen._moved is the
    # helper of the old-path aliases at the top
    ("codegen", "codegen.errors", "codegen.files", "codegen.resources", "codegen._moved"),
    # codegen/compiler/: model -> derivation -> C emission -> verification -> generation, build
    ("codegen.compiler",),
    ("codegen.compiler.model.*",),
    ("codegen.compiler.derivation.*",),
    ("codegen.compiler.emission.*",),
    ("codegen.compiler.verification", "codegen.compiler.verification_multibody"),
    ("codegen.compiler.generate",),
    ("codegen.compiler.build",),
    # codegen/runtime/: what is computed with a compiled library, returned as data (it draws
    # nothing: no matplotlib, test_only_the_presentation_imports_matplotlib). Its helper, one
    # compiled library, then what is computed with it, then the entry point
    ("codegen.runtime", "codegen.runtime.joining"),
    ("codegen.runtime.library", "codegen.runtime.functions"),
    ("codegen.runtime.analysis",),
    ("codegen.runtime.batch", "codegen.runtime.folds", "codegen.runtime.simulation",
     "codegen.runtime.sweep", "codegen.runtime.multibody"),
    ("codegen.runtime.branches", "codegen.runtime.response",
     "codegen.runtime.multibody_response", "codegen.runtime.multibody_motion",
     "codegen.runtime.drawing"),
    ("codegen.runtime.api",),
    # codegen/presentation/: the runtime's results drawn; figures is where matplotlib is
    # imported (when a figure is drawn), the rest draw through it
    ("codegen.presentation.figures",),
    ("codegen.presentation.*",),
    # the products: a user's model file generated, built and loaded (user_model), a library
    # written as an FMU (fmu); above both the compiler and the runtime, below the command line
    ("codegen.user_model", "codegen.fmu"),
    ("codegen.cli.*",),   # the verbs, what they share and report.py; codegen.cli (__init__) too
    ("codegen.__main__",),
    # the old paths of moved modules (codegen/api.py, codegen/analysis.py, ...): each aliases
    # its new module (see codegen/_moved.py), so it sits above everything it may name; nothing
    # in codegen imports one (an import of a shim from below would fail test_no_upward_import)
    ("codegen.api", "codegen.model", "codegen.analysis", "codegen.batch",
     "codegen.branches", "codegen.build_ext", "codegen.derivation", "codegen.emission",
     "codegen.folds", "codegen.functions", "codegen.generate",
     "codegen.joining", "codegen.library", "codegen.report", "codegen.simulation",
     "codegen.sweep", "codegen.verification"),
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


def outside_imports(module: str) -> set[str]:
    """The top-level names of what ``module`` imports from outside codegen (``numpy``,
    ``matplotlib``, ...): every absolute Import and ImportFrom, lazy ones included."""
    path = MODULES[module]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {alias.name.partition(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            found.add(node.module.partition(".")[0])
    return found - {"codegen"}


#: The one module that imports matplotlib, when a figure is drawn (the ``plot`` extra); the
#: rest of codegen.presentation draws through it, and nothing below that layer draws at all.
MATPLOTLIB = "codegen.presentation.figures"


def test_every_module_has_a_layer():
    for module in MODULES:
        layer_of(module)


def test_no_upward_import():
    upward = [f"{module} (layer {layer_of(module)}) imports {target} (layer {layer_of(target)})"
              for module in MODULES for target, _ in imports(module)
              if layer_of(target) > layer_of(module)]
    assert not upward, "imports from a higher layer:\n" + "\n".join(upward)


def test_only_the_presentation_imports_matplotlib():
    """The runtime and the compiler compute; codegen.presentation draws their results. Only
    its figures module names matplotlib (directly or in a function), and importing every
    module of the runtime and the compiler loads no matplotlib through anything else."""
    importing = sorted(m for m in MODULES if "matplotlib" in outside_imports(m))
    assert importing == [MATPLOTLIB], importing
    presentation = layer_of(MATPLOTLIB)
    for module in MODULES:
        if module.startswith(("codegen.runtime", "codegen.compiler")):
            assert layer_of(module) < presentation, module
    below = sorted(m for m in MODULES if m.startswith(("codegen.runtime", "codegen.compiler")))
    code = ("import importlib, json, sys\n"
            "for name in json.loads(sys.argv[1]):\n"
            "    importlib.import_module(name)\n"
            "print(json.dumps(sorted(m for m in sys.modules if m.partition('.')[0] == "
            "'matplotlib')))")
    run = subprocess.run([sys.executable, "-c", code, json.dumps(below)], capture_output=True,
                         text=True, check=True)
    assert json.loads(run.stdout) == []


def test_the_runtime_is_not_patched_from_above():
    """No module assigns to another module's attribute at import (``branches.figure =
    ...`` was one): what a module calls is what it imports."""
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text(), str(path))
        names = {alias.asname or alias.name.partition(".")[0] for node in tree.body
                 if isinstance(node, (ast.Import, ast.ImportFrom)) for alias in node.names}
        patched = [ast.unparse(target) for node in tree.body if isinstance(node, ast.Assign)
                   for target in node.targets if isinstance(target, ast.Attribute)
                   and isinstance(target.value, ast.Name) and target.value.id in names]
        assert not patched, (module, patched)


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
    assert ("codegen.runtime.library", False) in imports("codegen.runtime.analysis")
    assert ("codegen.compiler.generate", False) in imports("codegen.cli.common")  # in a function
    assert ("codegen", False) in imports("codegen.compiler.emission.render")  # from ... import x
    assert ("codegen.compiler.model", False) in imports("codegen.compiler.derivation.dynamics")
    assert (("codegen.compiler.model.mechanism", False)
            in imports("codegen.compiler.derivation.dynamics"))
    assert ("codegen.runtime.branches", True) in imports("codegen.cli.report")
    assert ("codegen.runtime.analysis", False) in imports("codegen.analysis")  # an old path
    assert ("codegen.runtime.branches", False) in imports("codegen.presentation.branches")
    assert "matplotlib" in outside_imports(MATPLOTLIB)  # in a function
    assert {"numpy", "sympy"} <= outside_imports("codegen.runtime.drawing")  # sympy: lazy


#: old path -> new module; the first two are supported public names, the rest deprecated.
MOVED = {"codegen.api": "codegen.runtime.api", "codegen.model": "codegen.compiler.model",
         **{f"codegen.{m}": f"codegen.runtime.{m}" for m in (
             "analysis", "batch", "branches", "folds", "functions",
             "joining", "library", "simulation", "sweep")},
         **{f"codegen.{m}": f"codegen.compiler.{m}" for m in (
             "derivation", "emission", "generate", "verification")},
         "codegen.build_ext": "codegen.compiler.build", "codegen.report": "codegen.cli.report"}


def test_old_paths():
    """Every old path is its new module (the same object, so a monkeypatch through either
    reaches both); the deprecated ones say where it went; codegen itself uses none of them
    (importing the runtime, the compiler and the command line warns nothing)."""
    top = len(LAYERS) - 1
    assert set(MOVED) == {m for m in MODULES if m.count(".") == 1 and layer_of(m) == top}
    code = ("import warnings, importlib, json, sys; warnings.simplefilter('always'); "
            "out = {}\n"
            "for old, new in json.loads(sys.argv[1]).items():\n"
            "    with warnings.catch_warnings(record=True) as caught:\n"
            "        warnings.simplefilter('always')\n"
            "        module = importlib.import_module(old)\n"
            "    out[old] = [module is importlib.import_module(new), "
            "[str(w.message) for w in caught if w.category is DeprecationWarning]]\n"
            "print(json.dumps(out))")
    run = subprocess.run([sys.executable, "-c", code, json.dumps(MOVED)], capture_output=True,
                         text=True, check=True)
    seen = json.loads(run.stdout)
    for old, new in MOVED.items():
        same, warned = seen[old]
        assert same, old
        if old in ("codegen.api", "codegen.model"):
            assert not warned, (old, warned)
        else:
            assert any(new in message for message in warned), (old, warned)
    subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c",
                    "import codegen.runtime.api, codegen.compiler.generate, codegen.cli, "
                    "codegen.user_model, codegen.compiler.model.four_bar"], check=True)
    # a submodule through an old package path is the new one too
    import codegen.compiler.model.mechanism
    import codegen.model.mechanism  # noqa: F401
    assert codegen.model.mechanism is codegen.compiler.model.mechanism
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        import codegen.derivation.algebra  # noqa: F401
        import codegen.compiler.derivation.algebra
    assert codegen.derivation.algebra is codegen.compiler.derivation.algebra
