"""Layer 7: the command line, ``python -m codegen`` (or ``doughty``)."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .api import shipped


#: The mechanism a command works on when none is named: the paper's example.
DEFAULT_MECHANISM = "doughty"


def _generator():
    try:  # the generator needs sympy, jinja2 and the checkout's templates/; analysis does not
        from . import generate
    except ImportError as error:
        raise SystemExit(f"error: generate needs the generator's dependencies ({error.name} is "
                         "missing): pip install -e '.[generate]' in a checkout") from None
    if not generate.TEMPLATES.is_dir():
        raise SystemExit(f"error: no templates at {generate.TEMPLATES}: run generate from a "
                         "checkout")
    return generate


def _user_library(generate, model: str, out: Path):
    """Generate and build a user's model into out; its Library."""
    from .api import load_from
    from .build_ext import build_into
    from .model import load

    mechanism = load(model)
    generate.write_folder(out / generate.RUNTIME, generate.runtime())
    generate.write_folder(out / mechanism.name, generate.emit(mechanism))
    build_into(out, mechanism.name)
    return load_from(out, mechanism.name)


def _generate(args) -> int:
    generate = _generator()
    start = time.perf_counter()
    if args.model:
        out = Path(args.out or "build/codegen")
        library = _user_library(generate, args.model, out)
        print(f"wrote and built {library.PREFIX} ({library.TITLE}) in {out} "
              f"in {time.perf_counter() - start:.1f} s")
        return 0
    out = Path(args.out) if args.out else generate.GENERATED
    names = [args.mechanism] if args.mechanism else list(generate.SHIPPED)
    if args.check:
        diff = generate.stale(out, names)
        if diff:
            sys.stdout.write(diff)
            print(f"{out} is stale: run `make generate` and commit the result", file=sys.stderr)
            return 1
        print(f"{out} is up to date ({time.perf_counter() - start:.1f} s)")
        return 0
    files = generate.write(out, names)
    print(f"wrote {len(files)} files to {out} in {time.perf_counter() - start:.1f} s: "
          + ", ".join(files))
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

    from .analysis import analyze, table
    from .api import load

    if args.model:
        library = _user_library(_generator(), args.model, Path(args.out or "build/codegen"))
    else:
        library = load(args.mechanism or DEFAULT_MECHANISM)
    params = library.example_params(**_overrides(args.set))
    result = analyze(params, args.method)
    if args.json:
        print(json.dumps(result.to_dict(), indent=1))
    else:
        values = ", ".join(f"{k}={v:g}" for k, v in vars(params).items())
        print(f"Vibration analysis of {library.TITLE}: {values}\n")
        print(table(result))
    return 0


def _mechanism_options(verb: argparse.ArgumentParser, out_help: str) -> None:
    which = verb.add_mutually_exclusive_group()
    which.add_argument("--mechanism", metavar="NAME",
                       help=f"a shipped mechanism: {', '.join(shipped())} "
                            f"(default {DEFAULT_MECHANISM})")
    which.add_argument("--model", metavar="FILE",
                       help="a model file of your own (Python, defining build() -> Mechanism)")
    verb.add_argument("--out", metavar="DIR", help=out_help)


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(prog="python -m codegen", description=__doc__)
    verbs = top.add_subparsers(dest="verb", required=True)
    gen = verbs.add_parser("generate", help="derive the mechanics and write the C library")
    _mechanism_options(gen, "output folder (default: generated/, or build/codegen for --model; "
                            "with --model the library is also built there)")
    gen.add_argument("--check", action="store_true",
                     help="only compare the folder with what would be written; exit 1 if stale")
    gen.set_defaults(run=_generate)
    ana = verbs.add_parser("analyze", help="every equilibrium and its vibration (Table 3)")
    _mechanism_options(ana, "with --model: where its library is generated and built "
                            "(default: build/codegen)")
    ana.add_argument("--set", action="append", type=_assignment, default=[], metavar="NAME=VALUE",
                     help="override a parameter of the example (repeatable)")
    ana.add_argument("--json", action="store_true", help="print one JSON object")
    ana.add_argument("--method", choices=("auto", "polynomial", "isolate"), default="auto",
                     help="polynomial: the roots of sigma, classified by branch; isolate: the "
                          "zeros of G itself, each proven in an interval, with what double "
                          "precision cannot decide listed as uncertain; auto (default): "
                          "polynomial where G is algebraic, else isolate")
    ana.set_defaults(run=_analyze)
    return top


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.run(args)
    except ValueError as error:  # bad input (LibraryError, ModelError included): one line
        print(f"error: {error}", file=sys.stderr)
        return 2
