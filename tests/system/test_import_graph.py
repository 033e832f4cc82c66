"""The package in layers (issue 28): every import in codegen/ goes down or sideways, never up,
and no modules import each other in a cycle.

Every Import and ImportFrom node of every module counts, wherever it is: at module level,
inside a function (a lazy import is still a dependency) and under ``if TYPE_CHECKING:``.
The one allowance: an import under ``if TYPE_CHECKING:`` never runs (its module has
``from __future__ import annotations``, checked here, so annotations stay strings), so it
is left out of the cycle check; it must still point down or sideways like any other.
``codegen.runtime.library`` and ``codegen.runtime.functions`` use this: the two are one layer,
the compiled library, and functions only names the Library type.

Two short public names stand above the layers (docs/python.md, "Import paths"): ``codegen.api``
(the objects of ``codegen.runtime.api``) and ``codegen.model.mechanism`` (those of
``codegen.compiler.model.mechanism``, what a model file imports); ``test_public_names`` checks
that they are those objects, that the model's loads no shipped model and no runtime, and that
the old paths of issue 28's layout (``codegen.analysis``, ...) are gone.

The runtime computes and codegen.presentation draws (issue 49): only
codegen.presentation.figures imports matplotlib, and no module sets another's attributes at
import (``Branches.plot`` once drew through a function that codegen.runtime.api patched in).

A submodule's import of its parent package (which Python runs first) is not counted: the
edges are what the source names. ``from X import name`` is an edge to ``X.name`` where that
is a module of codegen, else to ``X``. A new module has to be placed in ``LAYERS``.
"""
from __future__ import annotations

import ast
import importlib
import inspect
import json
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "codegen"

#: Bottom to top: a module may import from its own layer or one below, never from above.
#: A name ending in ".*" is every module of that subpackage.
LAYERS: list[tuple[str, ...]] = [
    # plumbing, standard library and numpy only, used by both sides
    ("codegen", "codegen.errors", "codegen.files", "codegen.resources", "codegen.ccodes"),
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
    # the public short names: codegen.api (runtime.api's objects) and codegen.model (the model
    # file's building blocks, compiler.model.mechanism's); nothing in codegen imports them
    ("codegen.api", "codegen.model.*"),
    # the products: a user's model file generated, built and loaded (user_model), a library
    # written as an FMU (fmu); above both the compiler and the runtime, below the command line
    ("codegen.user_model", "codegen.fmu"),
    ("codegen.cli.*",),   # the verbs, what they share and report.py; codegen.cli (__init__) too
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
    assert ("codegen.runtime.branches", False) in imports("codegen.presentation.branches")
    assert "matplotlib" in outside_imports(MATPLOTLIB)  # in a function
    assert {"numpy", "sympy"} <= outside_imports("codegen.runtime.drawing")  # sympy: lazy
    assert ("codegen.runtime.api", False) in imports("codegen.api")  # a public short name
    assert ("codegen.compiler.model.mechanism", False) in imports("codegen.model.mechanism")


#: The old paths of issue 28's layout, removed: each module is imported from where it is.
OLD_PATHS = ("codegen._moved", "codegen.analysis", "codegen.batch", "codegen.branch_figure",
             "codegen.branches", "codegen.build_ext", "codegen.derivation", "codegen.emission",
             "codegen.figures", "codegen.folds", "codegen.functions", "codegen.generate",
             "codegen.joining", "codegen.library", "codegen.report", "codegen.simulation",
             "codegen.sweep", "codegen.verification", "codegen.model.doughty")

#: What a model file's import must not load: the shipped models, the runtime, the command line.
SHIPPED_MODELS = ("doughty", "slider_crank", "four_bar", "torsion_pendulum", "double_pendulum",
                  "flexible_doughty")


def test_public_names():
    """codegen.api and codegen.model.mechanism are the objects of the modules that define
    them; the old paths are gone."""
    assert not [old for old in OLD_PATHS if old in MODULES], "old paths are back"
    api, runtime_api = (importlib.import_module(m) for m in ("codegen.api",
                                                             "codegen.runtime.api"))
    assert api.__all__ and all(getattr(api, n) is getattr(runtime_api, n) for n in api.__all__)
    assert set(api.__all__) <= set(runtime_api.__all__)
    model, mechanism, defined = (importlib.import_module(m) for m in (
        "codegen.model", "codegen.model.mechanism", "codegen.compiler.model.mechanism"))
    public = {n for n, v in vars(defined).items() if not n.startswith("_") and (
        inspect.isclass(v) or inspect.isfunction(v)) and v.__module__ == defined.__name__}
    assert set(mechanism.__all__) == public | {"TIME"}
    for name in mechanism.__all__:
        assert getattr(mechanism, name) is getattr(defined, name) is getattr(model, name), name


def test_a_model_files_import_loads_no_model_and_no_runtime():
    """``from codegen.model.mechanism import ...`` (every model file's first line) loads the
    model's building blocks, not the shipped models, the runtime, numpy or the compiler's
    derivation."""
    code = ("import sys, json; import codegen.model.mechanism; "
            "print(json.dumps(sorted(sys.modules)))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=PACKAGE.parent)
    loaded = json.loads(run.stdout)
    ours = [m for m in loaded if m.split(".")[0] == "codegen"]
    assert not [m for m in ours if m.rpartition(".")[2] in SHIPPED_MODELS], ours
    assert not [m for m in ours if m.startswith(("codegen.runtime", "codegen.cli",
                                                  "codegen.compiler.derivation"))], ours
    assert not [m for m in loaded if m.split(".")[0] in ("numpy", "cffi", "jinja2")]
    assert len(ours) <= 10, ours  # 8 now: codegen, codegen.model and compiler.model's own
