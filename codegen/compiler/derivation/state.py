"""Plain symbols for the state, so derived expressions can be evaluated and printed.

The derivation works with coordinates as functions of time (so d/dt is exact); every
result handed on is 'frozen': q_i(t), its first and second derivatives become the
symbols ``name``, ``name_d`` and ``name_dd``.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model import TIME, Mechanism


@dataclass(frozen=True)
class StateSymbols:
    coords: tuple[sp.Symbol, ...]
    rates: tuple[sp.Symbol, ...]
    accels: tuple[sp.Symbol, ...]
    multipliers: tuple[sp.Symbol, ...]

    @classmethod
    def of(cls, mechanism: Mechanism) -> "StateSymbols":
        names = [c.name for c in mechanism.coordinates]
        return cls(
            coords=tuple(sp.Symbol(n, real=True) for n in names),
            rates=tuple(sp.Symbol(f"{n}_d", real=True) for n in names),
            accels=tuple(sp.Symbol(f"{n}_dd", real=True) for n in names),
            multipliers=tuple(sp.Symbol(f"lambda_{i + 1}", real=True)
                              for i in range(len(mechanism.constraints))),
        )

    def freezer(self, mechanism: Mechanism) -> dict:
        """Substitutions from q(t), q'(t), q''(t) to symbols, highest derivative first."""
        functions = list(mechanism.q)
        return {
            **{f.diff(TIME, 2): s for f, s in zip(functions, self.accels)},
            **{f.diff(TIME): s for f, s in zip(functions, self.rates)},
            **mechanism.freezer(),  # the coordinates themselves: the same symbols
        }

