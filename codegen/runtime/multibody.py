"""A mechanism with n coordinates from Python: its receptance, and its analyses of many sets
at once.

One set's analysis is ``codegen.runtime.analysis.analyze(params)``, the same for any number
of coordinates (``library.analyze(params)``): with several it returns a ``MultibodyAnalysis``
(defined there, with ``MultibodyEquilibrium`` and ``UncertainBox``, and named here too).
``analyze(library, params)`` here is a thin alias of it, kept for older callers.

Many sets at once run through ``codegen.runtime.batch`` (the C ``NAME_analyze_batch`` over
threads, its results read in place as numpy arrays): ``equilibria`` reads a block of them,
``table_rows`` makes ``analyze_table``'s rows of it and ``sweep_roots`` a sweep's.
"""
from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from . import analysis
from .analysis import MultibodyAnalysis, MultibodyEquilibrium, UncertainBox

__all__ = ["MultibodyAnalysis", "MultibodyEquilibrium", "UncertainBox", "analyze",
           "receptance", "equilibria", "roots_dtype", "table_rows", "sweep_fields",
           "sweep_roots"]


def analyze(library: Any, params: Any) -> MultibodyAnalysis | analysis.Analysis:
    """A thin alias of ``codegen.runtime.analysis.analyze(params)`` (``params`` a Params or a
    mapping of every parameter, None the example), kept for older callers: with several
    coordinates every equilibrium in the box of their ranges, ordered by their coordinates,
    with its modes; raises LibraryError where the C analysis fails."""
    return analysis.analyze(library._params(params))


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

#: The codes of the C stability (codegen_multibody.h's, read from it) as analysis.STABILITY's
#: (stable, unstable, undecided), indexed by the C code less the least of them.
_LEAST_STABILITY = min(analysis.MULTIBODY_STABILITY)
_STABILITY_CODES = np.array(
    [analysis.STABILITY.index(analysis.MULTIBODY_STABILITY[code])
     for code in range(_LEAST_STABILITY, max(analysis.MULTIBODY_STABILITY) + 1)], dtype=np.int8)


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
    ratios, and the stability (analysis.STABILITY's code). ``certified``
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
