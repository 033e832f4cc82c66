"""Table 1 step 8: static equilibrium (42)-(43) and its polynomial form (44)-(45).

At rest the reduced equation is G(theta) = 0. G holds the spring length rho = sqrt(R(theta))
(34); multiplied by rho it reads alpha + beta*rho = 0 with alpha, beta free of roots.
Squaring isolates the root: (beta*rho + alpha)(beta*rho - alpha) = beta^2 R - alpha^2 = 0.
Its roots are those of the genuine branch alpha + beta*rho = 0 and of the extraneous branch
beta*rho - alpha = 0, which squaring introduced. The tangent half-angle substitution turns
beta^2 R - alpha^2 into the polynomial sum sigma_i tau^i.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import square_roots
from .half_angle import to_tau


@dataclass(frozen=True)
class Equilibrium:
    residual: sp.Expr   # G(theta), (43)
    radicand: sp.Expr   # R(theta) = rho^2
    alpha: sp.Expr
    beta: sp.Expr
    sigma: tuple[sp.Expr, ...]  # sigma_0..sigma_degree, (45)
    weight: int                 # sum sigma_i tau^i = (1+tau^2)^weight (beta^2 R - alpha^2)

    @property
    def rho(self) -> sp.Expr:
        return sp.sqrt(self.radicand)

    @property
    def genuine_branch(self) -> sp.Expr:
        """alpha + beta*rho = rho * G: zero at the equilibria."""
        return self.alpha + self.beta * self.rho

    @property
    def extraneous_branch(self) -> sp.Expr:
        """beta*rho - alpha: zero at the roots squaring added."""
        return self.beta * self.rho - self.alpha

    @property
    def squared(self) -> sp.Expr:
        return self.beta**2 * self.radicand - self.alpha**2


def split_square_root(residual: sp.Expr) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Write rho * residual as alpha + beta*rho, rho = sqrt(radicand)."""
    (radicand,) = square_roots(residual)
    rho = sp.Dummy("rho", positive=True)
    times_rho = sp.Poly(sp.expand(residual.subs(sp.sqrt(radicand), rho) * rho), rho)
    reduced = times_rho.rem(sp.Poly(rho**2 - radicand, rho))
    if reduced.degree() > 1:
        raise ValueError("residual is not linear in its square root")
    beta, alpha = (reduced.coeff_monomial(rho), reduced.coeff_monomial(1))
    return radicand, sp.factor(alpha), sp.factor(beta)


def derive_equilibrium(residual: sp.Expr, theta: sp.Symbol) -> Equilibrium:
    radicand, alpha, beta = split_square_root(residual)
    poly = to_tau(beta**2 * radicand - alpha**2, theta)
    return Equilibrium(residual, radicand, alpha, beta,
                       sigma=poly.padded(2 * poly.weight + 1), weight=poly.weight)
