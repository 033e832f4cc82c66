"""The units the analysis divides out: each parameter's powers of (m, kg, s), and those of G
and of sigma's coefficients, which the runtime multiplies back into its results.

The runtime (codegen_analysis.c) picks a power of two for each of a characteristic length,
mass and time from the parameters' values, divides every parameter by its unit's powers of
them, analyses, and scales K, M, B, the residuals, the frequencies and sigma back. Powers of
two scale exactly, so at ordinary scales nothing changes, while a mechanism given in
nanometres or in megatonnes is analysed as the same numbers. That is sound only where the
model is homogeneous in its units, which is checked here at 40 digits: G and sigma are
evaluated at a drawn point and at the point with every parameter multiplied by its unit's
powers of L = 2, M = 2^64, T = 2^4096; each ratio must be one power of two, at two points,
whose exponent names the quantity's own dimension. A model whose units are not all known,
whose coordinate is not an angle, or that is not homogeneous is analysed in its units as
given (scaling None).
"""
from __future__ import annotations

import random
from dataclasses import dataclass

import mpmath
import sympy as sp

from ..model.units import Dimension, dimension

#: The exponents of 2 that stand for L, M and T in the check: a ratio 2^n gives the powers
#: of the three as n's balanced base-64 digits (each within +-31).
_BASES = (0, 6, 12)


@dataclass(frozen=True)
class Scaling:
    parameters: tuple[Dimension, ...]   # each parameter's powers of (m, kg, s), in order
    force: Dimension                    # G's (and K's): energy per radian
    sigma: Dimension | None             # sigma's coefficients' (None: no polynomial)


def unit_scaling(derivation) -> Scaling | None:
    """The model's Scaling, or None where the analysis must keep the user's units."""
    m = derivation.mechanism
    coordinate = next(c for c in derivation.user.coordinates if c.name == derivation.user.independent)
    dims = tuple(dimension(p.unit) for p in derivation.user.parameters)
    if dimension(coordinate.unit) != (0, 0, 0) or None in dims:
        return None
    symbols = [p.symbol for p in m.parameters]
    theta = derivation.reduction.theta
    program = derivation.program
    residual = derivation.equilibrium.branches[0].residual
    force = _dimension_of(symbols + [theta], program, [residual], dims + ((0, 0, 0),))
    if force is None:
        return None
    polynomial = derivation.equilibrium.polynomial
    if polynomial is None:
        return Scaling(dims, force, None)
    sigma = _dimension_of(symbols, polynomial.definitions, polynomial.coefficients, dims)
    return Scaling(dims, force, sigma) if sigma is not None else None


def _dimension_of(symbols, definitions, exprs, dims) -> Dimension | None:
    """The one dimension every nonzero expr has, found by evaluating them at two drawn points
    and at their scaled copies; None where they are not homogeneous in those units."""
    f = sp.lambdify(symbols, list(exprs), modules="mpmath",
                    cse=lambda e: (list(definitions), e))
    draw = random.Random(48)
    found = set()
    with mpmath.workdps(60):
        for _ in range(2):
            point = [mpmath.mpf(draw.uniform(0.5, 2.0)) for _ in symbols]
            scaled = [x * mpmath.mpf(2) ** sum(power << base for power, base in zip(d, _BASES))
                      for x, d in zip(point, dims)]
            try:
                values, copies = f(*point), f(*scaled)
            except (ZeroDivisionError, ValueError, TypeError):
                return None
            for value, copy in zip(values, copies):
                if value == 0 and copy == 0:
                    continue
                n = _power_of_two(copy / value) if value != 0 else None
                if n is None:
                    return None
                found.add(n)
    if len(found) != 1:
        return None
    return _digits(found.pop())


def _power_of_two(ratio) -> int | None:
    """n where ratio is 2^n to 40 digits (real and positive), else None."""
    if isinstance(ratio, mpmath.mpc):
        if abs(ratio.imag) > mpmath.mpf(10) ** -40 * abs(ratio):
            return None
        ratio = ratio.real
    if not ratio > 0:
        return None
    n = int(mpmath.nint(mpmath.log(ratio, 2)))
    return n if abs(ratio / mpmath.mpf(2) ** n - 1) < mpmath.mpf(10) ** -40 else None


def _digits(n: int) -> Dimension | None:
    """n = a + 64 b + 4096 c with a, b, c within +-31, as (a, b, c)."""
    out = []
    for _ in range(3):
        digit = (n + 32) % 64 - 32
        out.append(digit)
        n = (n - digit) // 64
    return (out[0], out[1], out[2]) if n == 0 else None
