"""The analysis of a mechanism with n coordinates from Python: every equilibrium, proven, with
its modes, and the boxes the isolation could not decide.

``analyze(library, params)`` calls the library's C ``NAME_analyze`` (the runtime's
codegen_multibody.c) and returns a ``MultibodyAnalysis``: ``equilibria`` (each with its
coordinates, its proven box, the undamped natural frequencies and mass-normalised mode shapes,
the damped eigenvalues with their damping ratios, and the stability) and ``uncertain``
(boxes, never equilibria). Angles in radians, frequencies in rad/s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

#: codegen_multibody.h's stability codes
STABILITY = {1: "stable", 0: "unstable", -1: "undecided"}
#: codegen_boxes.h's and codegen_multibody.h's kinds of an undecided box
UNCERTAIN_KINDS = {1: "cluster", 2: "singular", 3: "at the end of a range"}


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


# --------------------------------------------------------------------------- sweeps

#: Sets analysed per C call of NAME_analyze_batch (its results buffer is reused).
BLOCK = 256
#: The stability codes of a sweep row, as the 1-coordinate sweep's (analysis.STABILITY:
#: stable, marginal, unstable); an undecided one is marginal.
SWEEP_STABILITY = {"stable": 0, "undecided": 1, "unstable": 2}


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


def sweep_rows(library: Any, table: np.ndarray, offset: int, dtype: np.dtype,
               columns: tuple[str, ...]) -> np.ndarray:
    """One row per equilibrium of each set (a set without one, or failed: one row of NaN),
    sets in order, equilibria by their coordinates."""
    ffi, P, n = library.ffi, library.PREFIX, library.dof
    found_names = {c["name"] for c in library.SPEC["coordinates"]}
    table = np.ascontiguousarray(table)
    statuses = np.zeros(len(table), dtype=np.intc)
    results = ffi.new(f"{P}_analysis[]", max(1, min(BLOCK, len(table))))
    c_params = ffi.from_buffer(f"{P}_params[]", table)
    c_statuses = ffi.from_buffer(f"{P}_status[]", statuses, require_writable=True)
    pieces = []
    for first in range(0, len(table), BLOCK):
        count = min(BLOCK, len(table) - first)
        getattr(library.lib, f"{P}_analyze_batch")(count, c_params + first, results,
                                                    c_statuses + first)
        for i in range(count):
            s = first + i
            found = (_read(library, results[i], n) if statuses[s] == 0
                     else MultibodyAnalysis((), (), ()))
            rows = np.zeros(max(1, len(found.equilibria)), dtype=dtype)
            rows["set"] = s + offset
            for name, column in zip(library.PARAMETER_NAMES, columns):
                rows[column] = table[name][s]
            rows["status"] = statuses[s]
            rows["uncertain"] = len(found.uncertain)
            for field in dtype.names:
                if field in found_names or field.startswith(("omega_n_", "zeta_")):
                    rows[field] = np.nan
            rows["stability"] = -1
            for r, e in enumerate(found.equilibria):
                for name, value in zip(found.coordinates, e.theta):
                    rows[name][r] = value
                rows["stability"][r] = SWEEP_STABILITY[e.stability]
                for j in range(n):
                    rows[f"omega_n_{j + 1}"][r] = e.frequencies[j]
                    rows[f"zeta_{j + 1}"][r] = e.modal_damping[j]
            pieces.append(rows)
    return np.concatenate(pieces) if pieces else np.zeros(0, dtype=dtype)
