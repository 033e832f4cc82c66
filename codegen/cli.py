"""Layer 7: the command line, ``python -m codegen`` (or ``doughty``)."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def _generate(args) -> int:
    from . import generate  # the generator needs sympy and jinja2, the analysis does not

    start = time.perf_counter()
    if args.check:
        diff = generate.stale(Path(args.out))
        if diff:
            sys.stdout.write(diff)
            print(f"{args.out} is stale: run `make generate` and commit the result",
                  file=sys.stderr)
            return 1
        print(f"{args.out} is up to date ({time.perf_counter() - start:.1f} s)")
        return 0
    names = generate.write(Path(args.out))
    print(f"wrote {len(names)} files to {args.out} in {time.perf_counter() - start:.1f} s: "
          + ", ".join(names))
    return 0


def parser() -> argparse.ArgumentParser:
    from .generate import GENERATED

    top = argparse.ArgumentParser(prog="python -m codegen", description=__doc__)
    verbs = top.add_subparsers(dest="verb", required=True)
    gen = verbs.add_parser("generate", help="derive the mechanics and write the C library")
    gen.add_argument("--out", default=str(GENERATED), help="output folder (default: generated/)")
    gen.add_argument("--check", action="store_true",
                     help="only compare the folder with what would be written; exit 1 if stale")
    gen.set_defaults(run=_generate)
    return top


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    return args.run(args)
