"""`mechvib list`: the mechanisms this installation has compiled."""
from __future__ import annotations

from . import common

EXAMPLES = """\
examples:
  {prog} list"""


def run(args) -> int:
    from ..runtime.api import load

    for name in common.shipped():
        library = load(name)
        route = ("polynomial" if library.has_polynomial else "isolation" if library.dof == 1
                 else f"{library.dof} coordinates, box isolation")
        print(f"{name:<18} {library.TITLE} ({len(library.PARAMETER_NAMES)} parameters, "
              f"{route})")
    return 0


def add(verbs, prog: str) -> None:
    common.verb(verbs, "list", "the mechanisms this installation has compiled", EXAMPLES, prog,
                run)
