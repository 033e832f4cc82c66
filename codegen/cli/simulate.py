"""`mechvib simulate`: the motion from an initial state."""
from __future__ import annotations

import math
import sys
import time

from . import common

EXAMPLES = """\
examples:
  {prog} simulate --theta0 160 --to 2                      CSV on stdout
  {prog} simulate --theta0 160 --to 2 --linearised --plot theta.png --out theta.json
  {prog} simulate --mechanism four_bar --theta0 -30 --thetadot0 100 --to 5 --out m.csv
  {prog} simulate --set b=0 --theta0 170 --to 10 --points 5001 --rtol 1e-11 --plot m.svg
  {prog} simulate --mechanism double_pendulum --theta0 -80 10 --to 3 --plot swing.png

Integrates the reduced equation of motion thetaddot = f(theta, thetadot) in C (adaptive
Dormand-Prince 5(4)) from theta0 [deg] and thetadot0 [deg/s] at t = 0 to --to [s], and
writes theta and thetadot at --points evenly spaced times: CSV on stdout, or --out FILE.csv
or FILE.json (degrees and seconds), and with --plot a figure of both. --linearised adds the
response of the linearisation about the stable equilibrium nearest theta0 (its M, B, K
from the analysis) from the same state. rtol and atol bound each step's error (atol in rad
and rad/s).

With several coordinates, --theta0 and --thetadot0 take one value each, in the model's order
(`mechvib list` names them; angles in deg and deg/s, lengths in m and m/s, rates 0 by
default), and the table has a column per coordinate and per rate."""


def _write_trajectory(args, trajectory):
    """CSV on stdout (no file to name), or the --out and --plot files: the files' names,
    and the linearised response drawn beside (None unless --linearised)."""
    from ..runtime import simulation

    linear = simulation.linearised(trajectory) if args.linearised else None
    return _write(args, simulation, trajectory, linear), linear


def _simulation_summary(trajectory, linear, seconds: float, written: list[str]) -> str:
    from .report import paragraph

    about = ""
    if linear is not None:
        e = linear.equilibrium
        about = (f" Linearised about theta_E = {math.degrees(linear.theta_e):.4f} deg "
                 f"({e.stability}, {e.damping}, zeta {e.zeta.real:.4g}).")
    return paragraph(
        f"Simulated {trajectory.t[-1]:g} s of {trajectory.library.TITLE} from theta0 = "
        f"{trajectory.theta_deg[0]:g} deg, thetadot0 = {trajectory.theta_d_deg[0]:g} deg/s: "
        f"{len(trajectory.t):,} points, {trajectory.steps:,} steps ({trajectory.rejected:,} "
        f"rejected), {trajectory.evaluations:,} evaluations of thetaddot, in "
        f"{seconds * 1e3:.1f} ms (rtol {trajectory.rtol:g}, atol {trajectory.atol:g}).{about} "
        f"Wrote {' and '.join(written)}.")


def run(args) -> int:
    """The motion from an initial state: CSV on stdout, or files and a summary."""
    import numpy as np

    from ..runtime import simulation

    common.check_outputs(args, simulation.FORMATS, "the trajectory")
    if not 0.0 < args.to < math.inf:
        raise ValueError(f"--to: the end time must be positive and finite, not {args.to!r}")
    if args.points < 2:
        raise ValueError("--points: at least 2 (the start and the end)")
    library = common.load_library(args)
    params = library.example_params(**common.overrides(args.set, library.UNITS))
    if library.dof > 1:
        return _several_coordinates(library, params, args)
    for option, values in (("--theta0", args.theta0), ("--thetadot0", args.thetadot0)):
        if values is not None and len(values) != 1:
            raise ValueError(f"{option}: {library.PREFIX} has one coordinate, so one value, "
                             f"not {len(values)}")
    args.theta0, args.thetadot0 = args.theta0[0], (args.thetadot0 or [0.0])[0]
    start = time.perf_counter()
    try:
        with common.ProgressBar(unit="points") as bar:
            trajectory = simulation.simulate(
                params, math.radians(args.theta0), math.radians(args.thetadot0),
                np.linspace(0.0, args.to, args.points), rtol=args.rtol, atol=args.atol,
                max_steps=args.max_steps, progress=bar)
    except simulation.IntegrationError as error:
        # what was computed before the failure is still written, and the failure said
        written, _ = _write_trajectory(args, error.trajectory)
        where = f"; the {len(error.trajectory.t):,} points before it" if written else ""
        raise ValueError(f"{error}{where}{' written to ' if written else ''}"
                         f"{' and '.join(written)}") from None
    seconds = time.perf_counter() - start
    written, linear = _write_trajectory(args, trajectory)
    if written:
        print(_simulation_summary(trajectory, linear, seconds, written))
    return 0


