/*
 * codegen_modal.h -- the small dense linear algebra of vibration about an equilibrium of a
 * mechanism with n coordinates, where M (mass), B (damping) and K (stiffness) are n x n:
 *
 *   codegen_modes             K phi = omega^2 M phi: the undamped natural frequencies squared
 *                             (ascending) and the mass-normalised mode shapes (phi^T M phi = 1),
 *                             by Cholesky M = L L^T and cyclic Jacobi rotations on
 *                             L^-1 K L^-T (symmetric-definite; every eigenvalue real);
 *   codegen_damped_eigenvalues the 2n roots s of det(M s^2 + B s + K) = 0: the eigenvalues of
 *                             the state matrix [[0, I], [-M^-1 K, -M^-1 B]], balanced, reduced
 *                             to Hessenberg form by Householder reflections and found by
 *                             Francis' double-shift QR iteration (general real);
 *   codegen_receptance        H(omega) = (K - omega^2 M + i omega B)^-1, the complex response
 *                             of the coordinates to unit harmonic generalised forces.
 *
 * Hand-written (not generated), written once for every library. Plain C99 + libm; no
 * allocation, no static state, no I/O: the caller passes every array, including the work
 * array each function needs (CODEGEN_*_WORK(n) values of codegen_real). Matrices are n x n,
 * row-major (entry (i, j) at [i * n + j]); M, B and K are read as symmetric, each pair
 * (i, j), (j, i) taken as their mean.
 */
#ifndef CODEGEN_MODAL_H
#define CODEGEN_MODAL_H

#include "codegen_real.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum codegen_modal_status {
    CODEGEN_MODAL_OK = 0,
    CODEGEN_MODAL_BAD_INPUT = 1,      /* a NULL pointer, n < 1, or a value not finite */
    CODEGEN_MODAL_NOT_DEFINITE = 2,   /* M is not positive definite (in working precision) */
    CODEGEN_MODAL_NO_CONVERGENCE = 3, /* the iteration did not converge within its budget */
    CODEGEN_MODAL_SINGULAR = 4,       /* K - omega^2 M + i omega B is singular (undamped
                                         resonance), or its inverse overflows */
    CODEGEN_MODAL_OVERFLOW = 5        /* a result is too large to represent */
} codegen_modal_status;

#define CODEGEN_MODES_WORK(n) (3 * (n) * (n))
#define CODEGEN_DAMPED_EIGENVALUES_WORK(n) (5 * (n) * (n) + 4 * (n))
#define CODEGEN_RECEPTANCE_WORK(n) (6 * (n) * (n))

/* omega_squared[0..n): the eigenvalues of K phi = omega^2 M phi, ascending (negative where K
 * is not positive definite: an unstable equilibrium); shapes (n x n): column j the mode of
 * omega_squared[j], with phi^T M phi = 1 and its largest component (the first such) positive. */
int codegen_modes(int n, const codegen_real *M, const codegen_real *K, codegen_real *omega_squared,
                  codegen_real *shapes, codegen_real *work);

/* re, im [0..2n): the eigenvalues s of M s^2 + B s + K, in ascending |s|, then ascending
 * imaginary part (a complex pair: the negative imaginary part first). */
int codegen_damped_eigenvalues(int n, const codegen_real *M, const codegen_real *B, const codegen_real *K,
                               codegen_real *re, codegen_real *im, codegen_real *work);

/* H_re + i H_im (n x n) = (K - omega^2 M + i omega B)^-1 at the circular frequency omega
 * [rad/s]: entry (i, j) is coordinate i's complex amplitude per unit amplitude of the
 * generalised force on coordinate j. */
int codegen_receptance(int n, const codegen_real *M, const codegen_real *B, const codegen_real *K,
                       codegen_real omega, codegen_real *H_re, codegen_real *H_im, codegen_real *work);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_MODAL_H */
