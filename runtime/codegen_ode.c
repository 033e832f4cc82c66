/*
 * codegen_ode.c -- Dormand-Prince 5(4) with dense output, and one RK4 step (codegen_ode.h).
 * Hand-written (not generated). Plain C99 + libm; no allocation, no mutable static state, no I/O.
 *
 * The coefficients are those of J. R. Dormand and P. J. Prince, "A family of embedded
 * Runge-Kutta formulae", J. Comput. Appl. Math. 6 (1980), and the continuous extension of
 * order 4 of L. F. Shampine, "Some practical Runge-Kutta formulas", Math. Comp. 46 (1986);
 * the step-size controller is the PI controller of Hairer, Norsett and Wanner, Solving
 * Ordinary Differential Equations I, section II.4, with their starting step heuristic.
 */
#include "codegen_ode.h"

#include <float.h>
#include <math.h>

#define STAGES 7

/* Nodes, and the tableau row by row; the last row is the fifth-order weights (FSAL: the last
 * stage is evaluated at the new state, and is the next step's first). */
static const codegen_real NODE[STAGES] = {0, CODEGEN_R(0.2), CODEGEN_R(0.3), CODEGEN_R(0.8), CODEGEN_R(8.0) / CODEGEN_R(9.0), 1, 1};
static const codegen_real TABLEAU[STAGES][STAGES - 1] = {
    {0, 0, 0, 0, 0, 0},
    {CODEGEN_R(0.2), 0, 0, 0, 0, 0},
    {CODEGEN_R(3.0) / CODEGEN_R(40.0), CODEGEN_R(9.0) / CODEGEN_R(40.0), 0, 0, 0, 0},
    {CODEGEN_R(44.0) / CODEGEN_R(45.0), -CODEGEN_R(56.0) / CODEGEN_R(15.0), CODEGEN_R(32.0) / CODEGEN_R(9.0), 0, 0, 0},
    {CODEGEN_R(19372.0) / CODEGEN_R(6561.0), -CODEGEN_R(25360.0) / CODEGEN_R(2187.0), CODEGEN_R(64448.0) / CODEGEN_R(6561.0), -CODEGEN_R(212.0) / CODEGEN_R(729.0), 0, 0},
    {CODEGEN_R(9017.0) / CODEGEN_R(3168.0), -CODEGEN_R(355.0) / CODEGEN_R(33.0), CODEGEN_R(46732.0) / CODEGEN_R(5247.0), CODEGEN_R(49.0) / CODEGEN_R(176.0), -CODEGEN_R(5103.0) / CODEGEN_R(18656.0), 0},
    {CODEGEN_R(35.0) / CODEGEN_R(384.0), 0, CODEGEN_R(500.0) / CODEGEN_R(1113.0), CODEGEN_R(125.0) / CODEGEN_R(192.0), -CODEGEN_R(2187.0) / CODEGEN_R(6784.0), CODEGEN_R(11.0) / CODEGEN_R(84.0)}};

/* Fifth-order minus fourth-order weights: the local error estimate is h sum ERROR_WEIGHT_j k_j. */
static const codegen_real ERROR_WEIGHT[STAGES] = {
    CODEGEN_R(71.0) / CODEGEN_R(57600.0), 0, -CODEGEN_R(71.0) / CODEGEN_R(16695.0), CODEGEN_R(71.0) / CODEGEN_R(1920.0), -CODEGEN_R(17253.0) / CODEGEN_R(339200.0), CODEGEN_R(22.0) / CODEGEN_R(525.0),
    -1 / CODEGEN_R(40.0)};

/* The continuous extension: y(t + s h) = y + h sum_j b_j(s) k_j with
 * b_j(s) = s (D_j0 + s (D_j1 + s (D_j2 + s D_j3))); b_j(1) are the fifth-order weights. */
