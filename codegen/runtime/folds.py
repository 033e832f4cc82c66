"""A fold polished to working precision: where G and K_EQ = G' vanish together.

Bisection on the number of equilibria finds a fold only as closely as the analysis tells a
close pair from a double root (the polynomial route merges roots ~2e-5 rad apart; on a flat
fold that is ~1e-6 of the parameter). At a fold G(theta, p) has a double root, so G' has a
simple zero theta*(p) between the pair (where G is extremal), and g(p) = G(theta*(p), p)
changes sign there, linearly in p. Both are found by bracketed root finding on the
declared mode's compiled G and K (``equilibrium_residual``, ``linearisation``), so the fold
is located to the given tolerance in the parameter, and its angle to working precision.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from .library import Library

#: Relative width [rad per rad] to which the extremum of G is located.
ANGLE_TOLERANCE = 4 * 2.0**-52


@dataclass(frozen=True)
class Fold:
    """A polished fold: the parameter's ``value`` [its unit] within ``bracket``, the angle
    ``theta`` [rad] of the double root, and K_EQ there [N m]."""

    value: float
    bracket: tuple[float, float]
    theta: float
    K: float


def zero(f: Callable[[float], float], a: float, b: float, fa: float, fb: float,
         tolerance: float, limit: int = 200) -> tuple[float, float]:
    """A bracket (lo, hi) no wider than ``tolerance`` (or as narrow as doubles allow)
    holding a sign change of f, from a and b where f has opposite signs: the Illinois
    method (regula falsi, halving the value kept twice)."""
    kept = 0
    for _ in range(limit):
        if abs(b - a) <= tolerance:
            break
        x = (a * fb - b * fa) / (fb - fa)
        if not min(a, b) < x < max(a, b):
            x = (a + b) / 2
            if not min(a, b) < x < max(a, b):
                break   # adjacent doubles
        fx = f(x)
        if fx == 0:
            return x, x
        if (fx > 0) == (fb > 0):
            b, fb = x, fx
            fa, kept = (fa / 2 if kept == -1 else fa), -1
        else:
            a, fa = x, fx
            fb, kept = (fb / 2 if kept == 1 else fb), 1
    return min(a, b), max(a, b)


def polish(library: Library, values: Mapping[str, float], parameter: str, start: float,
           pair: tuple[float, float], direction: int, first_step: float, reach: float,
           tolerance: float) -> Fold | None:
    """The fold of the pair of equilibria at angles ``pair`` [rad] (the declared mode's,
    for ``values`` with ``parameter`` = ``start``), which meet at most ``reach`` from
    ``start`` in ``direction`` (+1: increasing), the first step tried ``first_step``;
    located to ``tolerance`` [the parameter's unit]. None where G' is not bracketed around
    the pair, no sign change of G at its extremum is found, or an evaluation fails."""
    lo, hi = sorted(pair)
    window = (lo - (hi - lo), hi + (hi - lo))   # the extremum moves far less than the pair

    def params(p: float) -> object:
        return library.Params(**{**values, parameter: p})

    def extremum(p: float) -> tuple[float, float]:
        """(theta*, K there) at parameter p: where G' = K vanishes in the window."""
        at = params(p)

        def stiffness(theta: float) -> float:
            return float(library.linearisation(at, theta).K)

        ka, kb = stiffness(window[0]), stiffness(window[1])
        if not ka * kb < 0:
            raise ArithmeticError("K keeps its sign around the pair")
        a, b = zero(stiffness, window[0], window[1], ka, kb,
                    ANGLE_TOLERANCE * max(1.0, abs(window[0])))
        theta = (a + b) / 2
        return theta, stiffness(theta)

    def g(p: float) -> float:
        return float(library.equilibrium_residual(params(p), extremum(p)[0]).residual)

    try:
        near, g_near = start, g(start)
        step = first_step
        while step <= reach:
            far = start + direction * step
            g_far = g(far)
            if g_far * g_near < 0:
                a, b = zero(g, near, far, g_near, g_far, tolerance)
                value = (a + b) / 2
                theta, K = extremum(value)
                return Fold(value, (a, b), theta, K)
            near, g_near, step = far, g_far, 2 * step
    except (ArithmeticError, ValueError):   # ValueError: a LibraryError from the C
        return None
    return None

