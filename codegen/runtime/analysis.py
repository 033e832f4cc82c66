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
where M = 0: statics need no inertia).

Complex quantities: omega_n and zeta are complex numbers, imaginary where K < 0 (an
unstable equilibrium: omega_n = sqrt(K/M)); JSON gives each as [re, im], the table prints
"25.1746 i". An extraneous root is not an equilibrium: its ``stability`` and ``damping`` are
None (JSON null).

Units: angles are radians in every field here (``theta``, ``theta_lo``, ``lo``, ...), each
with a ``..._deg`` property in degrees; ``Analysis.to_dict()`` (the JSON the command line
prints) gives degrees under ``_deg`` names. Everything else is SI, for a mechanism whose
independent coordinate is an angle: G [N m], M [kg m^2], B [N m s], K [N m] (per rad),
omega_n [rad/s], eigenvalues [1/s], zeta dimensionless.

Analyses pickle (their params are rebuilt from their library's origin), so
``multiprocessing.get_context("spawn").Pool().map(analyze, sets)`` works.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np

from .. import ccodes
from .library import Library, ParameterSet, params_shown

# The words of the C enums' codes, indexed by code: the values are codegen_model.h's, read
# from it (codegen.ccodes); a word is its member's name unless given here.
STABILITY = ccodes.words("codegen_stability")   # stable, marginal, unstable
DAMPING = ccodes.words("codegen_damping", CRITICALLY_DAMPED="critical", NOT_OSCILLATORY="none")
KINDS = ccodes.words("codegen_root_kind", OTHER_ASSEMBLY="other assembly mode")
UNCERTAINTIES = ccodes.words("codegen_uncertainty")   # cluster, singular
METHODS = ("auto", "polynomial", "isolate")

#: The kind of root that is not an equilibrium (the squared equation's, with a negative
#: length): its stability and damping are None (JSON null, empty in CSV, "-" in the table).
NOT_AN_EQUILIBRIUM = "extraneous"

#: A route's name, as ``analyze`` takes it.
Method = Literal["auto", "polynomial", "isolate"]


@dataclass(frozen=True)
class Equilibrium:
    """One real root of the equilibrium equation: where it is, what it is, and its
    linearised vibration. Angles in radians (``theta_deg``, ``theta_lo_deg``,
    ``theta_hi_deg`` in degrees); M, B, K and omega_n as for an angle coordinate."""

    theta: float           # theta_E [rad]
    theta_lo: float        # an interval [rad] holding theta_E; when certified, G has exactly
    theta_hi: float        #   one zero in it (G changes sign, G' keeps its sign) [rad]
    certified: bool        # proven to exist, in [theta_lo, theta_hi]
    genuine: bool          # an equilibrium of the declared mode (kind == "equilibrium")
    kind: str              # one of KINDS: "mode undecided" where the model's assembly-mode
                           #   conditions do not place the state in a mode (checked for each
                           #   parameter set: which sign of a root is declared can change)
    mode: int | None       # its assembly mode as declared: 0 the declared one, bit i set where
                           #   the i-th dyad is assembled the other way; None: undecided
    residual: float        # G(theta_E) [N m]
    relative_residual: float  # |G(theta_E)| over the size of its terms [1]
    M: float               # M_EQ, the inertia at theta_E [kg m^2]
    B: float               # B_EQ, the damping [N m s]
    K: float               # K_EQ = G'(theta_E), the stiffness [N m] (per rad)
    omega_n: complex       # natural frequency sqrt(K/M) [rad/s]; imaginary where K < 0,
                           #   NaN where M = 0
    zeta: complex          # damping ratio B/(2 M omega_n) [1]; NaN where M = 0
    eigenvalues: tuple[complex, complex]  # roots of M s^2 + B s + K [1/s]
    stability: str | None  # one of STABILITY; None for an extraneous root (not an equilibrium)
    damping: str | None    # one of DAMPING; None for an extraneous root

    @property
    def theta_deg(self) -> float:
        """theta_E [deg]."""
        return math.degrees(self.theta)

    @property
    def theta_lo_deg(self) -> float:
        """The lower end of the interval holding theta_E [deg]."""
        return math.degrees(self.theta_lo)

    @property
    def theta_hi_deg(self) -> float:
        """The upper end of the interval holding theta_E [deg]."""
        return math.degrees(self.theta_hi)


@dataclass(frozen=True)
class Uncertain:
    """An interval the certified isolation could not decide in double precision. Ends in
    radians (``lo_deg``, ``hi_deg`` in degrees)."""

    lo: float              # lower end [rad]
    hi: float              # upper end [rad]
    kind: str              # "cluster": G and G' within rounding of 0 (a fold, a pair too close
                           # to separate, or a near-double complex pair: none); "singular":
                           # G undefined or not smooth inside (a pole, a limit position)
    mode: int | None       # the assembly mode at its middle, as Equilibrium.mode
    sign_change: bool      # G changes sign across it: an odd number of zeros if G is continuous

    @property
    def lo_deg(self) -> float:
        """The lower end [deg]."""
        return math.degrees(self.lo)

    @property
    def hi_deg(self) -> float:
        """The upper end [deg]."""
        return math.degrees(self.hi)


@dataclass(frozen=True)
class Analysis:
    """Every equilibrium of one parameter set, by one route. Angles in radians (the
    ``_deg`` properties and ``to_dict`` give degrees)."""

    params: ParameterSet               # the parameter set analysed (SI units)
    sigma: tuple[float, ...]           # the polynomial route's sigma_i; () after isolation
    roots: tuple[Equilibrium, ...]     # every classified root, by angle
    singular: tuple[float, ...] = ()  # angles [rad] of roots where a square root is zero
    unassembled: tuple[float, ...] = ()  # angles [rad] of roots where it cannot be assembled
    uncertain: tuple[Uncertain, ...] = ()  # what the isolation route could not decide
    method: str = "polynomial"        # the route taken: "polynomial" or "isolate"

    @property
    def equilibria(self) -> tuple[Equilibrium, ...]:
        """The genuine equilibria (of the declared assembly mode)."""
        return tuple(r for r in self.roots if r.genuine)

    @property
    def singular_deg(self) -> tuple[float, ...]:
        """``singular`` [deg]."""
        return tuple(math.degrees(t) for t in self.singular)

    @property
    def unassembled_deg(self) -> tuple[float, ...]:
        """``unassembled`` [deg]."""
        return tuple(math.degrees(t) for t in self.unassembled)

    @property
    def library(self) -> Library:
        """The library the parameter set belongs to."""
        return type(self.params).library

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, angles in degrees (keys ending in _deg), everything else SI; an
        infinite zeta (K = 0 with B > 0) becomes null, never Infinity."""
        def finite(x: float) -> float | None:
            return x if math.isfinite(x) else None

        def pair(z: complex) -> list[float | None]:
            return [finite(z.real), finite(z.imag)]

        return {
            "params": params_shown(asdict(self.params), self.library.UNITS),
            "method": self.method,
            "sigma": list(self.sigma),
            "roots": [{
                "theta_deg": r.theta_deg, "genuine": r.genuine, "kind": r.kind,
                "mode": r.mode,
                "certified": r.certified,
                "theta_interval_deg": [r.theta_lo_deg, r.theta_hi_deg],
                "residual": r.residual,
                "relative_residual": r.relative_residual, "M": r.M, "B": r.B, "K": r.K,
                "omega_n": pair(r.omega_n), "zeta": pair(r.zeta),
                "eigenvalues": [pair(z) for z in r.eigenvalues],
                "stability": r.stability, "damping": r.damping,
            } for r in self.roots],
            "singular_roots_deg": list(self.singular_deg),
            "unassembled_roots_deg": list(self.unassembled_deg),
            "uncertain": [{"interval_deg": [u.lo_deg, u.hi_deg], "kind": u.kind,
                           "mode": u.mode, "sign_change": u.sign_change}
                          for u in self.uncertain],
        }


def _mode(mode: int, library: Library) -> int | None:
    """A mode number from C (N_MODES: undecided) as Python's (None: undecided)."""
    return None if mode >= library.modes else int(mode)


def _equilibrium(e: Any, library: Library) -> Equilibrium:
    scale = e.residual_scale
    return Equilibrium(
        theta=e.theta, theta_lo=e.theta_lo, theta_hi=e.theta_hi, certified=bool(e.certified),
        genuine=bool(e.genuine), kind=KINDS[e.kind], mode=_mode(e.mode, library),
        residual=e.residual,
        relative_residual=abs(e.residual) / scale if scale else 0.0,
        M=e.M, B=e.B, K=e.K,
        omega_n=complex(e.omega_n[0], e.omega_n[1]), zeta=complex(e.zeta[0], e.zeta[1]),
        eigenvalues=(complex(e.eigen_re[0], e.eigen_im[0]), complex(e.eigen_re[1], e.eigen_im[1])),
        stability=None if KINDS[e.kind] == NOT_AN_EQUILIBRIUM else STABILITY[e.stability],
        damping=None if KINDS[e.kind] == NOT_AN_EQUILIBRIUM else DAMPING[e.damping],
    )


def _from_c(params: ParameterSet, result: Any, method: str) -> Analysis:
    return Analysis(params, tuple(result.sigma) if method == "polynomial" else (),
                    tuple(_equilibrium(result.roots[i], params.library)
                          for i in range(result.n_roots)),
                    tuple(result.singular_theta[i] for i in range(result.n_singular)),
                    tuple(result.unassembled_theta[i] for i in range(result.n_unassembled)),
                    tuple(Uncertain(u.lo, u.hi, UNCERTAINTIES[u.kind],
                                    _mode(u.mode, params.library),
                                    bool(u.sign_change))
                          for u in (result.uncertain[i] for i in range(result.n_uncertain))),
                    method)


def library_of_params(params: ParameterSet) -> Library:
    """The library a parameter set belongs to; TypeError if it is not a library's Params."""
    library = getattr(type(params), "library", None)
    if library is None:
        raise TypeError("expected the Params of a library (Library.example_params()), not "
                        f"{type(params).__name__}")
    return library


def route(library: Library, method: Method = "auto") -> Literal["polynomial", "isolate"]:
    """The route a method name takes for this library: "polynomial" or "isolate". Raises
    ValueError for an unknown method, or "polynomial" where G is not algebraic."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, not {method!r}")
    if method == "auto":
        return "polynomial" if library.has_polynomial else "isolate"
    if method == "polynomial" and not library.has_polynomial:
        raise ValueError(f"{library.PREFIX}: G is not algebraic in cos and sin of the angle, so "
                         "no polynomial holds its equilibria: use the isolation route")
    return method


def entry(library: Library, method: str, batch: bool = False) -> Any:
    """The C entry point of a route ("polynomial" or "isolate"), or its batch form."""
    name = {"polynomial": "analyze", "isolate": "isolate"}[method]
    return getattr(library.lib, f"{library.PREFIX}_{name}{'_batch' if batch else ''}")


def analyze(params: ParameterSet, method: Method = "auto") -> Analysis:
    """Every equilibrium for ``params`` (a Library's Params, SI units), by the route
    ``method`` names ("auto", "polynomial" or "isolate"), classified and linearised; angles
    in radians.

    Raises LibraryError (a ValueError) naming the parameter(s) responsible and their values,
    e.g. "F: a result is too large to represent (F=1e+308)"; ValueError for an unknown or
    unavailable method; TypeError if params is not a library's Params.
    """
    library = library_of_params(params)
    taken = route(library, method)
    c_entry, analysis_type = entry(library, taken), f"{library.PREFIX}_analysis *"
    result = library.ffi.new(analysis_type)

    def rerun(values: Any) -> int:
        return c_entry(library._c_params(values), library.ffi.new(analysis_type))

    library.check(c_entry(library._c_params(params), result), params, rerun=rerun)
    return _from_c(params, result, taken)


def analyze_batch(table: np.ndarray, library: Library, method: Method = "auto"
                  ) -> tuple[list[Analysis | None], np.ndarray]:
    """analyze over a params_array (numpy structured array of parameter sets, SI units), in
    one C call: (analyses, statuses), None where an item failed; statuses holds the C status
    of each item (0: OK; ``library.error(status, params)`` explains one)."""
    ffi, P = library.ffi, library.PREFIX
    taken = route(library, method)
    table = library.table(table)
    results = ffi.new(f"{P}_analysis[]", len(table))
    statuses = np.zeros(len(table), dtype=np.intc)
    entry(library, taken, batch=True)(
        len(table), ffi.from_buffer(f"{P}_params[]", table), results,
        ffi.from_buffer(f"{P}_status[]", statuses, require_writable=True))
    analyses = [
        _from_c(library.Params(**{n: float(table[n][i]) for n in library.PARAMETER_NAMES}),
                results[i], taken)
        if statuses[i] == library.STATUS["OK"] else None for i in range(len(table))]
    return analyses, statuses
