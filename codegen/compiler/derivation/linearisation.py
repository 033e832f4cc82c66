"""Table 1 step 9: the perturbed, linearised equation (46)-(53); step 10, the natural
frequency and damping ratio (54)-(55), is modes.ModeQuantities'.

With theta = theta_E + theta_p in e0 thetaddot + e1 thetadot^2 + e2 thetadot + G = 0,
first order in theta_p gives M thetaddot_p + B thetadot_p + K theta_p = 0 with
M = e0(theta_E), B = e2(theta_E) (e1 thetadot^2 is second order) and K = G'(theta_E), the
slope of the static force, taken along the motion term by term in the roots' symbols.
The same expressions with the assembly-mode roots' signs flipped are the linearisation of
the mechanism assembled the other way(s): each assembly mode has its own M, B, K.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .equilibrium import on_branch, terms_size
from .reduction import Reduction


@dataclass(frozen=True)
class Mode:
    """M, B, K of one assembly mode: ``signs`` of the roots (lengths always positive)."""

    signs: tuple[int, ...]
    mass: sp.Expr
    damping: sp.Expr
    stiffness: sp.Expr
    # the model's assembly-mode conditions as they stand on this mode (each positive where
    # its dyad is assembled as declared), and the sizes of their terms
    conditions: tuple[sp.Expr, ...] = ()
    condition_scales: tuple[sp.Expr, ...] = ()


@dataclass(frozen=True)
class Linearisation:
    #: every assembly mode, the declared one first; mode j flips assembly root i when bit i
    #: of j is set (counting assembly roots only)
    modes: tuple[Mode, ...]
    #: for each condition of a Mode, the bit of the mode number its dyad's sign sets
    condition_bits: tuple[int, ...] = ()
    #: for each condition of a Mode, its index in the model's assembly_modes
    condition_sources: tuple[int, ...] = ()

    @property
    def mass(self) -> sp.Expr:
        """M_EQ, (50), of the mechanism as declared."""
        return self.modes[0].mass

    @property
    def damping(self) -> sp.Expr:
        """B_EQ, (51)."""
        return self.modes[0].damping

    @property
    def stiffness(self) -> sp.Expr:
        """K_EQ, (52)-(53)."""
        return self.modes[0].stiffness



def derive_linearisation(reduction: Reduction) -> Linearisation:
    solution = reduction.solution
    slope = sum((solution.slope(t) for t in reduction.static_terms), sp.S.Zero)
    roots = solution.roots
    e0, _, e2 = reduction.e_in_roots
    assembly = [r for r in roots if r.kind == "assembly"]
    conditions = [c for r in assembly for c in r.conditions]

    def on(signs, x):
        return on_branch(x, roots, signs, solution.definitions)

    return Linearisation(
        tuple(Mode(signs, *(on(signs, x) for x in (e0, e2, slope)),
                   conditions=tuple(on(signs, c) for c in conditions),
                   condition_scales=tuple(terms_size(c, lambda t: on(signs, t))
                                          for c in conditions))
              for signs in mode_signs(tuple(r.kind for r in roots))),
        condition_bits=tuple(bit for bit, r in enumerate(assembly) for _ in r.conditions),
        condition_sources=tuple(k for r in assembly for k in r.condition_sources))


def mode_signs(kinds: tuple[str, ...]) -> list[tuple[int, ...]]:
    """Root signs of each assembly mode: mode j flips the i-th assembly root when bit i of
    j is set; lengths stay positive."""
    assembly = [i for i, k in enumerate(kinds) if k == "assembly"]
    return [tuple(-1 if i in assembly and j >> assembly.index(i) & 1 else 1
                  for i in range(len(kinds))) for j in range(2 ** len(assembly))]
