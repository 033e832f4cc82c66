"""The quantities of one angle (Table 1 steps 7-10: the dependent state, the reduced
equation's coefficients, G, the radicands and the linearisation) on one assembly mode.

The closed form of the positions carries a square root per dyad; each sign choice of the
assembly roots (mode j flips assembly root i where bit i of j is set) is a mechanism
assembled another way. Which sign choice is the mode the model declares (its conditions
hold) can differ between parameter sets and angles, so the library carries these
quantities on every sign choice and picks one at run time; mode 0 is the derivation's own
expressions, unchanged.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .equilibrium import Equilibrium, radicands_on
from .linearisation import Linearisation
from .positions import write_out
from .reduction import Reduction


@dataclass(frozen=True)
class ModeQuantities:
    """Every function of one angle on one sign choice of the assembly roots."""

    signs: tuple[int, ...]
    positions: tuple[sp.Expr, ...]       # q(theta), (30)-(34)
    velocities: tuple[sp.Expr, ...]      # S(theta) thetadot, (32), (35)
    e: tuple[sp.Expr, ...]               # e0, e1, e2, (37)-(41)
    residual: sp.Expr                    # G, (42)-(43)
    scale: sp.Expr                       # the sum of G's contributions' magnitudes
    radicands: tuple[sp.Expr, ...]
    radicand_scales: tuple[sp.Expr, ...]
    mass: sp.Expr                        # M_EQ, (50)
    damping: sp.Expr                     # B_EQ, (51)
    stiffness: sp.Expr                   # K_EQ, (52)-(53)
    theta_d: sp.Symbol                   # the rate thetadot the velocities are in

    @property
    def angular_acceleration(self) -> sp.Expr:
        """thetaddot solved from (36), which is affine in it."""
        e0, e1, e2 = self.e
        return -(e1 * self.theta_d**2 + e2 * self.theta_d + self.residual) / e0

    @property
    def omega_n_squared(self) -> sp.Expr:
        """omega_n^2 = K/M, (54)."""
        return self.stiffness / self.mass

    @property
    def zeta_omega_n(self) -> sp.Expr:
        """zeta * omega_n = B / (2 M), (55); zeta follows once omega_n is known."""
        return self.damping / (2 * self.mass)


def on_mode(k: int, reduction: Reduction, equilibrium: Equilibrium,
            linearisation: Linearisation) -> ModeQuantities:
    """The quantities on sign choice k (linearisation.modes[k]); k = 0 gives the
    derivation's declared expressions as they are."""
    mode = linearisation.modes[k]
    branch = equilibrium.branch(mode.signs)
    theta_d = reduction.theta_d
    if k == 0:
        return ModeQuantities(mode.signs, tuple(reduction.positions),
                              tuple(reduction.velocities), tuple(reduction.e),
                              equilibrium.residual, branch.scale, equilibrium.radicands,
                              equilibrium.radicand_scales, mode.mass, mode.damping,
                              mode.stiffness, theta_d)
    solution = reduction.solution
    roots, definitions = solution.roots, solution.definitions

    def on(expr):
        return write_out(expr, roots, definitions, mode.signs)

    positions = solution.positions.applyfunc(on)
    # as derive_reduction takes S: by differentiation, or through a chain's program
    slopes = (positions.diff(reduction.theta) if not definitions else
              solution.positions.applyfunc(lambda q: on(solution.derivative(q))))
    radicands, radicand_scales = radicands_on(roots, mode.signs, definitions)
    return ModeQuantities(mode.signs, tuple(positions), tuple(slopes * theta_d),
                          tuple(on(e) for e in reduction.e_in_roots), branch.residual,
                          branch.scale, radicands, radicand_scales, mode.mass, mode.damping,
                          mode.stiffness, theta_d)
