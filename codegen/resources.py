"""Where the templates and the shipped C libraries are: the checkout's, or the installed copies.

Run from a checkout (``pip install -e .``, or ``python -m codegen`` inside the repository),
the package uses the checkout's ``templates/`` and ``generated/`` themselves. Installed from
a wheel or ``pip install .``, it uses the copies the build put inside the package
(``codegen/data/templates`` and ``codegen/data/generated``, see setup.py); those are read
only, never written. Standard library only: importable without the generator's dependencies.
"""
from __future__ import annotations

from pathlib import Path

#: The folder of the ``codegen`` package.
PACKAGE = Path(__file__).resolve().parent
#: In a checkout, the repository; installed, the site-packages folder.
ROOT = PACKAGE.parent
#: The copies of templates/ and generated/ inside an installed package.
DATA = PACKAGE / "data"


def in_checkout() -> bool:
    """True when the package runs from a source checkout (its parent holds pyproject.toml
    and templates/), False when it runs from an installed copy."""
    return (ROOT / "pyproject.toml").is_file() and (ROOT / "templates").is_dir()


def templates() -> Path:
    """The Jinja2 templates (``*.j2``) and the hand-written runtime (``runtime/``)."""
    return ROOT / "templates" if in_checkout() else DATA / "templates"


def generated() -> Path:
    """The shipped C libraries: ``NAME/`` per mechanism and the shared ``runtime/``."""
    return ROOT / "generated" if in_checkout() else DATA / "generated"


#: The file names' start of the shipped libraries' extension modules, codegen/_native_NAME.*.so.
NATIVE = "_native_"


def compiled() -> list[str]:
    """Names of the mechanisms compiled into this installation, read from the extension
    modules' file names in the package folder (nothing is imported)."""
    return sorted({p.name.split(".")[0][len(NATIVE):] for p in PACKAGE.iterdir()
                   if p.name.startswith(NATIVE) and p.suffix in (".so", ".pyd")})


__all__ = ["DATA", "NATIVE", "PACKAGE", "ROOT", "compiled", "generated", "in_checkout",
           "templates"]
