"""Model -> derivation -> plan -> rendered files, written to (or compared with) a folder.

Each mechanism's library goes to its own folder (generated/NAME/); the hand-written runtime
(templates/runtime/) is copied once, unchanged, to generated/runtime/, shared by all.
"""
from __future__ import annotations

import difflib
import warnings
from pathlib import Path

import sympy

from .derivation import derive
from .emission.plan import build_plan
from .emission.render import render
from .model import SHIPPED, Mechanism, load

ROOT = Path(__file__).resolve().parent.parent
TEMPLATES = ROOT / "templates"
GENERATED = ROOT / "generated"
RUNTIME = "runtime"
BUILD_BYPRODUCTS = (".o",)  # objects a compiler may leave beside the sources

#: The SymPy release the committed generated/ was produced and tested with (pyproject pins it);
#: common-subexpression elimination and printing may differ between releases.
TESTED_SYMPY = "1.14.0"


def _present(out: Path) -> set[str]:
    if not out.is_dir():
        return set()
    return {p.name for p in out.iterdir() if p.is_file() and p.suffix not in BUILD_BYPRODUCTS}


def emit(mechanism: Mechanism, templates: Path = TEMPLATES) -> dict[str, str]:
    """File name -> text of one mechanism's library."""
    if sympy.__version__ != TESTED_SYMPY:
        warnings.warn(f"SymPy {sympy.__version__} is not the tested {TESTED_SYMPY}: the "
                      f"generated files may differ from the committed ones", stacklevel=2)
    return render(build_plan(derive(mechanism)), templates)


def runtime(templates: Path = TEMPLATES) -> dict[str, str]:
    """File name -> text of the shared runtime."""
    return {p.name: p.read_text() for p in sorted((templates / RUNTIME).iterdir()) if p.is_file()}


def emit_all(names=SHIPPED, templates: Path = TEMPLATES) -> dict[str, dict[str, str]]:
    """Folder -> its files, for the runtime and every named mechanism."""
    folders = {RUNTIME: runtime(templates)}
    for name in names:
        mechanism = load(name)
        folders[mechanism.name] = emit(mechanism, templates)
    return folders


def write_folder(out: Path, files: dict[str, str]) -> list[str]:
    """Write files into out (only those that changed), removing stale ones."""
    out.mkdir(parents=True, exist_ok=True)
    for stale_file in _present(out) - set(files):
        (out / stale_file).unlink()
    for name, text in files.items():
        path = out / name
        if not path.is_file() or path.read_text() != text:
            path.write_text(text)
    return sorted(files)


def write(out: Path = GENERATED, names=SHIPPED, templates: Path = TEMPLATES) -> list[str]:
    folders = emit_all(names, templates)
    return [f"{folder}/{name}" for folder, files in folders.items()
            for name in write_folder(out / folder, files)]


def stale(out: Path = GENERATED, names=SHIPPED, templates: Path = TEMPLATES) -> str:
    """A unified diff of committed files against what the generator emits now ('' if none)."""
    diff = []
    folders = emit_all(names, templates)
    present = {p.name for p in out.iterdir() if p.is_dir()} if out.is_dir() else set()
    for folder in sorted(set(folders) | present):
        files = folders.get(folder, {})
        here = _present(out / folder)
        for name in sorted(set(files) | here):
            old = (out / folder / name).read_text() if name in here else ""
            new = files.get(name, "")
            diff += difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                         f"committed/{folder}/{name}",
                                         f"generator/{folder}/{name}")
    return "".join(diff)
