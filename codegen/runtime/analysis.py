"""The vibration analysis of one parameter set, from Python, for any number of coordinates.

``analyze(params, method)`` calls the C entry point of the params' library once; it is the one
place that tells one coordinate from several. With one coordinate (Table 1 steps 8-10) it
returns an ``Analysis``, by one of two routes:

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

With several coordinates there is one route, ``"isolate"`` (``"auto"`` takes it,
``"polynomial"`` is refused): the C ``NAME_analyze`` (the runtime's codegen_multibody.c)
isolates every zero of G in the box of the coordinates' ranges, each proven the only one in
its box, and ``analyze`` returns a ``MultibodyAnalysis``: ``equilibria`` (each with its
coordinates, its box, M, B, K, the undamped natural frequencies and mass-normalised mode
shapes, the damped eigenvalues with their damping ratios, and the stability) and
``uncertain`` (boxes, never equilibria).

Both results have ``params``, ``method``, ``roots``, ``equilibria``, ``uncertain`` and
``to_dict()``, the JSON the command line prints: one shape for every mechanism (see
``to_dict``; docs/python.md, "The JSON").

One vocabulary for both: ``STABILITY`` and ``UNCERTAINTIES``. Stability: "stable" (one
coordinate: K > 0 and B > 0; several: K positive definite, every omega^2 > 0), "unstable"
(K < 0; some omega^2 < 0), "marginal" (one coordinate only: K > 0 with B = 0, or K = 0
exactly; a decided verdict: a disturbance neither grows nor decays) and "undecided" (several
coordinates only: the least omega^2 is within rounding of zero, so double precision cannot
tell stable from unstable).

Complex quantities: omega_n and zeta are complex numbers, imaginary where K < 0 (an
unstable equilibrium: omega_n = sqrt(K/M); with several coordinates each mode's, imaginary
where its omega^2 < 0); JSON gives each as [re, im], the table prints "25.1746 i". An
extraneous root is not an equilibrium: its ``stability`` and ``damping`` are None (JSON null).

Units: angles are radians in every field here (``theta``, ``theta_lo``, ``lo``, ...), each
with a ``..._deg`` property in degrees for one coordinate; ``to_dict()`` (the JSON the
command line prints) gives degrees under ``_deg`` names. Everything else is SI, for a
mechanism whose independent coordinate is an angle: G [N m], M [kg m^2], B [N m s], K [N m]
(per rad), omega_n [rad/s], eigenvalues [1/s], zeta dimensionless.

Analyses pickle (their params are rebuilt from their library's origin), so
``multiprocessing.get_context("spawn").Pool().map(analyze, sets)`` works.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np

from .. import ccodes
from ..errors import LibraryError
from .library import Library, ParameterSet, params_shown

#: The words of stability, for any number of coordinates (their codes are the indices, in
#: batch tables, sweeps and branches). 0-2 are one coordinate's C enum codegen_stability
#: (codegen_model.h, read from it by codegen.ccodes): "marginal" is one coordinate's only
#: (K > 0 undamped, or K = 0 exactly). "undecided" (3) is several coordinates' only:
#: codegen_multibody.h's CODEGEN_MB_UNDECIDED, the least omega^2 within rounding of zero.
STABILITY = ccodes.words("codegen_stability") + ("undecided",)
# The words of the C enums' codes, indexed by code (a word is its member's name unless given).
DAMPING = ccodes.words("codegen_damping", CRITICALLY_DAMPED="critical", NOT_OSCILLATORY="none")
KINDS = ccodes.words("codegen_root_kind", OTHER_ASSEMBLY="other assembly mode")
#: What the isolation could not decide, for any number of coordinates: one coordinate's C
#: codes (cluster, singular) and several coordinates' end of a range.
UNCERTAINTIES = ccodes.words("codegen_uncertainty") + ("at the end of a range",)
METHODS = ("auto", "polynomial", "isolate")
#: codegen_multibody.h's stability codes (1, 0, -1) as words of STABILITY.
MULTIBODY_STABILITY = ccodes.named({"MB_STABLE": "stable", "MB_UNSTABLE": "unstable",
                                    "MB_UNDECIDED": "undecided"})
#: codegen_boxes.h's and codegen_multibody.h's kinds of an undecided box as UNCERTAINTIES' words.
MULTIBODY_UNCERTAIN = ccodes.named({"BOX_CLUSTER": "cluster", "BOX_SINGULAR": "singular",
                                   "MB_AT_RANGE_END": "at the end of a range"})

#: The kind of root that is not an equilibrium (the squared equation's, with a negative
#: length): its stability and damping are None (JSON null, empty in CSV, "-" in the table).
NOT_AN_EQUILIBRIUM = "extraneous"

#: A route's name, as ``analyze`` takes it.
Method = Literal["auto", "polynomial", "isolate"]


def _finite(x: float) -> float | None:
    """A float for JSON: null where it is NaN or infinite (never NaN or Infinity tokens)."""
    x = float(x)
    return x if math.isfinite(x) else None


def _pair(z: complex) -> list[float | None]:
    """A complex number for JSON: [re, im]."""
    return [_finite(z.real), _finite(z.imag)]


def _plain(x: Any) -> Any:
    """Nested arrays and lists of floats for JSON (NaN and infinities null)."""
    if isinstance(x, (list, tuple, np.ndarray)):
        return [_plain(v) for v in x]
    return _finite(x)


@dataclass(frozen=True)
class Coordinate:
    """An independent coordinate as the JSON names it: an angle (unit rad) in degrees under
    ``NAME_deg``, its proven interval under ``NAME_interval_deg``; any other (a length, m)
    in SI under ``NAME`` and ``NAME_interval``."""

    name: str
    unit: str               # its SI unit: "rad" for an angle

    @property
    def angle(self) -> bool:
        """Whether it is an angle (shown in degrees)."""
        return self.unit == "rad"

    @property
    def key(self) -> str:
        """The JSON key of its value."""
        return f"{self.name}_deg" if self.angle else self.name

    @property
    def interval_key(self) -> str:
        """The JSON key of an interval of it, [lo, hi]."""
        return f"{self.name}_interval_deg" if self.angle else f"{self.name}_interval"

    def shown(self, value: float) -> float | None:
        """A value in the JSON's unit: degrees for an angle, else SI."""
        return _finite(math.degrees(value) if self.angle else value)

    def described(self) -> dict[str, str]:
        """Its entry of the JSON's ``coordinates``: name, unit (as the JSON gives it), key."""
        return {"name": self.name, "unit": "deg" if self.angle else self.unit, "key": self.key}


