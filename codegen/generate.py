"""Model -> derivation -> plan -> rendered files, written to (or compared with) a folder.

Hand-written C sources in templates/c/ are copied unchanged beside the generated ones.
"""
from __future__ import annotations

import difflib
import warnings
from pathlib import Path

import sympy

from .derivation import derive
from .emission.plan import build_plan
from .emission.render import render
from .model import Mechanism, doughty

ROOT = Path(__file__).resolve().parent.parent
TEMPLATES = ROOT / "templates"
GENERATED = ROOT / "generated"
BUILD_BYPRODUCTS = (".o",)  # objects a compiler may leave beside the sources


def _present(out: Path) -> set[str]:
    if not out.is_dir():
        return set()
    return {p.name for p in out.iterdir() if p.is_file() and p.suffix not in BUILD_BYPRODUCTS}


#: The SymPy release the committed generated/ was produced and tested with (pyproject pins it);
#: common-subexpression elimination and printing may differ between releases.
TESTED_SYMPY = "1.14.0"


def emit(mechanism: Mechanism | None = None, templates: Path = TEMPLATES) -> dict[str, str]:
    """File name -> text of every file in generated/."""
    if sympy.__version__ != TESTED_SYMPY:
        warnings.warn(f"SymPy {sympy.__version__} is not the tested {TESTED_SYMPY}: the "
                      f"generated files may differ from the committed ones", stacklevel=2)
    mechanism = mechanism or doughty.build()
    files = render(build_plan(derive(mechanism)), templates)
    for source in sorted((templates / "c").glob("*.c")):
        files[source.name] = source.read_text()
    return files


def write(out: Path = GENERATED, templates: Path = TEMPLATES) -> list[str]:
    out.mkdir(parents=True, exist_ok=True)
    files = emit(templates=templates)
    for stale in _present(out) - set(files):
        (out / stale).unlink()
    for name, text in files.items():
        (out / name).write_text(text)
    return sorted(files)


def stale(out: Path = GENERATED, templates: Path = TEMPLATES) -> str:
    """A unified diff of committed files against what the generator emits now ('' if none)."""
    files = emit(templates=templates)
    present = _present(out)
    diff = []
    for name in sorted(set(files) | present):
        old = (out / name).read_text() if name in present else ""
        new = files.get(name, "")
        diff += difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                     f"committed/{name}", f"generator/{name}")
    return "".join(diff)