static const codegen_real DENSE[STAGES][4] = {
    {1, -CODEGEN_R(8048581381.0) / CODEGEN_R(2820520608.0), CODEGEN_R(8663915743.0) / CODEGEN_R(2820520608.0),
     -CODEGEN_R(12715105075.0) / CODEGEN_R(11282082432.0)},
    {0, 0, 0, 0},
    {0, CODEGEN_R(131558114200.0) / CODEGEN_R(32700410799.0), -CODEGEN_R(68118460800.0) / CODEGEN_R(10900136933.0),
     CODEGEN_R(87487479700.0) / CODEGEN_R(32700410799.0)},
    {0, -CODEGEN_R(1754552775.0) / CODEGEN_R(470086768.0), CODEGEN_R(14199869525.0) / CODEGEN_R(1410260304.0),
     -CODEGEN_R(10690763975.0) / CODEGEN_R(1880347072.0)},
    {0, CODEGEN_R(127303824393.0) / CODEGEN_R(49829197408.0), -CODEGEN_R(318862633887.0) / CODEGEN_R(49829197408.0),
     CODEGEN_R(701980252875.0) / CODEGEN_R(199316789632.0)},
    {0, -CODEGEN_R(282668133.0) / CODEGEN_R(205662961.0), CODEGEN_R(2019193451.0) / CODEGEN_R(616988883.0),
     -CODEGEN_R(1453857185.0) / CODEGEN_R(822651844.0)},
    {0, CODEGEN_R(40617522.0) / CODEGEN_R(29380423.0), -CODEGEN_R(110615467.0) / CODEGEN_R(29380423.0), CODEGEN_R(69997945.0) / CODEGEN_R(29380423.0)}};

/* The PI controller: h_new = h * SAFETY * err^-EXPONENT * err_old^MEMORY, kept within
 * [SHRINK_LIMIT, GROWTH_LIMIT] times h; a stage that is not finite shrinks h by NONFINITE_SHRINK. */
#define SAFETY CODEGEN_R(0.9)
#define MEMORY CODEGEN_R(0.04)
#define EXPONENT (CODEGEN_R(0.2) - CODEGEN_R(0.75) * MEMORY)
#define SHRINK_LIMIT CODEGEN_R(0.2)
#define GROWTH_LIMIT CODEGEN_R(10.0)
#define NONFINITE_SHRINK CODEGEN_R(0.25)
#define FIRST_ERROR_OLD CODEGEN_R(1e-4)
/* Steps shorter than this many units in the last place of t are lost in rounding. */
#define UNDERFLOW_ULPS CODEGEN_R(16.0)

/* Where each vector lives in work[], in units of n. */
#define AT_Y_PREV 0
#define AT_Y 1
#define AT_STAGE_RATE(j) (2 + (j))
#define AT_STAGE 9

static int all_finite(const codegen_real *x, int n)
{
    int i;
    for (i = 0; i < n; ++i) {
        if (!isfinite(x[i])) {
            return 0;
        }
    }
    return 1;
}

static void copy(codegen_real *to, const codegen_real *from, int n)
{
    int i;
    for (i = 0; i < n; ++i) {
        to[i] = from[i];
    }
}

/* x / scale, where a zero scale (atol = 0 and y = 0) accepts only an exact zero. */
static codegen_real scaled(codegen_real x, codegen_real scale)
{
    return scale > 0 ? x / scale : (x == 0 ? 0 : CODEGEN_HUGE);
}

static codegen_real tolerance(const codegen_ode_options *o, codegen_real a, codegen_real b)
{
    return o->atol + o->rtol * codegen_fmax(codegen_fabs(a), codegen_fabs(b));
}

static int options_valid(const codegen_ode_options *o)
{
    return o->rtol >= CODEGEN_ODE_MIN_RTOL && o->rtol <= 1 && o->atol >= 0
           && isfinite(o->atol) && o->h_max > 0 && o->max_steps >= 1;
}

codegen_ode_options codegen_ode_defaults(void)
{
    codegen_ode_options o;
    o.rtol = CODEGEN_R(1e-9);
    o.atol = CODEGEN_R(1e-12);
    o.h_max = CODEGEN_HUGE;
    o.max_steps = 1000000L;
    return o;
}

/* The root mean square of x_i / (atol + rtol |y_i|). */
static codegen_real norm(const codegen_ode_options *o, const codegen_real *x, const codegen_real *y, int n)
{
    codegen_real sum = 0;
    int i;
    for (i = 0; i < n; ++i) {
        const codegen_real r = scaled(x[i], tolerance(o, y[i], 0));
        sum += r * r;
    }
    return codegen_sqrt(sum / (codegen_real)n);
}

