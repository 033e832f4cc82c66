"""Table 1 steps 9-10: the perturbed, linearised equation (46)-(53) and the
natural frequency and damping ratio (54)-(55).

With theta = theta_E + theta_p in e0 thetaddot + e1 thetadot^2 + e2 thetadot + G = 0,
first order in theta_p gives M thetaddot_p + B thetadot_p + K theta_p = 0 with
M = e0(theta_E), B = e2(theta_E) (e1 thetadot^2 is second order) and K = G'(theta_E), the
slope of the static force, taken along the motion term by term in the roots' symbols.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import tidy
from .reduction import Reduction


@dataclass(frozen=True)
class Linearisation:
    mass: sp.Expr       # M_EQ, (50)
    damping: sp.Expr    # B_EQ, (51)
    stiffness: sp.Expr  # K_EQ, (52)-(53)

    @property
    def omega_n_squared(self) -> sp.Expr:
        """omega_n^2 = K/M, (54)."""
        return self.stiffness / self.mass

    @property
    def zeta_omega_n(self) -> sp.Expr:
        """zeta * omega_n = B / (2 M), (55); zeta follows once omega_n is known."""
        return self.damping / (2 * self.mass)


def derive_linearisation(reduction: Reduction) -> Linearisation:
    solution = reduction.solution
    slope = sum((tidy(solution.derivative(t)) for t in reduction.static_terms), sp.S.Zero)
    return Linearisation(mass=reduction.e[0], damping=reduction.e[2],
                         stiffness=solution.explicit(slope))
