"""The analysis of a mechanism with n coordinates from Python: every equilibrium, proven, with
its modes, and the boxes the isolation could not decide.

``analyze(library, params)`` calls the library's C ``NAME_analyze`` (the runtime's
codegen_multibody.c) and returns a ``MultibodyAnalysis``: ``equilibria`` (each with its
coordinates, its proven box, the undamped natural frequencies and mass-normalised mode shapes,
the damped eigenvalues with their damping ratios, and the stability) and ``uncertain``
(boxes, never equilibria). Angles in radians, frequencies in rad/s.

Many sets at once run through ``codegen.runtime.batch`` (the C ``NAME_analyze_batch`` over
threads, its results read in place as numpy arrays): ``equilibria`` reads a block of them,
``table_rows`` makes ``analyze_table``'s rows of it and ``sweep_roots`` a sweep's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from .. import ccodes
from . import analysis

#: codegen_multibody.h's stability codes (their values read from it) -> words
STABILITY = ccodes.named({"MB_STABLE": "stable", "MB_UNSTABLE": "unstable",
                          "MB_UNDECIDED": "undecided"})
#: codegen_boxes.h's and codegen_multibody.h's kinds of an undecided box -> words
UNCERTAIN_KINDS = ccodes.named({"BOX_CLUSTER": "cluster", "BOX_SINGULAR": "singular",
                                "MB_AT_RANGE_END": "at the end of a range"})


@dataclass(frozen=True)
class MultibodyEquilibrium:
    theta: np.ndarray          # the independent coordinates [rad or m]
    lo: np.ndarray             # the box proven to hold exactly this one equilibrium
    hi: np.ndarray
    omega_squared: np.ndarray  # K phi = omega^2 M phi, ascending [rad^2/s^2]
    shapes: np.ndarray         # n x n, column j: mode j, phi^T M phi = 1
    eigenvalues: np.ndarray    # the 2n roots s of det(M s^2 + B s + K) [1/s], complex
    damping_ratios: np.ndarray  # -Re s / |s| of each eigenvalue
    modal_damping: np.ndarray  # phi_j^T B phi_j / (2 omega_j): mode j's damping ratio
    stability: str             # "stable", "unstable" or "undecided"

    @property
    def stable(self) -> bool:
        return self.stability == "stable"

    @property
    def frequencies(self) -> np.ndarray:
        """The undamped natural frequencies [rad/s] (NaN where omega^2 < 0)."""
        with np.errstate(invalid="ignore"):
            return np.sqrt(self.omega_squared)



@dataclass(frozen=True)
class UncertainBox:
    lo: np.ndarray
    hi: np.ndarray
    kind: str   # "cluster", "singular" or "at the end of a range"


@dataclass(frozen=True)
class MultibodyAnalysis:
    coordinates: tuple[str, ...]
    equilibria: tuple[MultibodyEquilibrium, ...]
    uncertain: tuple[UncertainBox, ...]

    def as_dict(self) -> dict[str, Any]:
        """Plain JSON types: lists and floats (NaN as None)."""
        def plain(x):
            return [plain(v) for v in x] if isinstance(x, (list, np.ndarray)) else (
                None if isinstance(x, float) and math.isnan(x) else float(x))

        return {
            "coordinates": list(self.coordinates),
            "equilibria": [{
                "theta": plain(e.theta), "box": [plain(e.lo), plain(e.hi)],
                "stability": e.stability, "omega_squared": plain(e.omega_squared),
                "natural_frequencies": plain(e.frequencies),
                "mode_shapes": plain(e.shapes),
                "eigenvalues": [[plain(s.real), plain(s.imag)] for s in e.eigenvalues],
                "damping_ratios": plain(e.damping_ratios),
                "modal_damping": plain(e.modal_damping)} for e in self.equilibria],
            "uncertain": [{"box": [plain(u.lo), plain(u.hi)], "kind": u.kind}
                          for u in self.uncertain],
        }


def analyze(library: Any, params: Any) -> MultibodyAnalysis:
    """Every equilibrium of ``params`` in the box of the coordinates' ranges, ordered by
    their coordinates, with its modes; raises LibraryError where the C analysis fails."""
    n = library.SPEC["dof"]
    result = library.ffi.new(f"{library.PREFIX}_analysis *")
    status = getattr(library.lib, f"{library.PREFIX}_analyze")(library._c_params(params), result)
    library.check(status, params)
    return _read(library, result, n)


def _array(ffi: Any, field: Any, count: int) -> np.ndarray:
    return np.frombuffer(ffi.buffer(field), dtype=np.float64)[:count].copy()


def _read(library: Any, result: Any, n: int) -> MultibodyAnalysis:
    ffi = library.ffi
    count, uncertain = result.n_equilibria, result.n_uncertain

    def rows(field, width):
        return _array(ffi, field, count * width).reshape(count, width)

    theta, lo, hi = rows(result.theta, n), rows(result.lo, n), rows(result.hi, n)
    omega_squared, shapes = rows(result.omega_squared, n), rows(result.shapes, n * n)
    s = rows(result.s_re, 2 * n) + 1j * rows(result.s_im, 2 * n)
    zeta, modal = rows(result.damping_ratio, 2 * n), rows(result.modal_damping, n)
    equilibria = [MultibodyEquilibrium(theta[r], lo[r], hi[r], omega_squared[r],
                                       shapes[r].reshape(n, n), s[r], zeta[r], modal[r],
                                       STABILITY[result.stability[r]]) for r in range(count)]
    equilibria.sort(key=lambda e: tuple(e.theta))
    u_lo = _array(ffi, result.uncertain_lo, uncertain * n).reshape(uncertain, n)
    u_hi = _array(ffi, result.uncertain_hi, uncertain * n).reshape(uncertain, n)
    boxes = [UncertainBox(u_lo[u], u_hi[u], UNCERTAIN_KINDS[result.uncertain_kind[u]])
             for u in range(uncertain)]
    names = tuple(c["name"] for c in library.SPEC["coordinates"])
    return MultibodyAnalysis(names, tuple(equilibria), tuple(boxes))


def receptance(library: Any, params: Any, theta: Any, omega: Any) -> np.ndarray:
    """H(omega) = (K - omega^2 M + i omega B)^-1 at theta, for each omega [rad/s]:
    complex, shape (len(omega), n, n)."""
    n = library.SPEC["dof"]
    c_params = library._c_params(params)
    point = library.ffi.new("double[]", [float(x) for x in theta])
    H_re, H_im = library.ffi.new("double[]", n * n), library.ffi.new("double[]", n * n)
    call = getattr(library.lib, f"{library.PREFIX}_receptance")
    omegas = np.atleast_1d(np.asarray(omega, dtype=float))
    out = np.empty((len(omegas), n, n), dtype=complex)
    for i, w in enumerate(omegas):
        library.check(call(c_params, point, float(w), H_re, H_im), params,
                      inputs={"theta": list(theta), "omega": float(w)})
        out[i] = (np.array(library.ffi.unpack(H_re, n * n))
                  + 1j * np.array(library.ffi.unpack(H_im, n * n))).reshape(n, n)
    return out


# ------------------------------------------------------------------- many sets at once

def route(library: Any, method: str = "auto") -> str:
    """The route a method name takes with several coordinates: "isolate", the proven
    isolation in boxes ("auto" too). ValueError for an unknown method or "polynomial", which
    several coordinates do not have."""
    if method not in analysis.METHODS:
        raise ValueError(f"method must be one of {', '.join(analysis.METHODS)}, not {method!r}")
    if method == "polynomial":
        raise ValueError(f"{library.PREFIX}: with several coordinates there is no polynomial "
                         "route; its equilibria are isolated in boxes (method isolate or auto)")
    return "isolate"


def batch_entry(library: Any, method: str) -> Any:
    """NAME_analyze_batch, the C analysis of many sets (its one route)."""
    return getattr(library.lib, f"{library.PREFIX}_analyze_batch")


#: The codes of the C stability (STABILITY: codegen_multibody.h's, read from it) as
#: analysis.STABILITY's (stable, marginal, unstable): an undecided equilibrium is marginal.
#: Indexed by the C code less the least of them (_LEAST_STABILITY).
_LEAST_STABILITY = min(STABILITY)
_STABILITY_CODES = np.array(
    [analysis.STABILITY.index({"undecided": "marginal"}.get(STABILITY[code], STABILITY[code]))
     for code in range(_LEAST_STABILITY, max(STABILITY) + 1)], dtype=np.int8)


def equilibria(library: Any, c: np.ndarray, statuses: np.ndarray
               ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray]:
    """The equilibria of a block of C results (NAME_analysis structs as numpy records, as
    codegen.runtime.batch reads them in place), in set order, then ordered by their
    coordinates as ``analyze`` orders them: (their columns: theta, theta_lo, theta_hi,
    omega_squared, omega_n (NaN where omega^2 < 0), shapes (n x n each), eigenvalues
    (complex), damping_ratios, zeta (each mode's modal damping) and stability
    (analysis.STABILITY codes); the index of each one's set in the block; each set's count
    of equilibria; each set's count of boxes not decided). A failed set has none of either."""
    n, count = library.dof, len(c)
    ok = statuses == library.STATUS["OK"]
    counts = np.where(ok, c["n_equilibria"], 0)
    uncertain = np.where(ok, c["n_uncertain"], 0)
    slots = c["stability"].shape[1]
    mask = np.arange(slots) < counts[:, None]
    sets = np.nonzero(mask)[0]

    def field(name: str, *shape: int) -> np.ndarray:
        return c[name].reshape(count, slots, *shape)[mask]

    theta = field("theta", n)
    order = np.lexsort([theta[:, k] for k in reversed(range(n))] + [sets])
    omega_squared = field("omega_squared", n)[order]
    with np.errstate(invalid="ignore"):
        omega_n = np.sqrt(omega_squared)
    columns = {
        "theta": theta[order], "theta_lo": field("lo", n)[order],
        "theta_hi": field("hi", n)[order], "omega_squared": omega_squared, "omega_n": omega_n,
        "shapes": field("shapes", n, n)[order],
        "eigenvalues": (field("s_re", 2 * n) + 1j * field("s_im", 2 * n))[order],
        "damping_ratios": field("damping_ratio", 2 * n)[order],
        "zeta": field("modal_damping", n)[order],
        "stability": _STABILITY_CODES[field("stability") - _LEAST_STABILITY][order]}
    return columns, sets[order], counts, uncertain


@lru_cache(maxsize=None)
def roots_dtype(library: Any) -> np.dtype:
    """A row of ``codegen.runtime.batch.analyze_table`` with n coordinates: one proven
    equilibrium, its set's index, its coordinates and their proven box, each mode's omega^2,
    undamped natural frequency (NaN where omega^2 < 0), modal damping ratio (zeta) and
    mass-normalised shape (column j: mode j), the 2n damped eigenvalues with their damping
    ratios, and the stability (analysis.STABILITY's code; undecided: marginal). ``certified``
    and ``kind`` (equilibrium) are those of every row, as a one-coordinate table's
    equilibria have them."""
    n = library.dof
    return np.dtype([
        ("set", np.int64), ("theta", np.float64, (n,)), ("theta_lo", np.float64, (n,)),
        ("theta_hi", np.float64, (n,)), ("certified", np.bool_), ("kind", np.int8),
        ("omega_squared", np.float64, (n,)), ("omega_n", np.float64, (n,)),
        ("zeta", np.float64, (n,)), ("shapes", np.float64, (n, n)),
        ("eigenvalues", np.complex128, (2 * n,)), ("damping_ratios", np.float64, (2 * n,)),
        ("stability", np.int8)])


def table_rows(library: Any, c: np.ndarray, statuses: np.ndarray, first: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ``roots_dtype`` rows of a block of C results (sets first, first + 1, ...), the
    number of rows of each set and the number of its boxes not decided."""
    columns, sets, counts, uncertain = equilibria(library, c, statuses)
    rows = np.empty(len(sets), dtype=roots_dtype(library))
    rows["set"] = sets + first
    rows["certified"] = True
    rows["kind"] = analysis.KINDS.index("equilibrium")
    for name, values in columns.items():
        rows[name] = values
    return rows, counts, uncertain


def sweep_fields(library: Any) -> list[tuple[str, Any]]:
    """A sweep row's columns after the parameters': the status, each coordinate, the
    stability, each mode's natural frequency and damping ratio, and how many boxes of the
    set could not be decided (never rows of their own)."""
    names = [c["name"] for c in library.SPEC["coordinates"]]
    modes = range(1, library.dof + 1)
    return ([("status", np.int32)] + [(n, np.float64) for n in names]
            + [("stability", np.int8)]
            + [(f"{q}_{j}", np.float64) for j in modes for q in ("omega_n", "zeta")]
            + [("uncertain", np.int32)])


def sweep_roots(library: Any, c: np.ndarray, statuses: np.ndarray, every_root: bool
                ) -> tuple[dict[str, np.ndarray], np.ndarray, dict[str, np.ndarray]]:
    """What a block of C results puts in a sweep's rows (``sweep_fields``): the columns of
    each set (status, uncertain), the index of each equilibrium's set, and the columns of
    each equilibrium. Every root is a proven equilibrium: ``every_root`` changes nothing."""
    columns, sets, _, uncertain = equilibria(library, c, statuses)
    found = {coordinate["name"]: columns["theta"][:, k]
             for k, coordinate in enumerate(library.SPEC["coordinates"])}
    found["stability"] = columns["stability"]
    for j in range(library.dof):
        found[f"omega_n_{j + 1}"] = columns["omega_n"][:, j]
        found[f"zeta_{j + 1}"] = columns["zeta"][:, j]
    return {"status": statuses, "uncertain": uncertain}, sets, found
