"""Section 4 of `make bench`: the genuine equilibria of the library and of the numpy
pipeline against a 40-digit reference (mpmath.findroot on G, started at the library's root)."""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import mpmath
import numpy as np

from pipeline import NumpyRoots

DIGITS = 40
#: A numpy root within this of a reference equilibrium [rad] is the same equilibrium; the
#: closest distinct equilibria of the shipped examples are ~5e-4 rad apart.
SAME = 1e-4


def reference(G: Callable[..., Any], params: Sequence[Any], start: float) -> Any | None:
    """The zero of G next to ``start`` at DIGITS digits; None if findroot does not converge."""
    with mpmath.workdps(DIGITS):
        try:
            return mpmath.findroot(lambda t: G(t, *params), mpmath.mpf(start))
        except (ValueError, ZeroDivisionError):
            return None


def relative_error(theta: float, exact: Any) -> float:
    """|theta - exact| / |exact|, the difference taken modulo a turn."""
    with mpmath.workdps(DIGITS):
        d = mpmath.mpf(theta) - exact
        d -= 2 * mpmath.pi * mpmath.nint(d / (2 * mpmath.pi))
        return float(abs(d) / max(abs(exact), mpmath.mpf("1e-300")))


def compare(G: Callable[..., Any], table: np.ndarray, names: Sequence[str],
            library: np.ndarray, numpy_roots: NumpyRoots) -> dict[str, Any]:
    """Per set of ``table``: the library's equilibria (rows of analyze_table's
    ``equilibria``) and the numpy pipeline's genuine roots against the references."""
    result = {"sets": len(table), "library_equilibria": 0, "library_max_rel_error": 0.0,
              "reference_failures": 0, "numpy_equilibria": 0, "numpy_max_rel_error": 0.0,
              "numpy_missed": 0, "numpy_extra": 0}
    genuine = numpy_roots.genuine
    for s in range(len(table)):
        params = [mpmath.mpf(float(table[n][s])) for n in names]
        found = library["theta"][library["set"] == s]
        exact = [reference(G, params, t) for t in found]
        result["reference_failures"] += sum(e is None for e in exact)
        pairs = [(t, e) for t, e in zip(found, exact) if e is not None]
        result["library_equilibria"] += len(found)
        for t, e in pairs:
            result["library_max_rel_error"] = max(result["library_max_rel_error"],
                                                  relative_error(t, e))
        ours = numpy_roots.theta[(numpy_roots.set == s) & genuine]
        result["numpy_equilibria"] += len(ours)
        _match(ours, [e for _, e in pairs], result)
    return result


def _match(ours: np.ndarray, exact: list[Any], result: dict[str, Any]) -> None:
    """Pair each reference with the nearest numpy root within SAME; count the rest."""
    unused = list(ours)
    for e in exact:
        distances = [abs(_wrapped(t - float(e))) for t in unused]
        if not distances or min(distances) > SAME:
            result["numpy_missed"] += 1
            continue
        t = unused.pop(int(np.argmin(distances)))
        result["numpy_max_rel_error"] = max(result["numpy_max_rel_error"], relative_error(t, e))
    result["numpy_extra"] += len(unused)


def _wrapped(d: float) -> float:
    return d - 2 * math.pi * round(d / (2 * math.pi))
