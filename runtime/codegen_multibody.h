/*
 * codegen_multibody.h -- the vibration analysis of a mechanism with n coordinates: every
 * equilibrium in the box of its coordinates' ranges, each proven (codegen_boxes.h), and at
 * each its linearisation M thetaddot + B thetadot + K theta = 0 in modes (codegen_modal.h):
 * the undamped natural frequencies and mass-normalised shapes, the 2n eigenvalues of the
 * damped linearisation with a damping ratio each, and the stability.
 *
 * Hand-written (not generated), written once for every library: a library contributes its
 * generated kernels through a codegen_mb_model, as for one coordinate (codegen_model.h).
 * Plain C99 + libm; no allocation, no static state, no I/O.
 */
#ifndef CODEGEN_MULTIBODY_H
#define CODEGEN_MULTIBODY_H

#include "codegen_boxes.h"
#include "codegen_modal.h"
#include "codegen_ode.h"
#include "codegen_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/* M, B and K (n x n, row-major) at the coordinates theta[0..n); 0, or nonzero where a value
 * is not finite (the state is singular). */
typedef int (*codegen_mb_linearisation)(const void *params, const codegen_real *theta,
                                        codegen_real *M, codegen_real *B, codegen_real *K);

/* M (n x n) and the forces f = h(theta, thetadot) + B thetadot + G(theta) (n) of the equation
 * of motion M thetaddot + f = 0 at a state; 0, or nonzero where a value is not finite. */
typedef int (*codegen_mb_dynamics)(const void *params, const codegen_real *theta,
                                   const codegen_real *theta_d, codegen_real *M, codegen_real *f);

/* What a library gives the analysis: its number of coordinates, G and K enclosed over a box
 * (the context is the parameters), its linearisation at a point and its equation of motion. */
typedef struct codegen_mb_model {
    int n;
    codegen_box_enclosure enclose;
    codegen_mb_linearisation linearisation;
    codegen_mb_dynamics dynamics;
} codegen_mb_model;

/* Each equilibrium's stability. */
#define CODEGEN_MB_STABLE 1     /* K positive definite: every omega^2 > 0 */
#define CODEGEN_MB_UNSTABLE 0   /* some omega^2 < 0 */
#define CODEGEN_MB_UNDECIDED -1 /* an omega^2 within rounding of 0, or the modes failed */

/* Why a box is uncertain: those of codegen_box_kind, and one more. */
#define CODEGEN_MB_AT_RANGE_END 3 /* a proven zero whose box straddles an end of a range that
                                     does not wrap: in the range or just outside it */

/* The results, arrays the caller owns: equilibrium r's coordinates theta[r * n + k], its
 * proven box lo/hi[r * n + k]; omega_squared[r * n + j] (ascending), shapes[r * n * n + ..]
 * (column j the shape of mode j), the damped eigenvalues s_re/s_im[r * 2n + j] with
 * damping_ratio[r * 2n + j] = -Re s / |s|, the modal damping ratios modal_damping[r * n + j] =
 * phi_j^T B phi_j / (2 omega_j) (mode j's own: exact where B is proportional to M and K, and
 * defined for an overdamped mode too), stability[r] and modal_status[r] (a
 * codegen_modal_status; the modal values are NaN unless 0). Uncertain box u:
 * uncertain_lo/hi[u * n + k], uncertain_kind[u]. */
typedef struct codegen_mb_result {
    int capacity, count;
    codegen_real *theta, *lo, *hi, *omega_squared, *shapes, *s_re, *s_im, *damping_ratio,
        *modal_damping;
    int *stability, *modal_status;
    int uncertain_capacity, uncertain_count;
    codegen_real *uncertain_lo, *uncertain_hi;
    int *uncertain_kind;
} codegen_mb_result;

#define CODEGEN_MB_WORK(n) (CODEGEN_BOXES_WORK(n) + 3 * (n) * (n) + \
                            CODEGEN_DAMPED_EIGENVALUES_WORK(n) + CODEGEN_MODES_WORK(n))

/* Returned besides 0 and the statuses of codegen_isolate_boxes and the model's enclosure. */
#define CODEGEN_MB_FULL (-11)       /* more equilibria or uncertain boxes than the result holds */

/* Every equilibrium with theta_k in (centre[k] - pi, centre[k] + pi] for each k (periodic[k]:
 * theta_k and theta_k + 2 pi are the same state), its modes and stability. boxes: room for
 * the isolation's raw results (at least capacity + uncertain_capacity entries, n each). */
int codegen_mb_analyze(const codegen_mb_model *model, const void *params,
                       const codegen_real *centre, const int *periodic,
                       codegen_mb_result *out, codegen_boxes *boxes, codegen_real *work);

/* The modal quantities of one linearisation (M, B, K): omega_squared[n], shapes[n * n],
 * s_re/s_im/damping_ratio[2n], modal_damping[n] (NaN where omega^2 <= 0), *stability;
 * returns a codegen_modal_status. */
int codegen_mb_modes(int n, const codegen_real *M, const codegen_real *B, const codegen_real *K,
                     codegen_real *omega_squared, codegen_real *shapes, codegen_real *s_re,
                     codegen_real *s_im, codegen_real *damping_ratio, codegen_real *modal_damping,
                     int *stability, codegen_real *work);

/* thetaddot = -M^-1 (h + B thetadot + G) at a state (M by Cholesky): CODEGEN_ODE_OK, or
 * CODEGEN_ODE_NONFINITE where M is not positive definite or a value is not finite.
 * work: CODEGEN_MB_ACCELERATIONS_WORK(n) reals. */
#define CODEGEN_MB_ACCELERATIONS_WORK(n) ((n) * (n))
int codegen_mb_accelerations(const codegen_mb_model *model, const void *params,
                             const codegen_real *theta, const codegen_real *theta_d,
                             codegen_real *theta_dd, codegen_real *work);

/* The time response: y = (theta, thetadot) (2n values) from y0 at times[0], integrated by the
 * runtime's Dormand-Prince 5(4) (codegen_ode.h) with thetaddot = -M^-1 f (M by Cholesky), y at
 * each time written to out[i * 2n ..]; a codegen_ode_status (CODEGEN_ODE_NONFINITE where M is
 * not positive definite or a value not finite). work: CODEGEN_MB_SIMULATE_WORK(n) reals. */
#define CODEGEN_MB_SIMULATE_WORK(n) ((n) * (n) + (n) + CODEGEN_ODE_WORK(2 * (n)))
int codegen_mb_simulate(const codegen_mb_model *model, const void *params, const codegen_real *y0,
                        const codegen_real *times, size_t n_times,
                        const codegen_ode_options *options, codegen_ode_state *state,
                        codegen_real *work, codegen_real *out, size_t *reached);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_MULTIBODY_H */
