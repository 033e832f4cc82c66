"""`mechvib sources`: where a shipped library's C files are, or a copy of them."""
from __future__ import annotations

import shutil
from pathlib import Path

from . import common

EXAMPLES = """\
examples:
  {prog} sources                              where the C files of the paper's example are
  {prog} sources --mechanism four_bar --copy vendor/four_bar
  cc -std=c99 -Ivendor/four_bar app.c vendor/four_bar/*.c -lm"""


def run(args) -> int:
    """Where the C files of a shipped library are, or a copy of them in a folder."""
    from ..resources import RUNTIME, generated

    name = common.checked_mechanism(args.mechanism or common.DEFAULT_MECHANISM, common.shipped())
    root = generated()
    folders = [root / name, root / RUNTIME]
    if not folders[0].is_dir():
        have = ", ".join(sorted(p.name for p in root.iterdir() if p.is_dir() and
                                p.name != RUNTIME)) if root.is_dir() else "none"
        raise ValueError(f"{name}: no C sources in this installation (it has {have})")
    files = sorted(f for folder in folders for f in folder.iterdir()
                   if f.suffix in (".c", ".h"))
    if not args.copy:
        for folder in folders:
            print(folder)
        return 0
    out = Path(args.copy)
    out.mkdir(parents=True, exist_ok=True)
    for f in files:
        shutil.copyfile(f, out / f.name)
    print(f"copied {len(files)} files to {out}: " + ", ".join(f.name for f in files))
    return 0


def add(verbs, prog: str) -> None:
    src = common.verb(verbs, "sources",
                      "print the folders of a library's C sources, or copy them",
                      EXAMPLES, prog, run)
    common.mechanism_options(src, None)
    src.add_argument("--copy", metavar="DIR",
                     help="copy the .c and .h files (library and runtime) into DIR")
