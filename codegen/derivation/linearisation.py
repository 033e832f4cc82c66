"""Table 1 steps 9-10: the perturbed, linearised equation (46)-(53) and the
natural frequency and damping ratio (54)-(55).

With theta = theta_E + theta_p and the reduced equation f(theta, thetadot, thetaddot) = 0,
first order in theta_p gives M thetaddot_p + B thetadot_p + K theta_p = 0 with the
partial derivatives of f at rest: M = df/dthetaddot, B = df/dthetadot, K = df/dtheta.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

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
    f = reduction.structured_equation
    at_rest = {reduction.theta_d: 0, reduction.theta_dd: 0}
    return Linearisation(
        mass=f.diff(reduction.theta_dd).subs(at_rest),
        damping=f.diff(reduction.theta_d).subs(at_rest),
        stiffness=f.diff(reduction.theta).subs(at_rest),
    )