def coordinates_of(library: Library) -> tuple[Coordinate, ...]:
    """A library's independent coordinates: one coordinate is the angle ``theta``, several
    are those the model names (SPEC["coordinates"])."""
    if library.dof == 1:
        return (Coordinate("theta", "rad"),)
    return tuple(Coordinate(c["name"], c["unit"]) for c in library.SPEC["coordinates"])


def _document(params: ParameterSet, method: str, sigma: Any, roots: list[dict[str, Any]],
              singular: list[float], unassembled: list[float],
              uncertain: list[dict[str, Any]]) -> dict[str, Any]:
    """The JSON of an analysis, for any number of coordinates: its keys, in their order."""
    library = library_of_params(params)
    return {
        "params": params_shown(asdict(params), library.UNITS),
        "method": method,
        "coordinates": [c.described() for c in coordinates_of(library)],
        "sigma": [float(x) for x in sigma],
        "roots": roots,
        "singular_roots_deg": singular,
        "unassembled_roots_deg": unassembled,
        "uncertain": uncertain,
    }


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

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The independent coordinate's name, as several coordinates list theirs: theta."""
        return ("theta",)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, the one shape of every analysis (docs/python.md, "The JSON"): angles
        in degrees (keys ending in _deg), everything else SI; an infinite zeta (K = 0 with
        B > 0) becomes null, never Infinity."""
        (theta,) = coordinates_of(self.library)
        return _document(self.params, self.method, self.sigma, [{
            "theta_deg": r.theta_deg, "genuine": r.genuine, "kind": r.kind,
            "mode": r.mode,
            "certified": r.certified,
            "theta_interval_deg": [r.theta_lo_deg, r.theta_hi_deg],
            "residual": _finite(r.residual),
            "relative_residual": _finite(r.relative_residual),
            "M": _finite(r.M), "B": _finite(r.B), "K": _finite(r.K),
            "omega_n": _pair(r.omega_n), "zeta": _pair(r.zeta),
            "eigenvalues": [_pair(z) for z in r.eigenvalues],
            "stability": r.stability, "damping": r.damping,
        } for r in self.roots], list(self.singular_deg), list(self.unassembled_deg), [{
            "interval_deg": [u.lo_deg, u.hi_deg], theta.interval_key: [u.lo_deg, u.hi_deg],
            "kind": u.kind, "mode": u.mode, "sign_change": u.sign_change}
            for u in self.uncertain])


# ----------------------------------------------------------------- several coordinates

@dataclass(frozen=True, eq=False)
class MultibodyEquilibrium:
    """One proven equilibrium of a mechanism with n coordinates and its modes. Coordinates
    in radians (an angle) or metres; M, B, K the n x n matrices there (SI)."""

    theta: np.ndarray          # the independent coordinates [rad or m]
    lo: np.ndarray             # the box proven to hold exactly this one equilibrium
    hi: np.ndarray
    omega_squared: np.ndarray  # K phi = omega^2 M phi, ascending [rad^2/s^2]
    shapes: np.ndarray         # n x n, column j: mode j, phi^T M phi = 1
    eigenvalues: np.ndarray    # the 2n roots s of det(M s^2 + B s + K) [1/s], complex
    damping_ratios: np.ndarray  # -Re s / |s| of each eigenvalue
    modal_damping: np.ndarray  # phi_j^T B phi_j / (2 omega_j): mode j's damping ratio, NaN
                               #   where omega_j^2 <= 0 (``zeta`` gives it complex there)
    stability: str             # "stable", "unstable" or "undecided" (STABILITY)
    zeta: np.ndarray           # each mode's damping ratio phi^T B phi / (2 omega_n), complex:
                               #   imaginary where omega^2 < 0, as one coordinate's zeta
    M: np.ndarray              # the mass, damping and stiffness matrices there, n x n (NaN
    B: np.ndarray              #   where the library could not evaluate them)
    K: np.ndarray

    #: As one coordinate's Equilibrium: every root of several coordinates is a proven
    #: equilibrium of the declared assembly mode.
    kind = "equilibrium"
    genuine = True
    certified = True
    mode = 0

    @property
    def stable(self) -> bool:
        """Whether its stability is "stable"."""
        return self.stability == "stable"

    @property
    def omega_n(self) -> np.ndarray:
        """Each mode's natural frequency sqrt(omega^2) [rad/s], complex: imaginary where
        omega^2 < 0 (the mode is unstable), as one coordinate's omega_n."""
        return np.sqrt(self.omega_squared.astype(complex))

    @property
    def frequencies(self) -> np.ndarray:
        """The undamped natural frequencies [rad/s] (NaN where omega^2 < 0)."""
        with np.errstate(invalid="ignore"):
            return np.sqrt(self.omega_squared)


