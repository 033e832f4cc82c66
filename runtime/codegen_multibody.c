/*
 * codegen_multibody.c -- every equilibrium of a mechanism with n coordinates and its modes
 * (codegen_multibody.h). Hand-written (not generated). Plain C99 + libm; no allocation, no
 * static state, no I/O.
 */
#include "codegen_multibody.h"

#include <math.h>
#include <stddef.h>

#define PI CODEGEN_R(3.14159265358979323846)
/* The isolation searches each range widened by this much on both sides [rad], so that a
 * zero at an end of a range lies inside the searched box, where it can be proven. */
#define MARGIN CODEGEN_R(0.015625)
/* omega^2 within this many ulps of the largest |omega^2| counts as zero: undecided. */
#define ZERO_ULPS CODEGEN_R(64.0)

typedef enum placement { OUTSIDE, INSIDE, STRADDLES } placement;

/* Where box [lo, hi] lies against the range (centre - pi, centre + pi] of every coordinate:
 * OUTSIDE if outside one, INSIDE if inside all, else STRADDLES. A proven zero straddling the
 * seam of a periodic range counts at its upper end (its copy 2 pi lower, at the lower end,
 * is outside). */
static placement place(int n, const codegen_real *lo, const codegen_real *hi,
                       const codegen_real *centre, const int *periodic)
{
    placement where = INSIDE;
    int k;
    for (k = 0; k < n; ++k) {
        const codegen_real a = centre[k] - PI, b = centre[k] + PI;
        if (hi[k] <= a || lo[k] > b || (periodic[k] && lo[k] <= a)) {
            return OUTSIDE;
        }
        if (hi[k] > b && !periodic[k]) {
            where = STRADDLES;
        }
        if (lo[k] <= a) {
            where = STRADDLES;
        }
    }
    return where;
}

/* Undecided boxes closer than this (relative to their bounds, at least 1) are reported as
 * one, their hull: the subdivision leaves many tiny boxes around one point where G is not
 * smooth. The hull adds only boxes proven empty, so it still holds every zero it must. */
#define NEAR CODEGEN_R(1e-6)

/* Whether boxes a and b (n sides each) overlap or lie within NEAR of each other. */
static int touching(int n, const codegen_real *a_lo, const codegen_real *a_hi,
                    const codegen_real *b_lo, const codegen_real *b_hi)
{
    int k;
    for (k = 0; k < n; ++k) {
        const codegen_real gap = NEAR * codegen_fmax(codegen_fmax(codegen_fabs(a_lo[k]),
                                                                  codegen_fabs(a_hi[k])),
                                                     CODEGEN_R(1.0));
        if (a_hi[k] + gap < b_lo[k] || b_hi[k] + gap < a_lo[k]) {
            return 0;
        }
    }
    return 1;
}

/* An undecided box, merged into the first reported one it touches (their hull). */
static int add_uncertain(codegen_mb_result *out, int n, const codegen_real *lo,
                         const codegen_real *hi, int kind)
{
    int u, k;
    for (u = 0; u < out->uncertain_count; ++u) {
        codegen_real *u_lo = &out->uncertain_lo[u * n], *u_hi = &out->uncertain_hi[u * n];
        if (touching(n, u_lo, u_hi, lo, hi)) {
            for (k = 0; k < n; ++k) {
                u_lo[k] = codegen_fmin(u_lo[k], lo[k]);
                u_hi[k] = codegen_fmax(u_hi[k], hi[k]);
            }
            if (kind == CODEGEN_BOX_SINGULAR) {  /* the hull is singular where a part is */
                out->uncertain_kind[u] = kind;
            }
            return 0;
        }
    }
    if (out->uncertain_count >= out->uncertain_capacity) {
        return CODEGEN_MB_FULL;
    }
    for (k = 0; k < n; ++k) {
        out->uncertain_lo[out->uncertain_count * n + k] = lo[k];
        out->uncertain_hi[out->uncertain_count * n + k] = hi[k];
    }
    out->uncertain_kind[out->uncertain_count++] = kind;
    return 0;
}

