"""The root finder's fast path (Ehrlich-Aberth iteration proven by inclusion discs, in
runtime/codegen_roots.c) against its reference, the isolation by derivatives
(codegen_poly_real_roots_reference_work), which it must agree with wherever it answers and
falls back to elsewhere: the same statuses and counts, and each root within the 4 eps at which
the finder merges values, on the runtime's own hard vectors (close pairs, double roots,
few-ulp coefficients) and on the sigma of every shipped mechanism over wide parameter ranges.
"""
from __future__ import annotations


import numpy as np
import pytest

from codegen.runtime import sweep
from codegen.api import load, shipped
from runtime_c.conftest import RUNTIME
from runtime_c.test_runtime_roots import (RUNTIME_CDEF, RUNTIME_SRC, SEED, _build,
                                          _degree12_vectors, known_case)

CDEF = RUNTIME_CDEF + """
codegen_roots_status codegen_poly_real_roots_work(const double *sigma, int degree,
                                                  double *theta, int *n_roots, double *work);
codegen_roots_status codegen_poly_real_roots_reference_work(const double *sigma, int degree,
                                                            double *theta, int *n_roots,
                                                            double *work);
"""
EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    d = tmp_path_factory.mktemp("fast_roots")
    return _build(d, "_fast_roots_test", CDEF, '#include "codegen_runtime.h"', [RUNTIME_SRC],
                  [RUNTIME])


def _roots(both, entry, sigma):
    ffi, lib = both
    degree = len(sigma) - 1
    theta, n = ffi.new("double[]", max(degree, 1)), ffi.new("int *", -1)
    work = ffi.new("double[]", 16 * degree + 16)        # CODEGEN_ROOTS_WORK(degree)
    status = getattr(lib, entry)(ffi.new("double[]", list(map(float, sigma))), degree, theta,
                                 n, work)
    return status, list(theta[0:max(n[0], 0)])


def assert_same(both, sigma):
    fast = _roots(both, "codegen_poly_real_roots_work", sigma)
    reference = _roots(both, "codegen_poly_real_roots_reference_work", sigma)
    assert fast[0] == reference[0], sigma
    assert len(fast[1]) == len(reference[1]), (sigma, fast, reference)
    for a, b in zip(fast[1], reference[1]):
        assert abs(a - b) <= 4 * EPS * max(1.0, abs(b)), (sigma, fast, reference)
    return len(fast[1])


def test_agrees_with_the_reference_on_hard_vectors(both):
    """Thousands of degree-12 vectors built to be hard (close pairs 5e-4 apart, double roots,
    vanishing or few-ulp end coefficients), and polynomials of prescribed roots up to degree 32."""
    found = sum(assert_same(both, v) for v in _degree12_vectors())
    assert found > 20000
    rng = np.random.default_rng([SEED, 77])
    for degree in range(1, 33):
        for _ in range(6):
            nreal = degree - 2 * int(rng.integers(0, degree // 2 + 1))
            sigma, _ = known_case(rng, degree, nreal, [])
            assert_same(both, sigma)


@pytest.mark.parametrize("name", [n for n in shipped() if load(n).has_polynomial])
def test_agrees_with_the_reference_on_every_mechanism(both, name):
    """Each shipped mechanism's sigma at 300 sets with every parameter within +-50 % of its
    example (where close pairs and near-double roots are common: the fast path must either
    find what the isolation finds or leave the polynomial to it)."""
    library = load(name)
    example = library.example_params()
    ranges = {k: sorted((0.5 * getattr(example, k), 1.5 * getattr(example, k) + 1e-9))
              for k in library.PARAMETER_NAMES}
    sigmas = library.sigma(sweep.sample(library, 300, ranges, seed=5))
    found = sum(assert_same(both, sigma) for sigma in sigmas if np.all(np.isfinite(sigma)))
    assert found > 300
