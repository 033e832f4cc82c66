"""`mechvib branches`: every equilibrium as one parameter varies."""
from __future__ import annotations

from . import common

#: --points' default: codegen.runtime.branches.DEFAULT_POINTS (written here so that building
#: the parser imports no runtime; tests/cli/test_lazy_imports.py holds the two equal).
DEFAULT_POINTS = 1001

EXAMPLES = """\
examples:
  {prog} branches --vary F --from 0 --to 200
  {prog} branches --vary F --from -200 --to 300 --out f.csv --plot docs/branches_doughty_F.png
  {prog} branches --mechanism torsion_pendulum --vary k_t --from 0 --to 50 --out k.json
  {prog} branches --mechanism slider_crank --vary T --from -20 --to 20 --points 4001 --set b=0
  {prog} branches --mechanism double_pendulum --vary k_1 --from 5 --to 40 --set F_x=0.5

The parameter runs over --points evenly spaced values from --from to --to (both included);
the others are the example's, or --set's. The equilibria of neighbouring values are joined
into branches, and every fold (two equilibria meet and vanish), pitchfork, branch end and
change of stability is located by bisection on the parameter. --out writes a row per point
of every branch (.csv, .json or .parquet), --plot the figure (.png or .svg; pip install
'mechvib[plot]'). Angles in degrees, the parameter in its unit, the rest SI. With several
coordinates, each is shown by name, omega_n and zeta for every mode, and det K for K_EQ."""


def run(args) -> int:
    """Follow every equilibrium as one parameter varies; a summary on stdout, the table
    and the figure to files."""
    from ..presentation import figures, plot_branches
    from ..runtime.branches import branches, check_table_path
    from .report import branch_summary

    if args.plot:   # before the work: a bad path or no matplotlib fails at once
        figures.check_path(args.plot)
        figures.pyplot()
    if args.out:
        check_table_path(args.out)
    library = common.load_library(args)
    base = common.overrides(args.set, library.UNITS)
    if args.vary in base:
        raise ValueError(f"{args.vary}: given more than once (--vary, --set)")
    unit = library.UNITS.get(args.vary)
    start, stop = (common.number(f"--{which}", value, unit)
                   for which, value in (("from", args.start), ("to", args.stop)))
    with common.ProgressBar() as bar:
        result = branches(library, args.vary, start, stop, args.points, base=base,
                          method=args.method, workers=args.workers, progress=bar)
    print(branch_summary(result))
    if args.out:
        rows = result.write(args.out)
        print(f"Wrote {rows:,} rows to {args.out}.")
    if args.plot:
        plot_branches(result, args.plot)
        print(f"Drew the figure to {args.plot}.")
    return 0


def add(verbs, prog: str) -> None:
    brn = common.verb(verbs, "branches", "every equilibrium as one parameter varies: branches, "
                      "folds and stability, as a table and a figure", EXAMPLES, prog, run)
    common.mechanism_options(brn, None, model=True)
    brn.add_argument("--vary", required=True, metavar="NAME", help="the parameter to vary")
    brn.add_argument("--from", dest="start", required=True, metavar="VALUE",
                     help="its first value, in its unit (an angle in degrees, or 90deg, "
                          "1.5708rad)")
    brn.add_argument("--to", dest="stop", required=True, metavar="VALUE",
                     help="its last value, in its unit (above --from)")
    brn.add_argument("--points", type=common.positive, default=DEFAULT_POINTS, metavar="N",
                     help=f"values sampled, evenly spaced, ends included (default "
                          f"{DEFAULT_POINTS})")
    brn.add_argument("--set", action="append", type=common.assignment, default=[],
                     metavar="NAME=VALUE",
                     help="another parameter held at VALUE instead of the example's, in SI "
                          f"units (repeatable); {common.ANGLE_HELP}")
    brn.add_argument("--out", metavar="FILE",
                     help="write every point of every branch: FILE.csv, FILE.json or "
                          "FILE.parquet (angles in degrees)")
    brn.add_argument("--plot", metavar="FILE",
                     help="draw the figure: FILE.png or FILE.svg (pip install 'mechvib[plot]')")
    common.method_option(brn)
    brn.add_argument("--workers", type=common.positive, metavar="N",
                     help="threads for the samples (default: every CPU)")
