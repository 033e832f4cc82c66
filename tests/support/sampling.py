"""Parameter sets drawn around a library's example, shared by the tests of every mechanism."""
from __future__ import annotations

import math

#: Parameters whose example value is 0, drawn from +-spread instead of scaled.
ZERO_SPREAD = {"slider_crank": {"T": 5.0}, "four_bar": {"T": 5.0},
               "torsion_pendulum": {"F_x": 20.0}}


def near_example(lib, rng, sd: float) -> dict[str, float]:
    """The values of lib's example with every parameter scaled by exp(N(0, sd)); one whose
    example is 0 is drawn uniformly from +-its ZERO_SPREAD (or left 0), in the order of the
    C struct, one draw each."""
    example = lib.example_params()
    spreads = ZERO_SPREAD.get(lib.PREFIX, {})
    values = {}
    for n in lib.PARAMETER_NAMES:
        v, spread = getattr(example, n), spreads.get(n)
        values[n] = (float(rng.uniform(-spread, spread)) if v == 0 and spread
                     else v * math.exp(rng.normal(0.0, sd)))
    return values