int codegen_mb_modes(int n, const codegen_real *M, const codegen_real *B, const codegen_real *K,
                     codegen_real *omega_squared, codegen_real *shapes, codegen_real *s_re,
                     codegen_real *s_im, codegen_real *damping_ratio, codegen_real *modal_damping,
                     int *stability, codegen_real *work)
{
    int status, i, j, k;
    codegen_real largest = CODEGEN_R(0.0), least;
    status = codegen_modes(n, M, K, omega_squared, shapes, work);
    if (status == CODEGEN_MODAL_OK) {
        status = codegen_damped_eigenvalues(n, M, B, K, s_re, s_im, work);
    }
    for (j = 0; j < 2 * n && status == CODEGEN_MODAL_OK; ++j) {  /* not finite: too large */
        if (!(codegen_fabs(s_re[j]) < CODEGEN_HUGE && codegen_fabs(s_im[j]) < CODEGEN_HUGE)) {
            status = CODEGEN_MODAL_OVERFLOW;
        }
    }
    if (status != CODEGEN_MODAL_OK) {
        for (j = 0; j < n * n; ++j) {
            shapes[j] = CODEGEN_NAN;
        }
        for (j = 0; j < 2 * n; ++j) {
            s_re[j] = s_im[j] = damping_ratio[j] = CODEGEN_NAN;
        }
        for (j = 0; j < n; ++j) {
            omega_squared[j] = modal_damping[j] = CODEGEN_NAN;
        }
        *stability = CODEGEN_MB_UNDECIDED;
        return status;
    }
    for (j = 0; j < 2 * n; ++j) {
        const codegen_real a = codegen_fabs(s_re[j]), b = codegen_fabs(s_im[j]);
        const codegen_real big = codegen_fmax(a, b);  /* |s| without overflow */
        const codegen_real size = big > CODEGEN_R(0.0)
                                  ? big * codegen_sqrt((a / big) * (a / big) + (b / big) * (b / big))
                                  : CODEGEN_R(0.0);
        damping_ratio[j] = size > CODEGEN_R(0.0) ? -s_re[j] / size : CODEGEN_NAN;
    }
    for (j = 0; j < n; ++j) {  /* phi_j^T B phi_j / (2 omega_j), B read as symmetric */
        codegen_real form = CODEGEN_R(0.0);
        for (i = 0; i < n; ++i) {
            for (k = 0; k < n; ++k) {
                form += shapes[i * n + j] * CODEGEN_R(0.5) * (B[i * n + k] + B[k * n + i])
                        * shapes[k * n + j];
            }
        }
        modal_damping[j] = omega_squared[j] > CODEGEN_R(0.0)
                           ? form / (CODEGEN_R(2.0) * codegen_sqrt(omega_squared[j])) : CODEGEN_NAN;
    }
    for (j = 0; j < n; ++j) {
        largest = codegen_fmax(codegen_fabs(omega_squared[j]), largest);
    }
    for (j = 0; j < n; ++j) {  /* an overflow in the damping ratios: none is reported */
        if (codegen_fabs(modal_damping[j]) >= CODEGEN_HUGE || codegen_fabs(omega_squared[j]) >= CODEGEN_HUGE) {
            for (k = 0; k < n; ++k) {
                omega_squared[k] = modal_damping[k] = CODEGEN_NAN;
            }
            for (k = 0; k < 2 * n; ++k) {
                s_re[k] = s_im[k] = damping_ratio[k] = CODEGEN_NAN;
            }
            for (k = 0; k < n * n; ++k) {
                shapes[k] = CODEGEN_NAN;
            }
            *stability = CODEGEN_MB_UNDECIDED;
            return CODEGEN_MODAL_OVERFLOW;
        }
    }
    least = omega_squared[0];  /* ascending */
    *stability = least > ZERO_ULPS * CODEGEN_EPSILON * largest ? CODEGEN_MB_STABLE
                 : least < -ZERO_ULPS * CODEGEN_EPSILON * largest ? CODEGEN_MB_UNSTABLE
                 : CODEGEN_MB_UNDECIDED;
    return CODEGEN_MODAL_OK;
}

/* Equilibrium r's modes, at its point. */
static void linearise(const codegen_mb_model *model, const void *params, codegen_mb_result *out,
                      int r, codegen_real *work)
{
    const int n = model->n;
    codegen_real *M = work, *B = M + n * n, *K = B + n * n, *rest = K + n * n;
    if (model->linearisation(params, &out->theta[r * n], M, B, K) != 0) {
        int j;
        for (j = 0; j < n * n; ++j) {
            M[j] = CODEGEN_NAN;  /* codegen_modes reports it: BAD_INPUT */
        }
    }
    out->modal_status[r] = codegen_mb_modes(
        n, M, B, K, &out->omega_squared[r * n], &out->shapes[r * n * n], &out->s_re[r * 2 * n],
        &out->s_im[r * 2 * n], &out->damping_ratio[r * 2 * n], &out->modal_damping[r * n],
        &out->stability[r], rest);
}