@dataclass(frozen=True, eq=False)
class UncertainBox:
    """A box the isolation could not decide: never an equilibrium."""

    lo: np.ndarray
    hi: np.ndarray
    kind: str   # one of UNCERTAINTIES: "cluster", "singular" or "at the end of a range"


@dataclass(frozen=True, eq=False)
class MultibodyAnalysis:
    """Every equilibrium of one parameter set of a mechanism with n coordinates, in the box
    of their ranges, ordered by their coordinates, with the boxes not decided. Coordinates in
    radians or metres (``to_dict`` gives angles in degrees)."""

    params: ParameterSet                          # the parameter set analysed (SI units)
    coordinates: tuple[str, ...]                  # the independent coordinates' names
    equilibria: tuple[MultibodyEquilibrium, ...]  # every one proven
    uncertain: tuple[UncertainBox, ...]           # boxes not decided, never equilibria
    method: str = "isolate"                       # the one route: isolation in boxes

    @property
    def roots(self) -> tuple[MultibodyEquilibrium, ...]:
        """Every root: the equilibria (each proven, of the declared mode)."""
        return self.equilibria

    @property
    def sigma(self) -> tuple[float, ...]:
        """No polynomial: ()."""
        return ()

    @property
    def library(self) -> Library:
        """The library the parameter set belongs to."""
        return type(self.params).library

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, the one shape of every analysis (docs/python.md, "The JSON"): each
        coordinate under its ``Coordinate.key`` (an angle in degrees, NAME_deg) and its box
        under ``interval_key``; per mode lists of omega_n and zeta as [re, im] pairs,
        eigenvalues as pairs; NaN and infinities null."""
        coordinates = coordinates_of(self.library)

        def place(lo: np.ndarray, hi: np.ndarray) -> dict[str, Any]:
            return {c.interval_key: [c.shown(a), c.shown(b)]
                    for c, a, b in zip(coordinates, lo, hi)}

        roots = [{
            **{c.key: c.shown(v) for c, v in zip(coordinates, e.theta)},
            "genuine": e.genuine, "kind": e.kind, "mode": e.mode, "certified": e.certified,
            **place(e.lo, e.hi),
            "M": _plain(e.M), "B": _plain(e.B), "K": _plain(e.K),
            "omega_n": [_pair(z) for z in e.omega_n], "zeta": [_pair(z) for z in e.zeta],
            "eigenvalues": [_pair(z) for z in e.eigenvalues],
            "stability": e.stability,
            "omega_squared": _plain(e.omega_squared), "mode_shapes": _plain(e.shapes),
            "damping_ratios": _plain(e.damping_ratios),
        } for e in self.equilibria]
        return _document(self.params, self.method, (), roots, [], [],
                         [{**place(u.lo, u.hi), "kind": u.kind} for u in self.uncertain])


def _array(ffi: Any, field: Any, count: int) -> np.ndarray:
    return np.frombuffer(ffi.buffer(field), dtype=np.float64)[:count].copy()


def _matrices(library: Library, params: ParameterSet, theta: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, B and K at theta; NaN where the library cannot evaluate them there."""
    try:
        return tuple(np.asarray(getattr(library, name)(params, theta), dtype=float)
                     for name in ("mass_matrix", "damping_matrix", "stiffness_matrix"))
    except LibraryError:   # the analysis found the point; its modes say what is wrong there
        n = library.dof
        return (np.full((n, n), np.nan),) * 3


