"""The vibration analysis of Table 1 steps 8-10 for one parameter set, from Python.

``analyze(params, method)`` calls the C entry point of the params' library once, by one of
two routes:

* ``"polynomial"``: every real root of the equilibrium polynomial sigma, labelled by what it
  is (an equilibrium as declared, an equilibrium of another assembly mode, or extraneous: a
  negative length), each equilibrium certified by interval enclosures around it where they
  prove it; for the paper's example, its Table 3. Roots where the mechanism cannot be
  assembled, or a square root is zero, are listed apart.
* ``"isolate"``: every zero of G itself on every assembly mode, each proven in an interval
  (G changes sign there and G' keeps its sign), with what double precision cannot decide
  (a fold, a pair too close to separate, a pole of G) listed as uncertain intervals. This is
  the only route where G is not algebraic (no polynomial holds it).

``"auto"`` (the default) takes the polynomial route where there is one. Every equilibrium
carries M, B, K, omega_n, zeta, eigenvalues, stability and damping (omega_n and zeta are NaN
where M = 0: statics need no inertia). Angles are radians here, degrees on the command line.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from .library import Library

# The C enums' values, in order (templates/analysis.h.j2).
STABILITY = ("stable", "marginal", "unstable")
DAMPING = ("underdamped", "critical", "overdamped", "undamped", "none")
KINDS = ("equilibrium", "other assembly mode", "extraneous")
UNCERTAINTIES = ("cluster", "singular")
METHODS = ("auto", "polynomial", "isolate")


@dataclass(frozen=True)
class Equilibrium:
    theta: float           # theta_E [rad]
    theta_lo: float        # an interval [rad] holding theta_E; when certified, G has exactly
    theta_hi: float        #   one zero in it (G changes sign, G' keeps its sign)
    certified: bool        # proven to exist, in [theta_lo, theta_hi]
    genuine: bool          # an equilibrium of the declared mode (kind == "equilibrium")
    kind: str              # one of KINDS
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
class Uncertain:
    """An interval the certified isolation could not decide in double precision."""

    lo: float              # [rad]
    hi: float
    kind: str              # "cluster": G and G' within rounding of 0 (a fold, a pair too close
                           # to separate, or a near-double complex pair: none); "singular":
                           # G undefined or not smooth inside (a pole, a limit position)
    mode: int              # the assembly mode it was found on (0: as declared)
    sign_change: bool      # G changes sign across it: an odd number of zeros if G is continuous

    @property
    def lo_deg(self) -> float:
        return math.degrees(self.lo)

    @property
    def hi_deg(self) -> float:
        return math.degrees(self.hi)


@dataclass(frozen=True)
class Analysis:
    params: object
    sigma: tuple[float, ...]           # the polynomial route's sigma_i; () after isolation
    roots: tuple[Equilibrium, ...]
    singular: tuple[float, ...] = ()  # angles [rad] of roots where a square root is zero
    unassembled: tuple[float, ...] = ()  # angles [rad] of roots where it cannot be assembled
    uncertain: tuple[Uncertain, ...] = ()
    method: str = "polynomial"        # the route taken: "polynomial" or "isolate"

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
            "method": self.method,
            "sigma": list(self.sigma),
            "roots": [{
                "theta_deg": r.theta_deg, "genuine": r.genuine, "kind": r.kind,
                "certified": r.certified,
                "theta_interval_deg": [math.degrees(r.theta_lo), math.degrees(r.theta_hi)],
                "residual": r.residual,
                "relative_residual": r.relative_residual, "M": r.M, "B": r.B, "K": r.K,
                "omega_n": pair(r.omega_n), "zeta": pair(r.zeta),
                "eigenvalues": [pair(z) for z in r.eigenvalues],
                "stability": r.stability, "damping": r.damping,
            } for r in self.roots],
            "singular_roots_deg": [math.degrees(t) for t in self.singular],
            "unassembled_roots_deg": [math.degrees(t) for t in self.unassembled],
            "uncertain": [{"interval_deg": [u.lo_deg, u.hi_deg], "kind": u.kind,
                           "mode": u.mode, "sign_change": u.sign_change}
                          for u in self.uncertain],
        }


def _equilibrium(e) -> Equilibrium:
    scale = e.residual_scale
    return Equilibrium(
        theta=e.theta, theta_lo=e.theta_lo, theta_hi=e.theta_hi, certified=bool(e.certified),
        genuine=bool(e.genuine), kind=KINDS[e.kind], residual=e.residual,
        relative_residual=abs(e.residual) / scale if scale else 0.0,
        M=e.M, B=e.B, K=e.K,
        omega_n=complex(e.omega_n[0], e.omega_n[1]), zeta=complex(e.zeta[0], e.zeta[1]),
        eigenvalues=tuple(complex(e.eigen_re[i], e.eigen_im[i]) for i in range(2)),
        stability=STABILITY[e.stability], damping=DAMPING[e.damping],
    )


def _from_c(params, result, method: str) -> Analysis:
    return Analysis(params, tuple(result.sigma) if method == "polynomial" else (),
                    tuple(_equilibrium(result.roots[i]) for i in range(result.n_roots)),
                    tuple(result.singular_theta[i] for i in range(result.n_singular)),
                    tuple(result.unassembled_theta[i] for i in range(result.n_unassembled)),
                    tuple(Uncertain(u.lo, u.hi, UNCERTAINTIES[u.kind], int(u.mode),
                                    bool(u.sign_change))
                          for u in (result.uncertain[i] for i in range(result.n_uncertain))),
                    method)


def _library(params) -> Library:
    library = getattr(type(params), "library", None)
    if library is None:
        raise TypeError("analyze takes the Params of a library (Library.example_params())")
    return library


def route(library: Library, method: str = "auto") -> str:
    """The route a method name takes for this library: "polynomial" or "isolate"."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, not {method!r}")
    if method == "auto":
        return "polynomial" if library.has_polynomial else "isolate"
    if method == "polynomial" and not library.has_polynomial:
        raise ValueError(f"{library.PREFIX}: G is not algebraic in cos and sin of the angle, so "
                         "no polynomial holds its equilibria: use the isolation route")
    return method


