"""The vibration analysis of Table 1 steps 8-10 for one parameter set, from Python.

``analyze(params)`` calls the C entry point once and returns every real root of (45),
classified as a genuine equilibrium or a root squaring added, with M, B, K, omega_n,
zeta, eigenvalues, stability and damping at each: the paper's Table 3.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from . import api
from ._native import ffi, lib

STABILITY = {lib.DOUGHTY_STABLE: "stable", lib.DOUGHTY_MARGINAL: "marginal",
             lib.DOUGHTY_UNSTABLE: "unstable"}
DAMPING = {lib.DOUGHTY_UNDERDAMPED: "underdamped", lib.DOUGHTY_CRITICALLY_DAMPED: "critical",
           lib.DOUGHTY_OVERDAMPED: "overdamped", lib.DOUGHTY_UNDAMPED: "undamped",
           lib.DOUGHTY_NOT_OSCILLATORY: "none"}


@dataclass(frozen=True)
class Equilibrium:
    theta: float           # theta_E [rad]
    genuine: bool          # satisfies (43); else a root squaring added
    residual: float        # G(theta_E) [N m]
    relative_residual: float  # |G(theta_E)| over the size of its terms
    M: float
    B: float
    K: float
    omega_n: complex
    zeta: complex
    eigenvalues: tuple[complex, complex]
    stability: str
    damping: str

    @property
    def theta_deg(self) -> float:
        return math.degrees(self.theta)


@dataclass(frozen=True)
class Analysis:
    params: object
    sigma: tuple[float, ...]
    roots: tuple[Equilibrium, ...]
    singular: tuple[float, ...] = ()  # angles [rad] of roots where r = 0: (43) undefined

    @property
    def equilibria(self) -> tuple[Equilibrium, ...]:
        return tuple(r for r in self.roots if r.genuine)

    def to_dict(self) -> dict:
        """JSON-ready; an infinite zeta (K = 0 with B > 0) becomes null, never Infinity."""
        def finite(x: float) -> float | None:
            return x if math.isfinite(x) else None

        def pair(z: complex) -> list[float | None]:
            return [finite(z.real), finite(z.imag)]

        return {
            "params": asdict(self.params),
            "sigma": list(self.sigma),
            "roots": [{
                "theta_deg": r.theta_deg, "genuine": r.genuine, "residual": r.residual,
                "relative_residual": r.relative_residual, "M": r.M, "B": r.B, "K": r.K,
                "omega_n": pair(r.omega_n), "zeta": pair(r.zeta),
                "eigenvalues": [pair(z) for z in r.eigenvalues],
                "stability": r.stability, "damping": r.damping,
            } for r in self.roots],
            "singular_roots_deg": [math.degrees(t) for t in self.singular],
        }


def _equilibrium(e) -> Equilibrium:
    scale = e.residual_scale
    return Equilibrium(
        theta=e.theta, genuine=bool(e.genuine), residual=e.residual,
        relative_residual=abs(e.residual) / scale if scale else 0.0,
        M=e.M, B=e.B, K=e.K,
        omega_n=complex(e.omega_n[0], e.omega_n[1]), zeta=complex(e.zeta[0], e.zeta[1]),
        eigenvalues=tuple(complex(e.eigen_re[i], e.eigen_im[i]) for i in range(2)),
        stability=STABILITY[e.stability], damping=DAMPING[e.damping],
    )


def _from_c(params, result) -> Analysis:
    return Analysis(params, tuple(result.sigma),
                    tuple(_equilibrium(result.roots[i]) for i in range(result.n_roots)),
                    tuple(result.singular_theta[i] for i in range(result.n_singular)))


def analyze(params=None) -> Analysis:
    """Every real root of (45) for ``params`` (Table 2 by default), classified and linearised."""
    params = params if params is not None else api.example_params()
    result = ffi.new("doughty_analysis *")
    api.check(lib.doughty_analyze(api._c_params(params), result), asdict(params))
    return _from_c(params, result)


def analyze_batch(table) -> tuple[list[Analysis | None], np.ndarray]:
    """analyze over a params_array; (analyses, statuses), None where an item failed."""
    table = np.ascontiguousarray(table, dtype=api.PARAMS_DTYPE)
    results = ffi.new("doughty_analysis[]", len(table))
    statuses = np.zeros(len(table), dtype=np.intc)
    lib.doughty_analyze_batch(len(table), ffi.from_buffer("doughty_params[]", table), results,
                              ffi.from_buffer("doughty_status[]", statuses,
                                              require_writable=True))
    analyses = [
        _from_c(api.Params(**{n: float(table[n][i]) for n in api.PARAMETER_NAMES}), results[i])
        if statuses[i] == api.STATUS["OK"] else None for i in range(len(table))]
    return analyses, statuses


def _number(x: float, digits: int = 4) -> str:
    """Fixed decimals like the paper's Table 3, scientific for values below 1e-2."""
    return f"{x:.{digits}f}" if x == 0 or abs(x) >= 1e-2 else f"{x:.{digits}e}"


def _complex(z: complex, digits: int = 4) -> str:
    if z.imag == 0:
        return _number(z.real, digits)
    if z.real == 0:
        return f"{_number(z.imag, digits)} i"
    return f"{_number(z.real, digits)}{'+' if z.imag >= 0 else '-'}{_number(abs(z.imag), digits)} i"


def table(analysis: Analysis) -> str:
    """A table like the paper's Table 3, plus what the paper leaves implicit."""
    head = (f"{'theta_E [deg]':>14} {'kind':>10} {'M_EQ':>8} {'B_EQ':>11} {'K_EQ':>11} "
            f"{'omega_n':>12} {'zeta':>13} {'eigenvalues [1/s]':>36} {'stability':>9} "
            f"{'damping':>11}")
    lines = [head, "-" * len(head)]
    for r in analysis.roots:
        eig = ", ".join(_complex(z, 4) for z in r.eigenvalues)
        lines.append(
            f"{r.theta_deg:14.4f} {'genuine' if r.genuine else 'extraneous':>10} {r.M:8.4f} "
            f"{_number(r.B):>11} {_number(r.K):>11} {_complex(r.omega_n):>12} "
            f"{_complex(r.zeta):>13} "
            f"{eig:>36} {r.stability:>9} {r.damping:>11}")
    n = len(analysis.roots) + len(analysis.singular)
    g = len(analysis.equilibria)
    lines.append(f"\n{n} real roots of (45): {g} genuine equilibria, "
                 f"{len(analysis.roots) - g} extraneous (roots of the squared equation only)"
                 + (f", {len(analysis.singular)} where r = 0." if analysis.singular else "."))
    if analysis.singular:
        angles = ", ".join(f"{math.degrees(t):.4f}" for t in analysis.singular)
        lines.append(f"Roots where the spring length r is zero, so (43) is undefined: {angles} deg.")
    lines.append("sigma_0..sigma_12 of (45):")
    lines += [f"  sigma_{i:<2} = {s: .10e}" for i, s in enumerate(analysis.sigma)]
    return "\n".join(lines)
