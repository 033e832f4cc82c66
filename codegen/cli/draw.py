"""`mechvib draw`: a drawing of a mechanism at one state, from its model's points."""
from __future__ import annotations

from . import common

EXAMPLES = """\
examples:
  {prog} draw -o doughty.svg
  {prog} draw --mechanism four_bar --theta 60 -o four_bar.svg
  {prog} draw --model my_model.py --set k=100 -o mine.png
  {prog} draw --mechanism double_pendulum --equilibrium 3 -o dp.png
  {prog} draw --mechanism double_pendulum --at theta_1=30 --at delta=-10 -o dp.svg

The bars, sliders, fixed points, springs and named points are where the model puts them at
the state drawn, computed by the mechanism's library: at the angle --theta (degrees; one
coordinate), at the values --at NAME=VALUE gives each independent coordinate (the columns of
`mechvib analyze` name them; angles in degrees or with a unit, 90deg, 1.5708rad, lengths in
m), or at the equilibrium --equilibrium N, numbered as `mechvib analyze` lists them. By
default: the first stable equilibrium of the parameters, else the first equilibrium, else
the centre of the coordinates' ranges; the line printed says which. Needs matplotlib (pip
install 'mechvib[plot]') and sympy, which reads the model (pip install 'mechvib[generate]')."""


def _given(args, coordinates, library) -> tuple[float, ...]:
    """--theta or the --at values, in SI units (angles in rad), one per independent
    coordinate in the model's order."""
    names = [name for name, _ in coordinates]
    if args.theta is not None:
        if len(coordinates) > 1:
            raise ValueError(f"--theta: {library.PREFIX} has {len(coordinates)} independent "
                             f"coordinates ({', '.join(names)}): give each with --at NAME=VALUE "
                             f"(e.g. --at {names[0]}=30)")
        return (common.number("--theta", args.theta, "rad"),)
    given: dict[str, float] = {}
    for name, text in args.at:
        if name not in names:
            raise ValueError(f"--at {name}: {library.PREFIX} has no independent coordinate "
                             f"{name!r}; it has {', '.join(names)}")
        if name in given:
            raise ValueError(f"--at {name} is given twice")
        given[name] = common.number(f"--at {name}", text, dict(coordinates)[name])
    missing = [name for name in names if name not in given]
    if missing:
        raise ValueError(f"--at: give every independent coordinate of {library.PREFIX} "
                         f"({', '.join(names)}); missing {', '.join(missing)}")
    return tuple(given[name] for name in names)


def _equilibria(library, params) -> list[tuple[tuple[float, ...], str]]:
    """Each equilibrium's independent coordinates and stability, numbered (from 0 here) as
    `mechvib analyze` numbers them from 1."""
    if library.dof > 1:
        return [(tuple(float(v) for v in e.theta), e.stability)
                for e in library.analyze(params).equilibria]
    from ..runtime.analysis import analyze

    return [((float(e.theta),), e.stability) for e in analyze(params).equilibria]


def _state(args, mechanism, library, params) -> tuple[tuple[float, ...], str]:
    """The independent coordinates to draw at, and what they are (for the line printed:
    empty where the options gave them)."""
    from ..runtime.drawing import independent_coordinates, range_centre

    coordinates = independent_coordinates(mechanism)
    if args.theta is not None or args.at:
        return _given(args, coordinates, library), ""
    found = _equilibria(library, params)
    if args.equilibrium is not None:
        theta, stability = found[common.equilibrium_index(args.equilibrium, len(found),
                                                          library.PREFIX)]
        return theta, f" (equilibrium {args.equilibrium}, {stability})"
    for number, (theta, stability) in enumerate(found, 1):
        if stability == "stable":
            return theta, f" (equilibrium {number}, stable)"
    if found:
        return found[0][0], f" (equilibrium 1, {found[0][1]}: none is stable)"
    return range_centre(mechanism, params), (" (no equilibrium at these parameters: the centre of "
                                                 "the coordinates' ranges)")


def geometry_of(args):
    """The Geometry the options describe (what the figure draws), and what the state drawn
    is (an equilibrium's number; empty where the options gave the coordinates)."""
    from ..runtime.drawing import geometry

    common.generator()   # the model is sympy: its dependencies, or a one-line error
    from ..compiler.model import load

    library = common.load_library(args)
    mechanism = load(args.model or common.checked_mechanism(
        args.mechanism or common.DEFAULT_MECHANISM, common.shipped()))
    params = library.example_params(**common.overrides(args.set, library.UNITS))
    theta, which = _state(args, mechanism, library, params)
    return geometry(mechanism, library, params, theta if library.dof > 1 else theta[0]), which


def run(args) -> int:
    from ..presentation import draw_mechanism, figures

    figures.check_path(args.output)
    figures.pyplot()   # before the work: no matplotlib fails at once, in one line
    drawn, which = geometry_of(args)
    draw_mechanism(drawn, args.output)
    print(f"Drew {drawn.title} at {drawn.at()}{which} to {args.output}.")
    return 0


def add(verbs, prog: str) -> None:
    drw = common.verb(verbs, "draw", "a drawing of the mechanism at one state (SVG or PNG)",
                      EXAMPLES, prog, run)
    common.mechanism_options(drw, None, model=True)
    common.set_option(drw)
    where = drw.add_mutually_exclusive_group()
    where.add_argument("--theta", metavar="ANGLE",
                       help="one coordinate: the angle to draw it at, in degrees (or 1.2rad)")
    where.add_argument("--at", action="append", type=common.assignment, default=[],
                       metavar="NAME=VALUE",
                       help="the value of an independent coordinate (repeatable, once for "
                            "each): an angle in degrees (or 30deg, 0.5rad), a length in m")
    where.add_argument("--equilibrium", type=int, metavar="N",
                       help="draw the N-th equilibrium of the parameters, "
                            f"{common.EQUILIBRIUM_NUMBERING}; "
                            "default: the first stable one, else the first, else the centre "
                            "of the coordinates' ranges")
    drw.add_argument("-o", "--output", required=True, metavar="FILE",
                     help="FILE.svg or FILE.png")
