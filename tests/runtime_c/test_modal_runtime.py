"""The runtime's modal linear algebra (runtime/codegen_modal.c), on its own, against
LAPACK through numpy and scipy (issue 31): the undamped modes of K phi = omega^2 M phi, the
eigenvalues of M s^2 + B s + K and the receptance (K - omega^2 M + i omega B)^-1, on thousands
of random matrices, matrices with repeated eigenvalues, defective ones (critically damped
modes: a double eigenvalue with one eigenvector) and badly scaled ones (rows and columns
scaled over 12 decades), in double and in float.

Self-contained: drivers/modal_driver.c is compiled here against the runtime with the
project's strict flags; numbers cross as hex floats, so nothing is rounded between C and
Python.
"""
from __future__ import annotations

import os

import numpy as np
import pytest
import scipy.linalg

OK, BAD_INPUT, NOT_DEFINITE, NO_CONVERGENCE, SINGULAR = range(5)
COUNT = 1000   # random matrices per kind


def h(x: float) -> str:
    return float(x).hex()


def words(a) -> str:
    return " ".join(h(x) for x in np.ravel(a))


class Modal:
    """tests/support/c/modal_driver.c: batches of commands as methods, the answers parsed."""

    def __init__(self, program):
        self.program = program

    def modes(self, cases):
        out = self.program([f"modes {len(M)} {words(M)} {words(K)}" for M, K in cases])
        result = []
        for (M, _), answer in zip(cases, out):
            n = len(M)
            values = [float.fromhex(w) for w in answer[1:]]
            result.append((int(answer[0]), np.array(values[:n]),
                           np.array(values[n:]).reshape(n, n)))
        return result

    def eigenvalues(self, cases):
        out = self.program([f"eigenvalues {len(M)} {words(M)} {words(B)} {words(K)}"
                            for M, B, K in cases])
        result = []
        for (M, _, _), answer in zip(cases, out):
            n = len(M)
            values = [float.fromhex(w) for w in answer[1:]]
            result.append((int(answer[0]), np.array(values[:2 * n]) + 1j * np.array(values[2 * n:])))
        return result

    def receptance(self, cases):
        out = self.program([f"receptance {len(M)} {h(omega)} {words(M)} {words(B)} {words(K)}"
                            for M, B, K, omega in cases])
        result = []
        for (M, _, _, _), answer in zip(cases, out):
            n = len(M)
            values = np.array([float.fromhex(w) for w in answer[1:]])
            result.append((int(answer[0]),
                           (values[:n * n] + 1j * values[n * n:]).reshape(n, n)))
        return result


def _build(runtime_driver, tmp_path_factory, name, defines=(), flags=None, env=None):
    exe = tmp_path_factory.mktemp(name) / name
    runtime_driver.build(exe, "modal_driver.c", "codegen_modal.c", flags=flags, defines=defines)
    return Modal(runtime_driver.program(exe, env))


@pytest.fixture(scope="module")
def modal(runtime_driver, tmp_path_factory):
    return _build(runtime_driver, tmp_path_factory, "modal_driver")


@pytest.fixture(scope="module")
def modal_float(runtime_driver, tmp_path_factory):
    return _build(runtime_driver, tmp_path_factory, "modal_driver_float", ("-DCODEGEN_FLOAT",))


# --------------------------------------------------------------------------- matrices


def spd(rng, n, condition=1e3):
    """A random symmetric positive definite matrix of about the given condition number."""
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    return q @ np.diag(np.geomspace(1.0, condition, n) * rng.uniform(0.5, 2.0)) @ q.T


def symmetric(rng, n):
    a = rng.standard_normal((n, n)) * 10 ** rng.uniform(-2, 2)
    return (a + a.T) / 2


def scaled(rng, n, decades=12):
    """Rows and columns scaled by S = diag(10^u), u over ``decades``: (S A S) has the same
    generalised eigenvalues as A with S B S."""
    return np.diag(10 ** rng.uniform(-decades / 2, decades / 2, n))


def sizes(rng):
    return int(rng.integers(1, 7))


# --------------------------------------------------------------------------- modes


def check_modes(got, cases, rtol):
    for (status, w, phi), (M, K) in zip(got, cases):
        assert status == OK, (M, K)
        expected = scipy.linalg.eigh(K, M, eigvals_only=True)
        scale = max(np.max(np.abs(expected)), np.finfo(float).tiny)
        assert np.all(np.abs(w - expected) <= rtol * scale), (w, expected)
        n = len(M)
        # mass-normalised, and each column a mode (independent of how a repeated
        # eigenvalue's vectors are chosen)
        assert np.allclose(phi.T @ M @ phi, np.eye(n), atol=rtol * 10)
        residual = K @ phi - M @ phi @ np.diag(w)
        assert np.all(np.abs(residual) <= rtol * 10 * scale * np.abs(M @ phi).max() + 1e-300)
        largest = np.abs(phi).argmax(axis=0)
        assert np.all(phi[largest, range(n)] > 0)   # the sign convention


