"""Layer 7: the command line, ``python -m codegen`` (or ``doughty``)."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def _generate(args) -> int:
    try:  # the generator needs sympy, jinja2 and the checkout's templates/; analysis does not
        from . import generate
    except ImportError as error:
        print(f"error: generate needs the generator's dependencies ({error.name} is missing): "
              "pip install -e '.[generate]' in a checkout", file=sys.stderr)
        return 2
    if not generate.TEMPLATES.is_dir():
        print(f"error: no templates at {generate.TEMPLATES}: run generate from a checkout",
              file=sys.stderr)
        return 2

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


def _assignment(text: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    return name.strip(), value.strip()


def _overrides(pairs: list[tuple[str, str]]) -> dict[str, float]:
    """Values as numbers; a ValueError names the parameter (reported as one line)."""
    values = {}
    for name, value in pairs:
        try:
            values[name] = float(value)
        except ValueError:
            raise ValueError(f"{name}: {value!r} is not a number") from None
    return values


def _analyze(args) -> int:
    import json

    from . import api
    from .analysis import analyze, table

    try:
        params = api.example_params(**_overrides(args.set))
        result = analyze(params)
    except ValueError as error:  # LibraryError included: one line, no traceback
        print(f"error: {error}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(result.to_dict(), indent=1))
    else:
        values = ", ".join(f"{k}={v:g}" for k, v in vars(params).items())
        print(f"Vibration analysis of Doughty's mechanism: {values}\n")
        print(table(result))
    return 0


def parser() -> argparse.ArgumentParser:
    GENERATED = Path(__file__).resolve().parent.parent / "generated"

    top = argparse.ArgumentParser(prog="python -m codegen", description=__doc__)
    verbs = top.add_subparsers(dest="verb", required=True)
    gen = verbs.add_parser("generate", help="derive the mechanics and write the C library")
    gen.add_argument("--out", default=str(GENERATED), help="output folder (default: generated/)")
    gen.add_argument("--check", action="store_true",
                     help="only compare the folder with what would be written; exit 1 if stale")
    gen.set_defaults(run=_generate)
    ana = verbs.add_parser("analyze", help="every equilibrium and its vibration (Table 3)")
    ana.add_argument("--set", action="append", type=_assignment, default=[], metavar="NAME=VALUE",
                     help="override a Table 2 parameter (repeatable): H, L, a, m_A, m_B, m_C, "
                          "k, b, l_ND, F, g")
    ana.add_argument("--json", action="store_true", help="print one JSON object")
    ana.set_defaults(run=_analyze)
    return top


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    return args.run(args)
