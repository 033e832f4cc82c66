"""`mechvib draw`: a drawing of a mechanism at one angle, from its model's points."""
from __future__ import annotations

from . import common

EXAMPLES = """\
examples:
  {prog} draw -o doughty.svg
  {prog} draw --mechanism four_bar --theta 60 -o four_bar.svg
  {prog} draw --model my_model.py --set k=100 -o mine.png

The bars, sliders, fixed points, springs and named points are where the model puts them at
the angle --theta (degrees; default: the first stable equilibrium of the parameters, else
0), computed by the mechanism's library. Needs matplotlib (pip install 'mechvib[plot]') and
sympy, which reads the model (pip install 'mechvib[generate]')."""


def geometry_of(args):
    """The Geometry the options describe (what the figure draws)."""
    import math

    from ..runtime.analysis import analyze
    from ..runtime.drawing import geometry

    common.generator()   # the model is sympy: its dependencies, or a one-line error
    from ..compiler.model import load

    library = common.load_library(args)
    mechanism = load(args.model or common.checked_mechanism(
        args.mechanism or common.DEFAULT_MECHANISM, common.shipped()))
    params = library.example_params(**common.overrides(args.set, library.UNITS))
    if args.theta is not None:
        theta = common.number("--theta", args.theta, "rad")
    else:
        stable = [r.theta for r in analyze(params).equilibria if r.stability == "stable"]
        theta = stable[0] if stable else 0.0
    if not math.isfinite(theta):
        raise ValueError(f"--theta {args.theta}: not a finite angle")
    return geometry(mechanism, library, params, theta)


def run(args) -> int:
    from ..presentation import draw_mechanism, figures

    figures.check_path(args.output)
    figures.pyplot()   # before the work: no matplotlib fails at once, in one line
    drawn = geometry_of(args)
    draw_mechanism(drawn, args.output)
    import math
    print(f"Drew {drawn.title} at theta = {math.degrees(drawn.theta):.4f} deg to {args.output}.")
    return 0


def add(verbs, prog: str) -> None:
    drw = common.verb(verbs, "draw", "a drawing of the mechanism at one angle (SVG or PNG)",
                      EXAMPLES, prog, run)
    common.mechanism_options(drw, None, model=True)
    common.set_option(drw)
    drw.add_argument("--theta", metavar="ANGLE",
                     help="the angle to draw it at, in degrees (or 1.2rad); default: the first "
                          "stable equilibrium")
    drw.add_argument("-o", "--output", required=True, metavar="FILE",
                     help="FILE.svg or FILE.png")
