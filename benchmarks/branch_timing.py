"""`make bench` section 6: ``Library.branches`` over a parameter range holding folds.

Per shipped mechanism, one parameter over a range where its equilibria fold (or, for the
torsion pendulum, buckle in a pitchfork): the wall time of the whole call (sampling on
threads, joining, and the refinement of every event by bisection) with one thread and with
two, and of the sampling alone (``sweep.sweep`` of the same values), medians of repeats.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from codegen.runtime import sweep
from codegen.runtime.branches import EVENTS
from codegen.runtime.library import Library

#: (parameter, from, to) per mechanism: each range holds events.
CASES = {"doughty": ("F", -200.0, 300.0), "four_bar": ("T", -20.0, 20.0),
         "slider_crank": ("F", -200.0, 200.0), "torsion_pendulum": ("k_t", 0.0, 50.0)}

Timer = Callable[[Callable[[], object], int], float]


def measure(name: str, library: Library, points: int, repeats: int, timer: Timer
            ) -> dict[str, Any]:
    """The timings and what was found, for one mechanism."""
    parameter, start, stop = CASES[name]
    values = np.linspace(start, stop, points)
    table = sweep.grid(library, {parameter: values})

    def run(workers: int) -> Callable[[], object]:
        return lambda: library.branches(parameter, start, stop, points=points, workers=workers)

    result = library.branches(parameter, start, stop, points=points)
    seconds = {w: timer(run(w), repeats) for w in (1, 2)}
    sampling = timer(lambda: sweep.sweep(library, table, workers=2), repeats)
    kinds = [e.kind for e in result.events]
    return {"parameter": parameter, "from": start, "to": stop, "points": points,
            "unit": library.UNITS[parameter], "branches": result.count,
            "events": {k: kinds.count(k) for k in EVENTS if k in kinds},
            "bisection_width": result.tolerance, "w1_seconds": seconds[1],
            "w2_seconds": seconds[2], "sampling_w2_seconds": sampling}