def test_modes_of_random_matrices_equal_lapack(modal):
    rng = np.random.default_rng(1)
    cases = [(spd(rng, n), symmetric(rng, n)) for n in (sizes(rng) for _ in range(COUNT))]
    check_modes(modal.modes(cases), cases, 1e-11)


def test_modes_with_repeated_eigenvalues(modal):
    """K = L Q D Q^T L^T with M = L L^T and D repeating values: every multiple eigenvalue found
    and its modes M-orthonormal."""
    rng = np.random.default_rng(2)
    cases = []
    for _ in range(COUNT // 4):
        n = int(rng.integers(2, 7))
        M = spd(rng, n)
        L = np.linalg.cholesky(M)
        q, _ = np.linalg.qr(rng.standard_normal((n, n)))
        d = rng.choice([1.0, 4.0, -2.0], size=n)
        cases.append((M, L @ q @ np.diag(d) @ q.T @ L.T))
    cases.append((np.eye(4), 3 * np.eye(4)))   # one eigenvalue four times, diagonal already
    check_modes(modal.modes(cases), cases, 1e-11)


def test_modes_of_badly_scaled_matrices(modal):
    """(S M S, S K S) over 12 decades of scaling: the same eigenvalues as (M, K)."""
    rng = np.random.default_rng(3)
    cases, unscaled = [], []
    for _ in range(COUNT // 4):
        n = sizes(rng)
        M, K, S = spd(rng, n, 1e2), symmetric(rng, n), scaled(rng, n)
        cases.append((S @ M @ S, S @ K @ S))
        unscaled.append((M, K))
    for (status, w, _), (M, K) in zip(modal.modes(cases), unscaled):
        assert status == OK
        expected = scipy.linalg.eigh(K, M, eigvals_only=True)
        assert np.all(np.abs(w - expected) <= 1e-9 * np.max(np.abs(expected)))


def test_modes_refuse_a_mass_matrix_not_positive_definite(modal):
    M = np.array([[1.0, 2.0], [2.0, 1.0]])   # eigenvalues 3 and -1
    ((status, _, _),) = modal.modes([(M, np.eye(2))])
    assert status == NOT_DEFINITE


# --------------------------------------------------------------------------- damped eigenvalues


def state_eigenvalues(M, B, K):
    """The reference: numpy's (LAPACK dgeev) eigenvalues of the state matrix, built here."""
    n = len(M)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ B]])
    return np.linalg.eigvals(A)


def matched(got, expected, tol):
    """Whether got and expected are the same multiset of complex numbers within tol."""
    left = list(expected)
    for z in got:
        distances = [abs(z - e) for e in left]
        i = int(np.argmin(distances))
        if distances[i] > tol:
            return False
        left.pop(i)
    return True


def check_eigenvalues(got, references, rtol):
    for (status, s), expected in zip(got, references):
        assert status == OK, expected
        scale = np.max(np.abs(expected))
        assert matched(s, expected, rtol * scale), (s, expected)
        modulus = np.abs(s)
        assert np.all(np.diff(modulus) >= -rtol * scale)   # ascending |s|


def test_damped_eigenvalues_of_random_matrices_equal_lapack(modal):
    rng = np.random.default_rng(4)
    cases = []
    for _ in range(COUNT):
        n = sizes(rng)
        b = rng.standard_normal((n, n))
        cases.append((spd(rng, n), b @ b.T * 10 ** rng.uniform(-3, 1), symmetric(rng, n)))
    check_eigenvalues(modal.eigenvalues(cases), [state_eigenvalues(*c) for c in cases], 1e-9)