def _initial_state(library, args):
    """--theta0 and --thetadot0 in SI units (angles in rad), one per coordinate."""
    import numpy as np

    coordinates = library.SPEC["coordinates"]
    names = ", ".join(c["name"] for c in coordinates)
    state = []
    for option, values in (("--theta0", args.theta0), ("--thetadot0", args.thetadot0)):
        values = [0.0] * len(coordinates) if values is None else values
        if len(values) != len(coordinates):
            raise ValueError(f"{option}: one value per coordinate of {library.PREFIX} "
                             f"({names}), not {len(values)}")
        state.append(np.array([math.radians(v) if c["unit"] == "rad" else v
                               for v, c in zip(values, coordinates)]))
    return state


def _several_coordinates(library, params, args) -> int:
    """The motion of a mechanism with several coordinates, as `run`'s for one."""
    import numpy as np

    from ..runtime import multibody_motion as motion
    from ..runtime.simulation import IntegrationError

    theta0, theta_d0 = _initial_state(library, args)
    times = np.linspace(0.0, args.to, args.points)
    start = time.perf_counter()
    try:
        trajectory = motion.simulate(library, params, theta0, theta_d0, times, rtol=args.rtol,
                                     atol=args.atol, max_steps=args.max_steps)
    except IntegrationError as error:
        # what was computed before the failure is still written, and the failure said
        written = _write(args, motion, error.trajectory, None)
        where = f"; the {len(error.trajectory.t):,} points before it" if written else ""
        raise ValueError(f"{error}{where}{' written to ' if written else ''}"
                         f"{' and '.join(written)}") from None
    seconds = time.perf_counter() - start
    linear = motion.linearised(trajectory) if args.linearised else None
    written = _write(args, motion, trajectory, linear)
    if written:
        print(_several_summary(trajectory, linear, seconds, written))
    return 0


def _several_summary(trajectory, linear, seconds: float, written: list[str]) -> str:
    import numpy as np

    from .report import paragraph

    coordinates, rates = trajectory.labels()

    def listed(names, values):
        return ", ".join(f"{name} = {value:.6g}" for name, value in zip(names, values))

    state = listed(coordinates, trajectory.theta_shown[0])
    if np.any(trajectory.theta_d[0]):
        state += ", " + listed(rates, trajectory.theta_d_shown[0])
    about = ""
    if linear is not None:
        centre = np.where(linear.angular, np.degrees(linear.theta_e), linear.theta_e)
        about = (f" Linearised about the {linear.equilibrium.stability} equilibrium at "
                 f"{listed(coordinates, centre)}.")
    return paragraph(
        f"Simulated {trajectory.t[-1]:g} s of {trajectory.library.TITLE} from {state}: "
        f"{len(trajectory.t):,} points in {seconds * 1e3:.1f} ms (rtol {trajectory.rtol:g}, "
        f"atol {trajectory.atol:g}).{about} Wrote {' and '.join(written)}.")


def _write(args, motion, trajectory, linear) -> list[str]:
    """CSV on stdout (no file to name), or the --out and --plot files: their names."""
    if not (args.out or args.plot):
        motion.write_csv(sys.stdout, trajectory, linear)
        return []
    from ..presentation import plot_trajectory

    written = [str(motion.write(trajectory, args.out, linear))] if args.out else []
    return written + ([str(plot_trajectory(trajectory, args.plot, linear))] if args.plot else [])


def add(verbs, prog: str) -> None:
    sim = common.verb(verbs, "simulate", "the motion from an initial state: theta(t) and "
                      "thetadot(t) as CSV or JSON, and a figure", EXAMPLES, prog, run)
    common.mechanism_options(sim, None, model=True)
    common.set_option(sim)
    sim.add_argument("--theta0", type=float, nargs="+", required=True, metavar="DEG",
                     help="the initial angle [deg] (several coordinates: one value each, "
                          "lengths in m)")
    sim.add_argument("--thetadot0", type=float, nargs="+", metavar="DEG/S",
                     help="the initial rate [deg/s] (default 0; several coordinates: one "
                          "value each)")
    sim.add_argument("--to", type=float, required=True, metavar="T",
                     help="the end time [s] (the motion starts at t = 0)")
    sim.add_argument("--points", type=common.positive, default=1001, metavar="N",
                     help="output times, evenly spaced from 0 to T (default 1001)")
    sim.add_argument("--rtol", type=float, metavar="R",
                     help="relative tolerance per step (default 1e-9)")
    sim.add_argument("--atol", type=float, metavar="A",
                     help="absolute tolerance per step, in rad and rad/s (default 1e-12)")
    sim.add_argument("--max-steps", type=common.positive, metavar="N",
                     help="the integrator's step budget (default 1000000)")
    sim.add_argument("--linearised", action="store_true",
                     help="also the linearised response about the stable equilibrium nearest "
                          "theta0")
    sim.add_argument("--out", metavar="FILE",
                     help="write FILE.csv or FILE.json instead of CSV on stdout")
    sim.add_argument("--plot", metavar="FILE",
                     help="draw theta(t) and thetadot(t) to FILE.png or FILE.svg (needs "
                          "matplotlib: pip install 'mechvib[plot]')")