/* Hairer, Norsett and Wanner's first step: small enough that an Euler step changes y by about
 * 1 % of its tolerance-weighted size, and that its estimated fifth-order error is 1 %. Uses
 * one evaluation (the rate at y0 is in the first stage slot). */
static codegen_real first_step(codegen_ode_rhs rhs, const void *context, const codegen_ode_options *o,
                         codegen_ode_state *s, codegen_real *work)
{
    const int n = s->n;
    const codegen_real *y = work + AT_Y * n, *rate = work + AT_STAGE_RATE(0) * n;
    codegen_real *trial = work + AT_STAGE * n, *trial_rate = work + AT_STAGE_RATE(1) * n;
    const codegen_real d0 = norm(o, y, y, n), d1 = norm(o, rate, y, n);
    codegen_real h0 = (d0 < CODEGEN_R(1e-5) || d1 < CODEGEN_R(1e-5)) ? CODEGEN_R(1e-6) : CODEGEN_R(0.01) * d0 / d1, h1, d2 = 0, larger;
    int i;
    h0 = codegen_fmin(isfinite(h0) ? h0 : CODEGEN_R(1e-6), o->h_max);
    for (i = 0; i < n; ++i) {
        trial[i] = y[i] + h0 * rate[i];
    }
    rhs(context, s->t + h0, trial, trial_rate);
    s->evaluations += 1;
    if (!all_finite(trial_rate, n)) {
        return h0;
    }
    for (i = 0; i < n; ++i) {
        const codegen_real r = scaled(trial_rate[i] - rate[i], tolerance(o, y[i], 0));
        d2 += r * r;
    }
    d2 = codegen_sqrt(d2 / (codegen_real)n) / h0;
    larger = codegen_fmax(d1, d2);
    h1 = larger <= CODEGEN_R(1e-15) ? codegen_fmax(CODEGEN_R(1e-6), h0 * CODEGEN_R(1e-3)) : codegen_pow(CODEGEN_R(0.01) / larger, CODEGEN_R(0.2));
    return codegen_fmin(codegen_fmin(CODEGEN_R(100.0) * h0, h1), o->h_max);
}

codegen_ode_status codegen_ode_start(codegen_ode_rhs rhs, const void *context, int n, codegen_real t0,
                                     const codegen_real *y0, const codegen_ode_options *options,
                                     codegen_ode_state *state, codegen_real *work)
{
    codegen_real *rate;
    if (rhs == NULL || y0 == NULL || options == NULL || state == NULL || work == NULL || n < 1
        || !isfinite(t0) || !all_finite(y0, n) || !options_valid(options)) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    state->n = n;
    state->t_prev = state->t = t0;
    state->error_old = FIRST_ERROR_OLD;
    state->steps = state->rejected = 0;
    state->evaluations = 1;
    state->last_nonfinite = 0;
    state->failed = CODEGEN_ODE_OK;
    copy(work + AT_Y_PREV * n, y0, n);
    copy(work + AT_Y * n, y0, n);
    rate = work + AT_STAGE_RATE(0) * n;
    rhs(context, t0, y0, rate);
    if (!all_finite(rate, n)) {
        state->h = 0;
        state->failed = CODEGEN_ODE_NONFINITE;
        return CODEGEN_ODE_NONFINITE;
    }
    state->h = first_step(rhs, context, options, state, work);
    return CODEGEN_ODE_OK;
}

/* One trial step of size h from (t, y), whose rate is in the first stage slot: every stage,
 * the new state (in the STAGE slot) and its rate (the last stage). Returns the error norm,
 * or HUGE_VAL with *nonfinite set where a stage is not finite. */