def _modal_zeta(omega_squared: np.ndarray, modal_damping: np.ndarray, shapes: np.ndarray,
                B: np.ndarray) -> np.ndarray:
    """Each mode's phi^T B phi / (2 omega_n), complex: the C's where omega^2 > 0, else from B
    (imaginary where omega^2 < 0; infinite where omega^2 = 0 and the mode is damped)."""
    zeta = modal_damping.astype(complex)
    form = np.einsum("ij,ik,kj->j", shapes, B, shapes)
    for j, w2 in enumerate(omega_squared):
        if w2 < 0:
            zeta[j] = -1j * form[j] / (2 * math.sqrt(-w2))   # B / (2 i w) = -i B / (2 w)
        elif w2 == 0:
            zeta[j] = math.inf if form[j] > 0 else 0.0
    return zeta


def _read_several(params: ParameterSet, result: Any) -> MultibodyAnalysis:
    """A MultibodyAnalysis of the C NAME_analysis ``result`` of ``params``."""
    library = library_of_params(params)
    ffi, n = library.ffi, library.dof
    count, uncertain = result.n_equilibria, result.n_uncertain

    def rows(field: Any, width: int) -> np.ndarray:
        return _array(ffi, field, count * width).reshape(count, width)

    theta, lo, hi = rows(result.theta, n), rows(result.lo, n), rows(result.hi, n)
    omega_squared, shapes = rows(result.omega_squared, n), rows(result.shapes, n * n)
    s = rows(result.s_re, 2 * n) + 1j * rows(result.s_im, 2 * n)
    ratios, modal = rows(result.damping_ratio, 2 * n), rows(result.modal_damping, n)
    equilibria = []
    for r in range(count):
        M, B, K = _matrices(library, params, theta[r])
        shape = shapes[r].reshape(n, n)
        equilibria.append(MultibodyEquilibrium(
            theta[r], lo[r], hi[r], omega_squared[r], shape, s[r], ratios[r], modal[r],
            MULTIBODY_STABILITY[result.stability[r]],
            _modal_zeta(omega_squared[r], modal[r], shape, B), M, B, K))
    equilibria.sort(key=lambda e: tuple(e.theta))
    u_lo = _array(ffi, result.uncertain_lo, uncertain * n).reshape(uncertain, n)
    u_hi = _array(ffi, result.uncertain_hi, uncertain * n).reshape(uncertain, n)
    boxes = [UncertainBox(u_lo[u], u_hi[u], MULTIBODY_UNCERTAIN[result.uncertain_kind[u]])
             for u in range(uncertain)]
    names = tuple(c.name for c in coordinates_of(library))
    return MultibodyAnalysis(params, names, tuple(equilibria), tuple(boxes))


