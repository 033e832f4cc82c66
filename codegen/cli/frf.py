"""`mechvib frf`: the frequency response about a stable equilibrium."""
from __future__ import annotations

import math
import sys

from . import common

EXAMPLES = """\
examples:
  {prog} frf                                          CSV on stdout (doughty's example)
  {prog} frf --equilibrium 5 --plot frf.png --out frf.json
  {prog} frf --mechanism four_bar --max-frequency 20 --points 2001 --out frf.csv

The receptance H = 1 / (K - omega^2 M + i omega B) of the linearisation about a stable
equilibrium (the first, or --equilibrium I of `analyze`'s list), computed in C at --points
forcing frequencies from 0 to --max-frequency [Hz] (default: three times the natural
frequency): the swing [rad] per unit amplitude of a harmonic torque [N m] on theta, and its
phase lag. CSV on stdout (frequency_hz, omega, amplitude, phase_deg, H_re, H_im), or --out
FILE.csv or FILE.json, and with --plot a figure of amplitude and phase with the natural
frequency marked."""


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


def run(args) -> int:
    """The receptance table: CSV on stdout, or files and a summary."""
    import numpy as np

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
    result = response.frequency_response(params, omega, equilibrium=args.equilibrium,
                                         method=args.method, points=args.points)
    if not (args.out or args.plot):
        response.write_csv(sys.stdout, result)
        return 0
    written = [str(response.write(result, args.out))] if args.out else []
    written += [str(response.plot(result, args.plot))] if args.plot else []
    print(_summary(result, written))
    return 0


def add(verbs, prog: str) -> None:
    frf = common.verb(verbs, "frf", "the frequency response about a stable equilibrium: "
                      "amplitude and phase against the forcing frequency, as CSV or JSON, "
                      "and a figure", EXAMPLES, prog, run)
    common.mechanism_options(frf, None, model=True)
    common.set_option(frf)
    frf.add_argument("--equilibrium", type=int, metavar="I",
                     help="which equilibrium (its index in `analyze`'s list, from 0; default "
                          "the first stable one)")
    frf.add_argument("--max-frequency", type=float, metavar="HZ",
                     help="the highest forcing frequency [Hz] (default: three times the "
                          "natural frequency)")
    frf.add_argument("--points", type=common.positive, default=801, metavar="N",
                     help="forcing frequencies, evenly spaced from 0 (default 801)")
    common.method_option(frf)
    frf.add_argument("--out", metavar="FILE",
                     help="write FILE.csv or FILE.json instead of CSV on stdout")
    frf.add_argument("--plot", metavar="FILE",
                     help="draw amplitude and phase to FILE.png or FILE.svg (needs "
                          "matplotlib: pip install 'mechvib[plot]')")
