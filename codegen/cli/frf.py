"""`mechvib frf`: the frequency response about a stable equilibrium."""
from __future__ import annotations

import math
import sys

from . import common

#: --points' default: codegen.runtime.response.POINTS (written here so that building the
#: parser imports no runtime; tests/cli/test_lazy_imports.py holds the two equal).
POINTS = 801

EXAMPLES = """\
examples:
  {prog} frf                                          CSV on stdout (doughty's example)
  {prog} frf --equilibrium 6 --plot frf.png --out frf.json
  {prog} frf --mechanism four_bar --max-frequency 20 --points 2001 --out frf.csv
  {prog} frf --mechanism double_pendulum --drive delta --plot frf.png

The receptance H = 1 / (K - omega^2 M + i omega B) of the linearisation about a stable
equilibrium (the first, or --equilibrium N, numbered from 1 as `mechvib analyze` lists
them), computed in C at --points forcing frequencies from 0 to --max-frequency [Hz]
(default: three times the natural frequency): the swing [rad] per unit amplitude of a
harmonic torque [N m] on theta, and its phase lag. CSV on stdout (frequency_hz, omega,
amplitude, phase_deg, H_re, H_im), or --out FILE.csv or FILE.json, and with --plot a figure
of amplitude [deg/(N m)] and phase with the natural frequency marked. With several
coordinates a harmonic generalised force (a torque [N m] on an angle, a force [N] on a
length) drives one (--drive NAME, default the first) and every coordinate's amplitude and
phase are listed (in SI units), the natural frequencies marked; the figure draws the
amplitudes on a panel per unit (angles in deg, lengths in m)."""


def _summary(response, written: list[str]) -> str:
    from .report import paragraph

    e = response.equilibrium
    f_peak, peak = response.peak
    return paragraph(
        f"Frequency response of {response.library.TITLE} about theta_E = "
        f"{math.degrees(e.theta):.4f} deg ({e.stability}, {e.damping}): natural frequency "
        f"{response.natural_frequency:.6g} Hz, zeta {e.zeta.real:.4g}, static compliance "
        f"1/K = {1 / e.K:.4g} rad/(N m); largest amplitude {peak:.4g} rad/(N m) at "
        f"{f_peak:.6g} Hz of the {len(response.omega):,} frequencies from 0 to "
        f"{response.frequency[-1]:.6g} Hz. Wrote {' and '.join(written)}.")


def _chosen(args, found, stable, prefix: str) -> int | None:
    """--equilibrium N as the index of a stable equilibrium in ``found`` (the analysis'
    list); None without it. A ValueError (one line) for a number out of range or an
    equilibrium that is not stable, naming the stable ones."""
    if args.equilibrium is None:
        return None
    index = common.equilibrium_index(args.equilibrium, len(found), prefix)
    if not stable(found[index]):
        numbers = [str(i) for i, e in enumerate(found, 1) if stable(e)]
        which = (f"the stable one{'s are' if len(numbers) > 1 else ' is'} "
                 f"{', '.join(numbers)}" if numbers else "none is stable")
        raise ValueError(f"--equilibrium {args.equilibrium} is {found[index].stability}: it has "
                         f"no steady response to a harmonic force ({which})")
    return index


def run(args) -> int:
    """The receptance table: CSV on stdout, or files and a summary."""
    import numpy as np

    from ..presentation import plot_response
    from ..runtime import response

    common.check_outputs(args, response.FORMATS, "the response")
    if args.max_frequency is not None and not 0.0 < args.max_frequency < math.inf:
        raise ValueError("--max-frequency: a positive, finite frequency [Hz], not "
                         f"{args.max_frequency!r}")
    if args.points < 2:
        raise ValueError("--points: at least 2 (0 Hz and the highest frequency)")
    library = common.load_library(args)
    params = library.example_params(**common.overrides(args.set, library.UNITS))
    omega = (None if args.max_frequency is None
             else np.linspace(0.0, 2 * math.pi * args.max_frequency, args.points))
    if library.dof > 1:
        return _several_coordinates(library, params, omega, args)
    if args.drive is not None:
        raise ValueError("--drive: only a mechanism with several coordinates has a choice")
    from ..runtime.analysis import analyze
    from ..runtime.simulation import is_stable

    chosen = _chosen(args, analyze(params, args.method).equilibria, is_stable, library.PREFIX)
    result = response.frequency_response(params, omega, equilibrium=chosen,
                                         method=args.method, points=args.points)
    if not (args.out or args.plot):
        response.write_csv(sys.stdout, result)
        return 0
    written = [str(response.write(result, args.out))] if args.out else []
    written += [str(plot_response(result, args.plot))] if args.plot else []
    print(_summary(result, written))
    return 0


def _several_coordinates(library, params, omega, args) -> int:
    from ..presentation import plot_response
    from ..runtime import multibody_response as response
    from .report import paragraph

    names = [c["name"] for c in library.SPEC["coordinates"]]
    if args.drive and args.drive not in names:
        raise ValueError(f"--drive {args.drive}: not a coordinate of {library.PREFIX} "
                         f"({', '.join(names)})")
    drive = names.index(args.drive) if args.drive else 0
    chosen = _chosen(args, library.analyze(params).equilibria, lambda e: e.stable,
                     library.PREFIX)
    result = response.frequency_response(library, params, omega, chosen, drive, args.points)
    if not (args.out or args.plot):
        response.write_csv(sys.stdout, result)
        return 0
    written = [str(response.write(result, args.out))] if args.out else []
    written += [str(plot_response(result, args.plot))] if args.plot else []
    at = ", ".join(f"{n} = {x:.6g}" for n, x in zip(names, result.equilibrium.theta))
    natural = ", ".join(f"{f:.6g}" for f in result.natural_frequencies)
    print(paragraph(f"Frequency response of {library.TITLE} about {at}, driven on "
                    f"{names[drive]}: natural frequencies {natural} Hz, "
                    f"{len(result.omega):,} forcing frequencies. Wrote {' and '.join(written)}."))
    return 0


def add(verbs, prog: str) -> None:
    frf = common.verb(verbs, "frf", "the frequency response about a stable equilibrium: "
                      "amplitude and phase against the forcing frequency, as CSV or JSON, "
                      "and a figure", EXAMPLES, prog, run)
    common.mechanism_options(frf, None, model=True)
    common.set_option(frf)
    frf.add_argument("--equilibrium", type=int, metavar="N",
                     help="about the N-th equilibrium, "
                          f"{common.EQUILIBRIUM_NUMBERING}; it must be stable (default: "
                          "the first stable one)")
    frf.add_argument("--max-frequency", type=float, metavar="HZ",
                     help="the highest forcing frequency [Hz] (default: three times the "
                          "natural frequency)")
    frf.add_argument("--points", type=common.positive, default=POINTS, metavar="N",
                     help=f"forcing frequencies, evenly spaced from 0 (default {POINTS})")
    frf.add_argument("--drive", metavar="NAME",
                     help="with several coordinates: the one a harmonic force drives (default "
                          "the first)")
    common.method_option(frf)
    frf.add_argument("--out", metavar="FILE",
                     help="write FILE.csv or FILE.json instead of CSV on stdout")
    frf.add_argument("--plot", metavar="FILE",
                     help="draw amplitude and phase to FILE.png or FILE.svg (needs "
                          "matplotlib: pip install 'mechvib[plot]')")
