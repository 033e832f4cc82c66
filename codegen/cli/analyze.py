"""`mechvib analyze`: every equilibrium of one parameter set and its vibration."""
from __future__ import annotations

from . import common

EXAMPLES = """\
examples:
  {prog} analyze
  {prog} analyze --set F=0 --set b=0 --wide
  {prog} analyze --mechanism torsion_pendulum --json
  {prog} analyze --method isolate --sigma
  {prog} analyze --model my_model.py --out build/mine
  {prog} analyze --mechanism double_pendulum --set k_1=20"""


def run(args) -> int:
    import json

    from ..runtime.analysis import analyze
    from .report import paragraph, table

    library = common.load_library(args, args.out)
    params = library.example_params(**common.overrides(args.set, library.UNITS))
    result = analyze(params, args.method)
    if args.json:
        print(json.dumps(result.to_dict(), indent=1))
    else:
        values = common.params_line(vars(params), library.UNITS)
        print(paragraph(f"Vibration analysis of {library.TITLE}: {values}") + "\n")
        print(table(result, wide=args.wide, sigma=args.sigma))
    return 0


def add(verbs, prog: str) -> None:
    ana = common.verb(verbs, "analyze",
                      "every equilibrium and its vibration (the paper's Table 3)",
                      EXAMPLES, prog, run)
    common.mechanism_options(ana, "with --model: where its library is generated and built "
                                  "(default: the per-user cache ~/.cache/mechvib; a build "
                                  "there or in DIR is reused while the file is unchanged)")
    common.set_option(ana)
    ana.add_argument("--json", action="store_true",
                     help="print one JSON object instead of the table, of one shape for every "
                          "mechanism (angles in degrees, under NAME_deg keys)")
    ana.add_argument("--wide", action="store_true",
                     help="every column: M_EQ, B_EQ and the eigenvalues too")
    ana.add_argument("--sigma", action="store_true",
                     help="also print the polynomial's coefficients sigma_i")
    common.method_option(ana)
