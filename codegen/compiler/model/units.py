"""A parameter's unit as the powers of metre, kilogram and second it stands for.

The analysis works on dimensionless quantities: it divides each parameter by the powers of a
characteristic length, mass and time its unit names (runtime: codegen_analysis.c), so that a
mechanism and its copy in other units get the same equilibria and proofs. Units are read as
a model file writes them: symbols separated by spaces or '*', one '/' before the
denominator, powers as '^2' or '**2' ("N m s/rad", "m/s^2", "kg m^2", "1").
"""
from __future__ import annotations

import re

Dimension = tuple[int, int, int]   # powers of (m, kg, s)

#: The symbols a unit may use, each as powers of (m, kg, s). An angle is dimensionless.
SYMBOLS: dict[str, Dimension] = {
    "1": (0, 0, 0), "rad": (0, 0, 0), "m": (1, 0, 0), "kg": (0, 1, 0), "s": (0, 0, 1),
    "N": (1, 1, -2), "J": (2, 1, -2), "W": (2, 1, -3), "Pa": (-1, 1, -2), "Hz": (0, 0, -1),
}
_FACTOR = re.compile(r"^([A-Za-z]+|1)(?:\^(-?\d+))?$")


def dimension(unit: str) -> Dimension | None:
    """(m, kg, s) powers of unit, or None where it names a symbol outside SYMBOLS (a unit
    the analysis cannot scale: it then works in the user's units as given)."""
    numerator, _, denominator = unit.strip().partition("/")
    total = [0, 0, 0]
    for part, sign in ((numerator, 1), (denominator, -1)):
        for factor in part.replace("**", "^").replace("*", " ").split():
            match = _FACTOR.match(factor)
            if match is None or match.group(1) not in SYMBOLS:
                return None
            power = sign * int(match.group(2) or 1)
            for i, base in enumerate(SYMBOLS[match.group(1)]):
                total[i] += power * base
    return (total[0], total[1], total[2])