def test_damped_eigenvalues_repeated_and_defective(modal):
    """Undamped repeated modes (M = K = I: +-i, n times each) and critically damped ones
    (B = 2 sqrt(K M) per mode: a double real eigenvalue with one eigenvector, found to the
    square root of the rounding, as LAPACK finds it)."""
    rng = np.random.default_rng(5)
    cases = [(np.eye(n), np.zeros((n, n)), np.eye(n)) for n in range(1, 7)]
    for _ in range(COUNT // 4):
        n = sizes(rng)
        omega = rng.uniform(0.5, 50.0, n)
        q, _ = np.linalg.qr(rng.standard_normal((n, n)))
        cases.append((np.eye(n), q @ np.diag(2 * omega) @ q.T, q @ np.diag(omega ** 2) @ q.T))
    exact = [np.repeat(-np.asarray(np.linalg.eigvalsh(K)) ** 0.5, 2) if B.any()
             else np.concatenate([1j * np.ones(len(M)), -1j * np.ones(len(M))])
             for M, B, K in cases]
    check_eigenvalues(modal.eigenvalues(cases), exact, 1e-6)


def test_damped_eigenvalues_of_badly_scaled_matrices(modal):
    rng = np.random.default_rng(6)
    cases, unscaled = [], []
    for _ in range(COUNT // 4):
        n = sizes(rng)
        b = rng.standard_normal((n, n))
        M, B, K, S = spd(rng, n, 1e2), b @ b.T * 0.1, symmetric(rng, n), scaled(rng, n)
        cases.append((S @ M @ S, S @ B @ S, S @ K @ S))
        unscaled.append((M, B, K))
    check_eigenvalues(modal.eigenvalues(cases), [state_eigenvalues(*c) for c in unscaled], 1e-8)


# --------------------------------------------------------------------------- receptance


def test_receptance_of_random_matrices_equals_the_inverse(modal):
    rng = np.random.default_rng(7)
    cases = []
    for _ in range(COUNT):
        n = sizes(rng)
        b = rng.standard_normal((n, n))
        cases.append((spd(rng, n), b @ b.T * 0.1, spd(rng, n) * 100, rng.uniform(0, 30)))
    for (status, H), (M, B, K, omega) in zip(modal.receptance(cases), cases):
        assert status == OK
        D = K - omega ** 2 * M + 1j * omega * B
        expected = np.linalg.inv(D)
        bound = 1e-12 * np.linalg.cond(D) * np.abs(expected).max()
        assert np.abs(H - expected).max() <= bound, (H, expected)


def test_receptance_at_an_undamped_resonance_is_singular(modal):
    M, B, K = np.eye(2), np.zeros((2, 2)), np.diag([4.0, 9.0])
    ((status, _),) = modal.receptance([(M, B, K, 2.0)])
    assert status == SINGULAR
    ((status, H),) = modal.receptance([(M, B, K, 1.0)])
    assert status == OK and np.allclose(H, np.diag([1 / 3, 1 / 8]))


def test_misuse_is_refused_with_a_status(modal):
    assert modal.program(["misuse"])[0] == [str(BAD_INPUT)] * 6


# --------------------------------------------------------------------------- float


def test_float_build_agrees_to_float_precision(modal_float):
    """The same functions compiled with -DCODEGEN_FLOAT (as on the Cortex-M4F), on inputs
    exact in float, within a few hundred units of float's rounding of LAPACK in double."""
    rng = np.random.default_rng(8)
    as_float = lambda a: np.asarray(a, dtype=np.float32).astype(float)   # noqa: E731
    modes = [(as_float(spd(rng, n, 1e2)), as_float(symmetric(rng, n)))
             for n in (sizes(rng) for _ in range(200))]
    check_modes(modal_float.modes(modes), modes, 3e-5)
    damped = []
    for _ in range(200):
        n = sizes(rng)
        b = rng.standard_normal((n, n))
        damped.append(tuple(as_float(x) for x in (spd(rng, n, 1e2), b @ b.T * 0.1,
                                                  symmetric(rng, n))))
    check_eigenvalues(modal_float.eigenvalues(damped), [state_eigenvalues(*c) for c in damped],
                      1e-4)


# --------------------------------------------------------------------------- sanitizers


def test_sanitized_driver_gives_the_same_answers(modal, sanitizer, runtime_driver,
                                                 tmp_path_factory):
    """Every function under AddressSanitizer + UBSan, each work array exactly its
    CODEGEN_*_WORK(n) values on the heap: clean, and the same answers bit for bit."""
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0", UBSAN_OPTIONS="print_stacktrace=1")
    sanitized = _build(runtime_driver, tmp_path_factory, "modal_driver_san",
                       flags=[*sanitizer.flags, *runtime_driver.warnings], env=env)
    rng = np.random.default_rng(9)
    lines = ["misuse"]
    for n in range(1, 9):
        b = rng.standard_normal((n, n))
        M, B, K = spd(rng, n), b @ b.T, symmetric(rng, n)
        lines += [f"modes {n} {words(M)} {words(K)}",
                  f"eigenvalues {n} {words(M)} {words(B)} {words(K)}",
                  f"receptance {n} {h(1.5)} {words(M)} {words(B)} {words(K)}"]
    assert sanitized.program.raw(lines) == modal.program.raw(lines)