static codegen_real trial_step(codegen_ode_rhs rhs, const void *context, const codegen_ode_options *o,
                         codegen_ode_state *s, codegen_real *work, codegen_real h, int *nonfinite)
{
    const int n = s->n;
    const codegen_real *y = work + AT_Y * n;
    codegen_real *stage = work + AT_STAGE * n, sum = 0;
    int i, j, k;
    for (k = 1; k < STAGES; ++k) {
        codegen_real *rate = work + AT_STAGE_RATE(k) * n;
        for (i = 0; i < n; ++i) {
            codegen_real increment = 0;
            for (j = 0; j < k; ++j) {
                increment += TABLEAU[k][j] * work[AT_STAGE_RATE(j) * n + i];
            }
            stage[i] = y[i] + h * increment;
        }
        rhs(context, s->t + NODE[k] * h, stage, rate);
        s->evaluations += 1;
        if (!all_finite(stage, n) || !all_finite(rate, n)) {
            *nonfinite = 1;
            return CODEGEN_HUGE;
        }
    }
    for (i = 0; i < n; ++i) {
        codegen_real error = 0, r;
        for (j = 0; j < STAGES; ++j) {
            error += ERROR_WEIGHT[j] * work[AT_STAGE_RATE(j) * n + i];
        }
        r = scaled(h * error, tolerance(o, y[i], stage[i]));
        sum += r * r;
    }
    *nonfinite = 0;
    return codegen_sqrt(sum / (codegen_real)n);
}

/* Steps until the time reached is at least t_out (no step if it already is). */
static codegen_ode_status step_to(codegen_ode_rhs rhs, const void *context,
                                  const codegen_ode_options *o, codegen_ode_state *s,
                                  codegen_real *work, codegen_real t_out)
{
    const int n = s->n;
    /* After an accepted step the first stage slot still holds that step's first rate (for
     * output inside it); the next trial starts from its last rate (first same as last). */
    int stale = s->steps > 0, rejected_last = 0;
    while (s->t < t_out) {
        const codegen_real h = codegen_fmin(s->h, o->h_max);
        codegen_real error, factor;
        int nonfinite;
        if (s->steps + s->rejected >= o->max_steps) {
            return CODEGEN_ODE_BUDGET;
        }
        if (!(h > UNDERFLOW_ULPS * CODEGEN_EPSILON * codegen_fabs(s->t))) {
            return s->last_nonfinite ? CODEGEN_ODE_NONFINITE : CODEGEN_ODE_STEP_UNDERFLOW;
        }
        if (stale) {
            copy(work + AT_STAGE_RATE(0) * n, work + AT_STAGE_RATE(STAGES - 1) * n, n);
            stale = 0;
        }
        error = trial_step(rhs, context, o, s, work, h, &nonfinite);
        s->last_nonfinite = nonfinite;
        if (!(error <= 1)) {
            factor = nonfinite ? NONFINITE_SHRINK
                               : codegen_fmax(SHRINK_LIMIT, SAFETY * codegen_pow(error, -EXPONENT));
            s->h = h * factor;
            s->rejected += 1;
            rejected_last = 1;
            continue;
        }
        factor = SAFETY * codegen_pow(codegen_fmax(error, CODEGEN_R(1e-10)), -EXPONENT) * codegen_pow(s->error_old, MEMORY);
        factor = codegen_fmin(GROWTH_LIMIT, codegen_fmax(SHRINK_LIMIT, factor));
        if (rejected_last) {
            factor = codegen_fmin(factor, (codegen_real)1);
        }
        s->error_old = codegen_fmax(error, FIRST_ERROR_OLD);
        s->h = h * factor;
        copy(work + AT_Y_PREV * n, work + AT_Y * n, n);
        copy(work + AT_Y * n, work + AT_STAGE * n, n);
        s->t_prev = s->t;
        s->t += h;
        s->steps += 1;
        stale = 1;
        rejected_last = 0;
    }
    return CODEGEN_ODE_OK;
}

/* y(t_out) for t_prev <= t_out <= t, from the last step's stages; exact at its ends. */
static void interpolate(const codegen_ode_state *s, const codegen_real *work, codegen_real t_out, codegen_real *out)
{
    const int n = s->n;
    const codegen_real h = s->t - s->t_prev;
    codegen_real b[STAGES], theta;
    int i, j;
    if (t_out == s->t || h == 0) {
        copy(out, work + AT_Y * n, n);
        return;
    }
    if (t_out == s->t_prev) {
        copy(out, work + AT_Y_PREV * n, n);
        return;
    }
    theta = (t_out - s->t_prev) / h;
    for (j = 0; j < STAGES; ++j) {
        b[j] = theta * (DENSE[j][0] + theta * (DENSE[j][1] + theta * (DENSE[j][2]
                                                                     + theta * DENSE[j][3])));
    }
    for (i = 0; i < n; ++i) {
        codegen_real increment = 0;
        for (j = 0; j < STAGES; ++j) {
            increment += b[j] * work[AT_STAGE_RATE(j) * n + i];
        }
        out[i] = work[AT_Y_PREV * n + i] + h * increment;
    }
}

