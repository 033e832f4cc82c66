"""`mechvib generate`: the C libraries written, or a model of one's own built."""
from __future__ import annotations

import sys
import time
from pathlib import Path

from . import common

EXAMPLES = """\
examples:
  {prog} generate                             regenerate generated/ (in a checkout)
  {prog} generate --check                     exit 1 if generated/ is stale
  {prog} generate --mechanism slider_crank --out /tmp/gen
  {prog} generate --model my_model.py --out build/mine"""


def run(args) -> int:
    generate = common.generator()
    start = time.perf_counter()
    if args.model:
        from ..user_model import library as user_library

        out = Path(args.out or "build/codegen")
        library = user_library(args.model, out, progress=common.stage, rebuild=True)
        print(f"wrote and built {library.PREFIX} ({library.TITLE}) in {out} "
              f"in {time.perf_counter() - start:.1f} s")
        return 0
    out = Path(args.out) if args.out else generate.default_output()
    names = ([common.checked_mechanism(args.mechanism, generate.EVERY)] if args.mechanism
             else list(generate.EVERY))
    cache = None if args.no_cache else generate.default_cache()
    if args.check:
        diff = generate.stale(out, names, cache=cache)
        if diff:
            sys.stdout.write(diff)
            print(f"{out} is stale: regenerate it (`make generate` in a checkout) and commit "
                  "the result", file=sys.stderr)
            return 1
        print(f"{out} is up to date ({time.perf_counter() - start:.1f} s)")
        return 0
    files = generate.write(out, names, cache=cache)
    changed = ": " + ", ".join(files) if files else " (every file was already up to date)"
    print(f"wrote {len(files)} files to {out} in {time.perf_counter() - start:.1f} s{changed}")
    return 0


def add(verbs, prog: str) -> None:
    gen = common.verb(verbs, "generate", "derive the mechanics and write the C library",
                      EXAMPLES, prog, run)
    common.mechanism_options(gen, "output folder (default: the checkout's generated/, or "
                                  "./generated when installed; build/codegen for --model, "
                                  "where the library is also built)")
    gen.add_argument("--check", action="store_true",
                     help="only compare the folder with what would be written; exit 1 if stale")
    gen.add_argument("--no-cache", action="store_true",
                     help="derive every mechanism again, even where nothing it is made from "
                          "changed since the last run in this checkout (build/generate-cache)")
