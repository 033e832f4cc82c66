"""A fold polished to working precision: where G and K_EQ = G' vanish together.

Bisection on the number of equilibria finds a fold only as closely as the analysis tells a
close pair from a double root (the polynomial route merges roots ~2e-5 rad apart; on a flat
fold that is ~1e-6 of the parameter). At a fold G(theta, p) has a double root, so G' has a
simple zero theta*(p) between the pair (where G is extremal), and g(p) = G(theta*(p), p)
changes sign there, linearly in p. Both are found by bracketed root finding on the
declared mode's compiled G and K (``equilibrium_residual``, ``linearisation``), so the fold
is located to the given tolerance in the parameter, and its angle to working precision.

With n coordinates (``polish_multibody``) a fold is where G(q, p) = 0 and det K(q, p) = 0
together, K = dG/dq: n + 1 equations in the n coordinates and the parameter, solved by
Newton's method from the pair's midpoint where bisection left it.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .library import Library

#: Relative width [rad per rad] to which the extremum of G is located.
ANGLE_TOLERANCE = 4 * 2.0**-52


@dataclass(frozen=True)
class Fold:
    """A polished fold: the parameter's ``value`` [its unit] within ``bracket``, the angle
    ``theta`` [rad] of the double root, and K_EQ there [N m]; for n coordinates ``theta``
    holds each coordinate and ``K`` is det K."""

    value: float
    bracket: tuple[float, float]
    theta: float | tuple[float, ...]
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



#: The central differences' step, relative to the scale of the coordinates and the parameter.
STEP = 1e-6
#: Newton's iterations before it is given up.
ITERATIONS = 40
#: A Newton step this small (relative to the scales) leaves an error far below rounding
#: after it (quadratic convergence; the differences' error is ~1e-10 relative).
SETTLED = 1e-9


def polish_multibody(library: Library, values: Mapping[str, float], parameter: str,
                     start: float, pair: tuple[Any, Any], direction: int, first_step: float,
                     reach: float, tolerance: float) -> Fold | None:
    """The fold of a mechanism with n coordinates where the pair of equilibria at positions
    ``pair`` (n coordinates each, for ``values`` with ``parameter`` = ``start``) meets: the
    (q, p) where G(q, p) = 0 and det K(q, p) = 0, by Newton's method from the pair's
    midpoint at ``start``. G and K = dG/dq are the library's compiled ones
    (``generalised_force``, ``stiffness_matrix``); dG/dp and the derivatives of det K by
    central differences. The arguments are ``polish``'s. None where Newton's method does not
    converge, or converges beyond ``reach`` of ``start`` in ``direction`` or away from the
    pair, or an evaluation fails."""
    a, b = (np.asarray(x, dtype=np.float64) for x in pair)
    n = len(a)
    gap = float(np.linalg.norm(b - a))
    q, p = (a + b) / 2, float(start)
    scale = max(abs(p), abs(first_step), abs(reach))
    h_p, h_q = STEP * scale, STEP * max(1.0, float(np.max(np.abs(q))))

    def params(p: float) -> object:
        return library.Params(**{**values, parameter: p})

    def force(q: np.ndarray, p: float) -> np.ndarray:
        return np.asarray(library.generalised_force(params(p), q), dtype=np.float64).reshape(n)

    def determinant(q: np.ndarray, p: float) -> float:
        K = np.asarray(library.stiffness_matrix(params(p), q), dtype=np.float64)
        return float(np.linalg.det(K.reshape(n, n)))

    try:
        K = np.asarray(library.stiffness_matrix(params(p), q), dtype=np.float64).reshape(n, n)
        size = float(np.prod(np.linalg.norm(K, axis=1)))   # |det K| <= this (Hadamard)
        if not size > 0:
            return None
        step, settled = np.full(n + 1, np.inf), False
        for _ in range(ITERATIONS):
            K = np.asarray(library.stiffness_matrix(params(p), q),
                           dtype=np.float64).reshape(n, n)
            residual = np.append(force(q, p), np.linalg.det(K) / size)
            jacobian = np.empty((n + 1, n + 1))
            jacobian[:n, :n] = K
            jacobian[:n, n] = (force(q, p + h_p) - force(q, p - h_p)) / (2 * h_p)
            for j in range(n):
                e = np.zeros(n)
                e[j] = h_q
                jacobian[n, j] = (determinant(q + e, p) - determinant(q - e, p)) / (2 * h_q)
            jacobian[n, n] = (determinant(q, p + h_p) - determinant(q, p - h_p)) / (2 * h_p)
            jacobian[n] /= size
            step = np.linalg.solve(jacobian, -residual)
            q, p = q + step[:n], p + float(step[n])
            if not np.all(np.isfinite(step)):
                return None
            if settled:   # one step more once the steps are small: to working precision
                break
            settled = bool(abs(step[n]) <= SETTLED * scale and
                           np.max(np.abs(step[:n])) <= SETTLED * max(1.0, np.max(np.abs(q))))
        else:
            return None
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        return None
    beyond = (p - start) * direction
    near = float(np.linalg.norm(q - (a + b) / 2)) <= 2 * gap + STEP * max(1.0, np.max(np.abs(q)))
    if not (-tolerance <= beyond <= reach + tolerance and near):
        return None
    half = max(tolerance / 2, abs(float(step[n])))
    return Fold(p, (p - half, p + half), tuple(float(x) for x in q), determinant(q, p))