int codegen_mb_analyze(const codegen_mb_model *model, const void *params,
                       const codegen_real *centre, const int *periodic,
                       codegen_mb_result *out, codegen_boxes *boxes, codegen_real *work)
{
    const int n = model ? model->n : 0;
    codegen_real *lo = work, *hi = work + n;
    int status, e, k;
    if (model == NULL || out == NULL || boxes == NULL || work == NULL || centre == NULL
        || periodic == NULL || n < 1) {
        return CODEGEN_BOXES_BAD_INPUT;
    }
    out->count = out->uncertain_count = 0;
    for (k = 0; k < n; ++k) {
        lo[k] = centre[k] - PI - MARGIN;
        hi[k] = centre[k] + PI + MARGIN;
    }
    status = codegen_isolate_boxes(n, model->enclose, params, lo, hi, boxes, work + 2 * n);
    if (status != 0) {
        return status == CODEGEN_BOXES_FULL ? CODEGEN_MB_FULL : status;
    }
    for (e = 0; e < boxes->count; ++e) {
        const codegen_real *box_lo = &boxes->lo[e * n], *box_hi = &boxes->hi[e * n];
        const placement where = place(n, box_lo, box_hi, centre, periodic);
        const int proven = boxes->kind[e] == CODEGEN_BOX_ROOT;
        if (where == OUTSIDE) {
            continue;
        }
        if (!proven || where == STRADDLES) {
            status = add_uncertain(out, n, box_lo, box_hi,
                                   proven ? CODEGEN_MB_AT_RANGE_END : (int)boxes->kind[e]);
            if (status != 0) {
                return status;
            }
            continue;
        }
        if (out->count >= out->capacity) {
            return CODEGEN_MB_FULL;
        }
        for (k = 0; k < n; ++k) {
            out->theta[out->count * n + k] = boxes->point[e * n + k];
            out->lo[out->count * n + k] = box_lo[k];
            out->hi[out->count * n + k] = box_hi[k];
        }
        linearise(model, params, out, out->count, work);
        ++out->count;
    }
    return 0;
}

/* An integration's context: the model, its parameters and room for M and f. */
typedef struct motion {
    const codegen_mb_model *model;
    const void *params;
    codegen_real *M, *f;
} motion;

/* x := M^-1 x, M (n x n, symmetric positive definite) overwritten by its Cholesky factor;
 * nonzero where M is not positive definite. */
static int cholesky_solve(int n, codegen_real *M, codegen_real *x)
{
    int i, j, k;
    for (j = 0; j < n; ++j) {
        codegen_real d = M[j * n + j];
        for (k = 0; k < j; ++k) {
            d -= M[j * n + k] * M[j * n + k];
        }
        if (!(d > CODEGEN_R(0.0))) {
            return 1;
        }
        M[j * n + j] = codegen_sqrt(d);
        for (i = j + 1; i < n; ++i) {
            codegen_real s = CODEGEN_R(0.5) * (M[i * n + j] + M[j * n + i]);
            for (k = 0; k < j; ++k) {
                s -= M[i * n + k] * M[j * n + k];
            }
            M[i * n + j] = s / M[j * n + j];
        }
    }
    for (i = 0; i < n; ++i) {  /* L z = x */
        for (k = 0; k < i; ++k) {
            x[i] -= M[i * n + k] * x[k];
        }
        x[i] /= M[i * n + i];
    }
    for (i = n - 1; i >= 0; --i) {  /* L^T x = z */
        for (k = i + 1; k < n; ++k) {
            x[i] -= M[k * n + i] * x[k];
        }
        x[i] /= M[i * n + i];
    }
    return 0;
}

static void equation_of_motion(const void *context, codegen_real t, const codegen_real *y,
                               codegen_real *dydt)
{
    const motion *m = (const motion *)context;
    const int n = m->model->n;
    int i;
    (void)t;
    if (m->model->dynamics(m->params, y, y + n, m->M, m->f) != 0
        || cholesky_solve(n, m->M, m->f) != 0) {
        for (i = 0; i < 2 * n; ++i) {
            dydt[i] = CODEGEN_NAN;  /* the integrator reports CODEGEN_ODE_NONFINITE */
        }
        return;
    }
    for (i = 0; i < n; ++i) {
        dydt[i] = y[n + i];
        dydt[n + i] = -m->f[i];
    }
}

int codegen_mb_accelerations(const codegen_mb_model *model, const void *params,
                             const codegen_real *theta, const codegen_real *theta_d,
                             codegen_real *theta_dd, codegen_real *work)
{
    int i, n;
    if (model == NULL || work == NULL || model->n < 1) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    n = model->n;
    if (model->dynamics(params, theta, theta_d, work, theta_dd) != 0
        || cholesky_solve(n, work, theta_dd) != 0) {
        return CODEGEN_ODE_NONFINITE;
    }
    for (i = 0; i < n; ++i) {
        theta_dd[i] = -theta_dd[i];
    }
    return CODEGEN_ODE_OK;
}

int codegen_mb_simulate(const codegen_mb_model *model, const void *params, const codegen_real *y0,
                        const codegen_real *times, size_t n_times,
                        const codegen_ode_options *options, codegen_ode_state *state,
                        codegen_real *work, codegen_real *out, size_t *reached)
{
    motion m;
    int n;
    if (model == NULL || work == NULL || model->n < 1) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    n = model->n;
    m.model = model;
    m.params = params;
    m.M = work;
    m.f = work + n * n;
    return (int)codegen_ode_solve(equation_of_motion, &m, 2 * n, y0, times, n_times, options, state,
                             work + n * n + n, out, reached);
}
