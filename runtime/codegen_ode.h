/*
 * codegen_ode.h -- an adaptive explicit Runge-Kutta integrator for y' = f(t, y), y in R^n:
 * Dormand and Prince's 5(4) pair with its first-same-as-last stage, a PI step-size controller,
 * and output at any times the caller asks for through the pair's continuous extension of
 * order 4 (Shampine's). Also one classical fourth-order Runge-Kutta step, for fixed-step loops.
 * Hand-written (not generated). Plain C99 + libm; no allocation, no mutable static state, no I/O:
 * the caller owns every byte (the state and a work array), so integrations are reentrant and
 * may run on any number of threads at once.
 *
 * Error control: a step is accepted when the root mean square over the components of
 * e_i / (atol + rtol * max(|y_i|, |y_new_i|)) is at most 1, e the difference of the two
 * embedded solutions; the fifth-order solution is kept (local extrapolation).
 *
 * Use: codegen_ode_start(...) once, then codegen_ode_advance(...) as often as wanted with
 * output times that never go back before the last step taken; the integration is the same
 * (bit for bit) however the output times are split between calls, because an output is
 * interpolated and never shortens a step. codegen_ode_solve does both in one call.
 */
#ifndef CODEGEN_ODE_H
#define CODEGEN_ODE_H

#include <stddef.h>

#include "codegen_real.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum codegen_ode_status {
    CODEGEN_ODE_OK = 0,
    CODEGEN_ODE_BAD_INPUT = 1,      /* a NULL pointer, n < 1, an option out of range, a value
                                       not finite, output times out of order or before the
                                       last step */
    CODEGEN_ODE_BUDGET = 2,         /* max_steps steps were tried before the last output time */
    CODEGEN_ODE_STEP_UNDERFLOW = 3, /* the step size fell below the resolution of t (16 units
                                       in the last place): a singularity, or too stiff */
    CODEGEN_ODE_NONFINITE = 4       /* f is NaN or infinite at the initial state, or at every
                                       trial state down to the smallest step */
} codegen_ode_status;

/* The right-hand side: dydt[0..n) = f(t, y[0..n)). It may write NaN or infinity where f is
 * undefined; the integrator then tries a shorter step. */
typedef void (*codegen_ode_rhs)(const void *context, codegen_real t, const codegen_real *y, codegen_real *dydt);

typedef struct codegen_ode_options {
    codegen_real rtol;     /* relative tolerance per step, in [CODEGEN_ODE_MIN_RTOL, 1] */
    codegen_real atol;     /* absolute tolerance per step, >= 0, in the units of every y_i */
    codegen_real h_max;    /* longest step [units of t], > 0; HUGE_VAL for no limit */
    long max_steps;  /* budget of tried steps (accepted and rejected) over the whole
                        integration, >= 1 */
} codegen_ode_options;

/* Below this rtol the error estimate is mostly rounding: 100 units of double's epsilon. */
#define CODEGEN_ODE_MIN_RTOL CODEGEN_R(2.220446049250313e-14)

/* Where an integration stands. Plain data: it may be copied, and it holds no pointers. */
typedef struct codegen_ode_state {
    int n;                 /* dimension */
    codegen_real t_prev;         /* start of the last accepted step (t before the first step) */
    codegen_real t;              /* time reached; y(t) is work[n .. 2n) */
    codegen_real h;              /* the next step size to try, > 0 */
    codegen_real error_old;      /* error norm of the last accepted step (PI controller) */
    long steps;            /* accepted steps */
    long rejected;         /* rejected steps: error too large, or f not finite */
    long evaluations;      /* evaluations of f */
    int last_nonfinite;    /* 1: the last rejection met a value that is not finite */
    codegen_ode_status failed; /* the first failure, returned by later calls */
} codegen_ode_state;

/* Doubles of work the integrator needs for dimension n (the last step's start and end
 * states, its seven stages and a trial state), and of one RK4 step (four stages and a
 * trial state). */
#define CODEGEN_ODE_WORK(n) (10 * (n))
#define CODEGEN_ODE_RK4_WORK(n) (5 * (n))

/* rtol 1e-9, atol 1e-12, no step limit, 1e6 steps. */
codegen_ode_options codegen_ode_defaults(void);

/* Starts an integration at (t0, y0[0..n)): checks the options, evaluates f(t0, y0) and picks
 * the first step size (one more evaluation). work: CODEGEN_ODE_WORK(n) doubles, owned by the
 * integration until it ends. Returns CODEGEN_ODE_OK, CODEGEN_ODE_BAD_INPUT, or
 * CODEGEN_ODE_NONFINITE (f not finite at y0: state->failed says so as well). */
codegen_ode_status codegen_ode_start(codegen_ode_rhs f, const void *context, int n, codegen_real t0,
                                     const codegen_real *y0, const codegen_ode_options *options,
                                     codegen_ode_state *state, codegen_real *work);

/* Integrates on and writes y(times[i]) to out[i * n .. i * n + n) for i = 0 .. n_times - 1, in
 * order; f, context and options must be those given to codegen_ode_start. The times must be
 * finite, non-decreasing and >= state->t_prev (an output inside the last step taken is
 * interpolated); otherwise CODEGEN_ODE_BAD_INPUT, and nothing is written or changed. On a
 * failure (CODEGEN_ODE_BUDGET, _STEP_UNDERFLOW, _NONFINITE) the outputs before the time where
 * it happened are written; *reached (may be NULL) receives how many were, in every case. A
 * failure is final: later calls return it. The last step may end beyond the last output time. */
codegen_ode_status codegen_ode_advance(codegen_ode_rhs f, const void *context,
                                       const codegen_ode_options *options,
                                       codegen_ode_state *state, codegen_real *work,
                                       const codegen_real *times, size_t n_times, codegen_real *out,
                                       size_t *reached);

/* codegen_ode_start at times[0] from y0, then codegen_ode_advance over all of times (so
 * out[0 .. n) = y0): the whole integration in one call. state receives the statistics. */
codegen_ode_status codegen_ode_solve(codegen_ode_rhs f, const void *context, int n,
                                     const codegen_real *y0, const codegen_real *times, size_t n_times,
                                     const codegen_ode_options *options,
                                     codegen_ode_state *state, codegen_real *work, codegen_real *out,
                                     size_t *reached);

/* One classical fourth-order Runge-Kutta step of size h from (t, y): y_next = y(t + h) with a
 * local error O(h^5). work: CODEGEN_ODE_RK4_WORK(n) doubles; y_next may be y. Four
 * evaluations of f. Returns CODEGEN_ODE_BAD_INPUT (NULL, n < 1, t, h or y not finite) or
 * CODEGEN_ODE_NONFINITE (a stage or the result not finite); y_next is written only on OK. */
codegen_ode_status codegen_ode_rk4_step(codegen_ode_rhs f, const void *context, int n, codegen_real t,
                                        const codegen_real *y, codegen_real h, codegen_real *work,
                                        codegen_real *y_next);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_ODE_H */