def _entry(library: Library, method: str, batch: bool = False):
    name = {"polynomial": "analyze", "isolate": "isolate"}[method]
    return getattr(library.lib, f"{library.PREFIX}_{name}{'_batch' if batch else ''}")


def analyze(params, method: str = "auto") -> Analysis:
    """Every equilibrium for ``params`` (a Library's Params), by the route ``method`` names
    ("auto", "polynomial" or "isolate"), classified and linearised."""
    library = _library(params)
    taken = route(library, method)
    result = library.ffi.new(f"{library.PREFIX}_analysis *")
    library.check(_entry(library, taken)(library._c_params(params), result), asdict(params))
    return _from_c(params, result, taken)


def analyze_batch(table, library: Library, method: str = "auto"
                  ) -> tuple[list[Analysis | None], np.ndarray]:
    """analyze over a params_array; (analyses, statuses), None where an item failed."""
    ffi, P = library.ffi, library.PREFIX
    taken = route(library, method)
    table = np.ascontiguousarray(table, dtype=library.PARAMS_DTYPE)
    results = ffi.new(f"{P}_analysis[]", len(table))
    statuses = np.zeros(len(table), dtype=np.intc)
    _entry(library, taken, batch=True)(
        len(table), ffi.from_buffer(f"{P}_params[]", table), results,
        ffi.from_buffer(f"{P}_status[]", statuses, require_writable=True))
    analyses = [
        _from_c(library.Params(**{n: float(table[n][i]) for n in library.PARAMETER_NAMES}),
                results[i], taken)
        if statuses[i] == library.STATUS["OK"] else None for i in range(len(table))]
    return analyses, statuses