# ----------------------------------------------------------------- one coordinate from C

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
    """The route a method name takes for this library: "polynomial" or "isolate" ("auto":
    the polynomial where there is one). Several coordinates have one route, "isolate" (the
    proven isolation in boxes). Raises ValueError for an unknown method, or "polynomial"
    where G is not algebraic or there are several coordinates."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, not {method!r}")
    if library.dof > 1:
        if method == "polynomial":
            raise ValueError(f"{library.PREFIX}: with several coordinates there is no "
                             "polynomial route; its equilibria are isolated in boxes (method "
                             "isolate or auto)")
        return "isolate"
    if method == "auto":
        return "polynomial" if library.has_polynomial else "isolate"
    if method == "polynomial" and not library.has_polynomial:
        raise ValueError(f"{library.PREFIX}: G is not algebraic in cos and sin of the angle, so "
                         "no polynomial holds its equilibria: use the isolation route")
    return method


def entry(library: Library, method: str, batch: bool = False) -> Any:
    """The C entry point of a route ("polynomial" or "isolate"), or its batch form; with
    several coordinates NAME_analyze (their isolation)."""
    name = "analyze" if library.dof > 1 else {"polynomial": "analyze", "isolate": "isolate"}[method]
    return getattr(library.lib, f"{library.PREFIX}_{name}{'_batch' if batch else ''}")


def _from_result(params: ParameterSet, result: Any, method: str
                 ) -> Analysis | MultibodyAnalysis:
    """The analysis of one C result, by the number of coordinates."""
    if library_of_params(params).dof > 1:
        return _read_several(params, result)
    return _from_c(params, result, method)


def analyze(params: ParameterSet, method: Method = "auto") -> Analysis | MultibodyAnalysis:
    """Every equilibrium for ``params`` (a Library's Params, SI units), by the route
    ``method`` names ("auto", "polynomial" or "isolate"), classified and linearised; angles
    in radians. One coordinate: an ``Analysis``; several: a ``MultibodyAnalysis`` (one
    route, "isolate"; "auto" takes it, "polynomial" is refused).

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

    library.check(c_entry(library._c_params(params), result), params,
                  rerun=rerun if library.dof == 1 else None)
    return _from_result(params, result, taken)


def analyze_batch(table: np.ndarray, library: Library, method: Method = "auto"
                  ) -> tuple[list[Analysis | MultibodyAnalysis | None], np.ndarray]:
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
        _from_result(library.Params(**{n: float(table[n][i]) for n in library.PARAMETER_NAMES}),
                     results[i], taken)
        if statuses[i] == library.STATUS["OK"] else None for i in range(len(table))]
    return analyses, statuses
