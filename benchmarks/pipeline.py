"""The numpy pipeline `make bench` sets against the library: what a competent numpy user
writes in an afternoon from the SymPy derivation, vectorised over parameter sets.

sigma_i lambdified (numpy), one companion matrix per set and ``numpy.linalg.eigvals`` over
all of them at once, the roots with a small imaginary part kept, tau -> theta = 2 atan(tau),
G lambdified at every kept root to tell genuine from extraneous, and M, B, K, omega_n and
zeta lambdified at the kept roots. No polishing, no branch bookkeeping, no certificates.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from symbolic import Symbolic, numpy_function

#: A root is real when |imag| <= REAL * |root| (numpy.roots is compared by the same rule).
REAL = 1e-8
#: A real root is an equilibrium when |G| <= GENUINE * (the sum of |contributions to G|).
#: Set in numpy's favour, between the largest |G| / scale of the genuine roots and the
#: smallest of the others over 200 sets of each mechanism (from the library's labels): with
#: sigma in double and unpolished roots, genuine roots reach 1e-9 (doughty), 2e-4
#: (slider_crank) and 2e-3 (four_bar), extraneous ones come down to 9e-2, 8e-4 and 2e-4:
#: for the four-bar no threshold separates them.
GENUINE = 4e-4


@dataclass(frozen=True)
class Pipeline:
    """The lambdified functions of one mechanism."""

    sigma: Callable[..., list[np.ndarray]]     # (*params) -> sigma_0..sigma_n
    at_roots: Callable[..., list[np.ndarray]]  # (theta, *params) -> G, scale, M, B, K


@dataclass(frozen=True)
class NumpyRoots:
    """Every real root of every set, as flat arrays (``set`` indexes the table)."""

    set: np.ndarray
    theta: np.ndarray
    genuine: np.ndarray
    M: np.ndarray
    B: np.ndarray
    K: np.ndarray
    omega_n: np.ndarray  # complex where K/M < 0
    zeta: np.ndarray


def build(symbols: Symbolic) -> Pipeline | None:
    """The pipeline of a mechanism; None where G is transcendental (no polynomial)."""
    if symbols.sigma is None:
        return None
    definitions, coefficients = symbols.sigma
    return Pipeline(
        sigma=numpy_function(symbols.parameters, coefficients, definitions),
        at_roots=numpy_function((symbols.theta, *symbols.parameters),
                                (symbols.residual, symbols.scale, symbols.mass,
                                 symbols.damping, symbols.stiffness)))


def columns(table: np.ndarray, names: Sequence[str]) -> list[np.ndarray]:
    """The parameter columns of a params_array, in the order the pipeline takes them."""
    return [np.ascontiguousarray(table[n]) for n in names]


def analyze(pipeline: Pipeline, params: Sequence[np.ndarray]) -> NumpyRoots:
    """The whole analysis of every set at once."""
    sigma = np.stack(pipeline.sigma(*params), axis=1)
    tau, index = real_roots(sigma)
    theta = 2.0 * np.arctan(tau)
    G, scale, M, B, K = pipeline.at_roots(theta, *(p[index] for p in params))
    with np.errstate(invalid="ignore", divide="ignore"):
        genuine = np.abs(G) <= GENUINE * scale  # NaN (not assembled) is never genuine
        omega_n = np.sqrt((K / M).astype(complex))
        zeta = B / (2.0 * M * omega_n)
    return NumpyRoots(index, theta, genuine, M, B, K, omega_n, zeta)


def companion_roots(sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All roots of every row's sum sigma_i tau^i (rows: sets), by the eigenvalues of the
    batched companion matrices; and a mask of the rows that could be solved (a row whose
    leading coefficient is zero or which is not finite is left out)."""
    highest_first = sigma[:, ::-1]
    # a leading coefficient zero in every set is structural: the degree is lower
    while highest_first.shape[1] > 1 and not highest_first[:, 0].any():
        highest_first = highest_first[:, 1:]
    with np.errstate(invalid="ignore", divide="ignore"):
        monic = highest_first[:, 1:] / highest_first[:, :1]
    ok = np.isfinite(monic).all(axis=1)
    count, degree = monic.shape
    companion = np.zeros((count, degree, degree))
    companion[:, 0, :] = -np.where(ok[:, None], monic, 0.0)
    companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
    return np.linalg.eigvals(companion), ok


def real_roots(sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(tau of every real root, the row it belongs to), over all rows."""
    roots, ok = companion_roots(sigma)
    real = is_real(roots) & ok[:, None]
    return roots.real[real], np.nonzero(real)[0]


def is_real(roots: np.ndarray) -> np.ndarray:
    return np.abs(roots.imag) <= REAL * np.abs(roots)


def numpy_roots_counts(sigma: np.ndarray) -> np.ndarray:
    """The number of real roots ``numpy.roots`` finds for each row (one call per row)."""
    return np.array([int(is_real(np.roots(row[::-1])).sum()) for row in sigma])