/* Whether the times are finite, non-decreasing and none before `earliest`. */
static int times_valid(codegen_real earliest, const codegen_real *times, size_t n_times)
{
    size_t i;
    for (i = 0; i < n_times; ++i) {
        if (!isfinite(times[i]) || times[i] < (i == 0 ? earliest : times[i - 1])) {
            return 0;
        }
    }
    return 1;
}

codegen_ode_status codegen_ode_advance(codegen_ode_rhs rhs, const void *context,
                                       const codegen_ode_options *options,
                                       codegen_ode_state *state, codegen_real *work,
                                       const codegen_real *times, size_t n_times, codegen_real *out,
                                       size_t *reached)
{
    size_t i;
    if (reached != NULL) {
        *reached = 0;
    }
    if (rhs == NULL || options == NULL || state == NULL || work == NULL
        || (n_times > 0 && (times == NULL || out == NULL))) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    if (state->failed != CODEGEN_ODE_OK) {
        return state->failed;
    }
    if (state->n < 1 || !options_valid(options) || !times_valid(state->t_prev, times, n_times)) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    for (i = 0; i < n_times; ++i) {
        const codegen_ode_status status = step_to(rhs, context, options, state, work, times[i]);
        if (status != CODEGEN_ODE_OK) {
            state->failed = status;
            return status;
        }
        interpolate(state, work, times[i], out + i * (size_t)state->n);
        if (reached != NULL) {
            *reached = i + 1;
        }
    }
    return CODEGEN_ODE_OK;
}

codegen_ode_status codegen_ode_solve(codegen_ode_rhs rhs, const void *context, int n,
                                     const codegen_real *y0, const codegen_real *times, size_t n_times,
                                     const codegen_ode_options *options,
                                     codegen_ode_state *state, codegen_real *work, codegen_real *out,
                                     size_t *reached)
{
    codegen_ode_status status;
    if (reached != NULL) {
        *reached = 0;
    }
    if (times == NULL || n_times < 1 || !times_valid(times[0], times, n_times)) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    status = codegen_ode_start(rhs, context, n, times[0], y0, options, state, work);
    if (status != CODEGEN_ODE_OK) {
        return status;
    }
    return codegen_ode_advance(rhs, context, options, state, work, times, n_times, out, reached);
}

codegen_ode_status codegen_ode_rk4_step(codegen_ode_rhs rhs, const void *context, int n, codegen_real t,
                                        const codegen_real *y, codegen_real h, codegen_real *work,
                                        codegen_real *y_next)
{
    static const codegen_real NODES[4] = {0, CODEGEN_R(0.5), CODEGEN_R(0.5), 1};
    static const codegen_real WEIGHTS[4] = {1 / CODEGEN_R(6.0), 1 / CODEGEN_R(3.0), 1 / CODEGEN_R(3.0), 1 / CODEGEN_R(6.0)};
    codegen_real *stage;
    int i, k;
    if (rhs == NULL || y == NULL || work == NULL || y_next == NULL || n < 1 || !isfinite(t)
        || !isfinite(h) || !all_finite(y, n)) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    stage = work + 4 * n;
    for (k = 0; k < 4; ++k) {
        codegen_real *rate = work + k * n;
        for (i = 0; i < n; ++i) {
            stage[i] = k == 0 ? y[i] : y[i] + NODES[k] * h * work[(k - 1) * n + i];
        }
        rhs(context, t + NODES[k] * h, stage, rate);
        if (!all_finite(rate, n)) {
            return CODEGEN_ODE_NONFINITE;
        }
    }
    for (i = 0; i < n; ++i) {
        codegen_real increment = 0;
        for (k = 0; k < 4; ++k) {
            increment += WEIGHTS[k] * work[k * n + i];
        }
        stage[i] = y[i] + h * increment;
    }
    if (!all_finite(stage, n)) {
        return CODEGEN_ODE_NONFINITE;
    }
    copy(y_next, stage, n);
    return CODEGEN_ODE_OK;
}
