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
    if library.dof > 1:
        return _several_coordinates(library, params, args.json)
    result = analyze(params, args.method)
    if args.json:
        print(json.dumps(result.to_dict(), indent=1))
    else:
        values = common.params_line(vars(params), library.UNITS)
        print(paragraph(f"Vibration analysis of {library.TITLE}: {values}") + "\n")
        print(table(result, wide=args.wide, sigma=args.sigma))
    return 0


def _several_coordinates(library, params, as_json: bool) -> int:
    """Every equilibrium of a mechanism with n coordinates: its coordinates (angles in
    degrees), stability, and each mode's natural frequency and damping ratio; then the boxes
    that could not be decided."""
    import json
    import math

    from .report import paragraph

    result = library.analyze(params)
    if as_json:
        print(json.dumps(result.as_dict(), indent=1))
        return 0
    units = [c["unit"] for c in library.SPEC["coordinates"]]

    def shown(values):
        return [math.degrees(v) if unit == "rad" else v for v, unit in zip(values, units)]

    names = [f"{c} [{'deg' if u == 'rad' else u}]" for c, u in zip(result.coordinates, units)]
    values = common.params_line(vars(params), library.UNITS)
    print(paragraph(f"Vibration analysis of {library.TITLE}: {values}") + "\n")
    modes = [f"{h} {j + 1}" for j in range(library.dof) for h in ("omega_n", "zeta")]
    header = ["#", *names, "stability", *modes]
    rows = [[str(i + 1), *(f"{v:.6f}" for v in shown(e.theta)), e.stability,
             *(f"{x:.6g}" for j in range(library.dof)
               for x in (e.frequencies[j], e.modal_damping[j]))]
            for i, e in enumerate(result.equilibria)]
    widths = [max(len(r[k]) for r in [header, *rows]) for k in range(len(header))]
    for row in [header, *rows]:
        print("  ".join(cell.rjust(w) for cell, w in zip(row, widths)))
    print(f"\n{len(result.equilibria)} equilibria, each proven to be the only one in its box; "
          "omega_n [rad/s] undamped (nan: unstable mode), zeta each mode's damping ratio")
    for u in result.uncertain:
        box = ", ".join(f"{n} in [{a:.6f}, {b:.6f}]" for n, a, b in
                        zip(names, shown(u.lo), shown(u.hi)))
        print(f"uncertain ({u.kind}, not an equilibrium): {box}")
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
                     help="print one JSON object (angles in degrees) instead of the table")
    ana.add_argument("--wide", action="store_true",
                     help="every column: M_EQ, B_EQ and the eigenvalues too")
    ana.add_argument("--sigma", action="store_true",
                     help="also print the polynomial's coefficients sigma_i")
    common.method_option(ana)
