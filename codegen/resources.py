"""Where the templates, the C runtime and the shipped C libraries are: the checkout's, or the
installed copies; and the C compiler flags, which are written once, in the runtime's cflags.txt.

Run from a checkout (``pip install -e .``, or ``python -m codegen`` inside the repository),
the package uses the checkout's ``templates/``, ``runtime/`` and ``generated/`` themselves.
Installed from a wheel or ``pip install .``, it uses the copies the build put inside the
package (``codegen/data/templates``, ``codegen/data/runtime`` and ``codegen/data/generated``,
see setup.py); those are read only, never written. Standard library only: importable without
the generator's dependencies, and loadable by path (codegen/compiler/build.py, which setuptools
runs outside the package, does so).
"""
from __future__ import annotations

from pathlib import Path

#: The folder of the ``codegen`` package.
PACKAGE = Path(__file__).resolve().parent
#: In a checkout, the repository; installed, the site-packages folder.
ROOT = PACKAGE.parent
#: The copies of templates/, runtime/ and generated/ inside an installed package.
DATA = PACKAGE / "data"
#: The folder of the C runtime, in the checkout (runtime/), in generated/ (its copy, beside
#: the libraries) and inside an installed package.
RUNTIME = "runtime"
#: The file of runtime/ that holds every set of C compiler flags (see cflags()).
CFLAGS = "cflags.txt"


def in_checkout() -> bool:
    """True when the package runs from a source checkout (its parent holds pyproject.toml
    and templates/), False when it runs from an installed copy."""
    return (ROOT / "pyproject.toml").is_file() and (ROOT / "templates").is_dir()


def templates() -> Path:
    """The Jinja2 templates (``*.j2``, and the FMU's in ``fmi/``)."""
    return ROOT / "templates" if in_checkout() else DATA / "templates"


def runtime() -> Path:
    """The hand-written C runtime: its sources, the FMI glue (``fmi/``) and ``cflags.txt``."""
    return ROOT / RUNTIME if in_checkout() else DATA / RUNTIME


def generated() -> Path:
    """The shipped C libraries: ``NAME/`` per mechanism and the shared ``runtime/`` (a copy
    of the runtime's sources)."""
    return ROOT / "generated" if in_checkout() else DATA / "generated"


#: The file names' start of the shipped libraries' extension modules, codegen/_native_NAME.*.so.
NATIVE = "_native_"


def compiled() -> list[str]:
    """Names of the mechanisms compiled into this installation, read from the extension
    modules' file names in the package folder (nothing is imported)."""
    return sorted({p.name.split(".")[0][len(NATIVE):] for p in PACKAGE.iterdir()
                   if p.name.startswith(NATIVE) and p.suffix in (".so", ".pyd")})


def cflag_sets(path: Path | None = None) -> dict[str, list[str]]:
    """Every named set of C compiler flags of ``runtime/cflags.txt`` (or of ``path``): its
    lines ``NAME = FLAGS``, the flags split at spaces; ``#`` starts a comment line."""
    text = (runtime() / CFLAGS if path is None else path).read_text()
    sets = {}
    for line in text.splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            name, _, flags = line.partition("=")
            sets[name.strip()] = flags.split()
    return sets


def cflags(*names: str) -> list[str]:
    """The flags of the named sets of ``runtime/cflags.txt``, in order: e.g. ``cflags("base",
    "optimize")``; a KeyError names a set the file does not have."""
    sets = cflag_sets()
    return [flag for name in names for flag in sets[name]]


__all__ = ["CFLAGS", "DATA", "NATIVE", "PACKAGE", "ROOT", "RUNTIME", "cflag_sets", "cflags",
           "compiled", "generated", "in_checkout", "runtime", "templates"]
