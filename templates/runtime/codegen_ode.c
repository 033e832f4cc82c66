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
static const double NODE[STAGES] = {0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0};
static const double TABLEAU[STAGES][STAGES - 1] = {
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.2, 0.0, 0.0, 0.0, 0.0, 0.0},
    {3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0},
    {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0},
    {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0},
    {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0},
    {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0}};

/* Fifth-order minus fourth-order weights: the local error estimate is h sum ERROR_WEIGHT_j k_j. */
static const double ERROR_WEIGHT[STAGES] = {
    71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
    -1.0 / 40.0};

/* The continuous extension: y(t + s h) = y + h sum_j b_j(s) k_j with
 * b_j(s) = s (D_j0 + s (D_j1 + s (D_j2 + s D_j3))); b_j(1) are the fifth-order weights. */
static const double DENSE[STAGES][4] = {
    {1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0,
     -12715105075.0 / 11282082432.0},
    {0.0, 0.0, 0.0, 0.0},
    {0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0,
     87487479700.0 / 32700410799.0},
    {0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0,
     -10690763975.0 / 1880347072.0},
    {0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0,
     701980252875.0 / 199316789632.0},
    {0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0,
     -1453857185.0 / 822651844.0},
    {0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0}};

/* The PI controller: h_new = h * SAFETY * err^-EXPONENT * err_old^MEMORY, kept within
 * [SHRINK_LIMIT, GROWTH_LIMIT] times h; a stage that is not finite shrinks h by NONFINITE_SHRINK. */
#define SAFETY 0.9
#define MEMORY 0.04
#define EXPONENT (0.2 - 0.75 * MEMORY)
#define SHRINK_LIMIT 0.2
#define GROWTH_LIMIT 10.0
#define NONFINITE_SHRINK 0.25
#define FIRST_ERROR_OLD 1e-4
/* Steps shorter than this many units in the last place of t are lost in rounding. */
#define UNDERFLOW_ULPS 16.0

/* Where each vector lives in work[], in units of n. */
#define AT_Y_PREV 0
#define AT_Y 1
#define AT_STAGE_RATE(j) (2 + (j))
#define AT_STAGE 9

static int all_finite(const double *x, int n)
{
    int i;
    for (i = 0; i < n; ++i) {
        if (!isfinite(x[i])) {
            return 0;
        }
    }
    return 1;
}

static void copy(double *to, const double *from, int n)
{
    int i;
    for (i = 0; i < n; ++i) {
        to[i] = from[i];
    }
}

/* x / scale, where a zero scale (atol = 0 and y = 0) accepts only an exact zero. */
static double scaled(double x, double scale)
{
    return scale > 0.0 ? x / scale : (x == 0.0 ? 0.0 : HUGE_VAL);
}

static double tolerance(const codegen_ode_options *o, double a, double b)
{
    return o->atol + o->rtol * fmax(fabs(a), fabs(b));
}

static int options_valid(const codegen_ode_options *o)
{
    return o->rtol >= CODEGEN_ODE_MIN_RTOL && o->rtol <= 1.0 && o->atol >= 0.0
           && isfinite(o->atol) && o->h_max > 0.0 && o->max_steps >= 1;
}

codegen_ode_options codegen_ode_defaults(void)
{
    codegen_ode_options o;
    o.rtol = 1e-9;
    o.atol = 1e-12;
    o.h_max = HUGE_VAL;
    o.max_steps = 1000000L;
    return o;
}

/* The root mean square of x_i / (atol + rtol |y_i|). */
static double norm(const codegen_ode_options *o, const double *x, const double *y, int n)
{
    double sum = 0.0;
    int i;
    for (i = 0; i < n; ++i) {
        const double r = scaled(x[i], tolerance(o, y[i], 0.0));
        sum += r * r;
    }
    return sqrt(sum / (double)n);
}

/* Hairer, Norsett and Wanner's first step: small enough that an Euler step changes y by about
 * 1 % of its tolerance-weighted size, and that its estimated fifth-order error is 1 %. Uses
 * one evaluation (the rate at y0 is in the first stage slot). */
static double first_step(codegen_ode_rhs f, const void *context, const codegen_ode_options *o,
                         codegen_ode_state *s, double *work)
{
    const int n = s->n;
    const double *y = work + AT_Y * n, *rate = work + AT_STAGE_RATE(0) * n;
    double *trial = work + AT_STAGE * n, *trial_rate = work + AT_STAGE_RATE(1) * n;
    const double d0 = norm(o, y, y, n), d1 = norm(o, rate, y, n);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1, h1, d2 = 0.0, larger;
    int i;
    h0 = fmin(isfinite(h0) ? h0 : 1e-6, o->h_max);
    for (i = 0; i < n; ++i) {
        trial[i] = y[i] + h0 * rate[i];
    }
    f(context, s->t + h0, trial, trial_rate);
    s->evaluations += 1;
    if (!all_finite(trial_rate, n)) {
        return h0;
    }
    for (i = 0; i < n; ++i) {
        const double r = scaled(trial_rate[i] - rate[i], tolerance(o, y[i], 0.0));
        d2 += r * r;
    }
    d2 = sqrt(d2 / (double)n) / h0;
    larger = fmax(d1, d2);
    h1 = larger <= 1e-15 ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / larger, 0.2);
    return fmin(fmin(100.0 * h0, h1), o->h_max);
}

codegen_ode_status codegen_ode_start(codegen_ode_rhs f, const void *context, int n, double t0,
                                     const double *y0, const codegen_ode_options *options,
                                     codegen_ode_state *state, double *work)
{
    double *rate;
    if (f == NULL || y0 == NULL || options == NULL || state == NULL || work == NULL || n < 1
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
    f(context, t0, y0, rate);
    if (!all_finite(rate, n)) {
        state->h = 0.0;
        state->failed = CODEGEN_ODE_NONFINITE;
        return CODEGEN_ODE_NONFINITE;
    }
    state->h = first_step(f, context, options, state, work);
    return CODEGEN_ODE_OK;
}

/* One trial step of size h from (t, y), whose rate is in the first stage slot: every stage,
 * the new state (in the STAGE slot) and its rate (the last stage). Returns the error norm,
 * or HUGE_VAL with *nonfinite set where a stage is not finite. */
static double trial_step(codegen_ode_rhs f, const void *context, const codegen_ode_options *o,
                         codegen_ode_state *s, double *work, double h, int *nonfinite)
{
    const int n = s->n;
    const double *y = work + AT_Y * n;
    double *stage = work + AT_STAGE * n, sum = 0.0;
    int i, j, k;
    for (k = 1; k < STAGES; ++k) {
        double *rate = work + AT_STAGE_RATE(k) * n;
        for (i = 0; i < n; ++i) {
            double increment = 0.0;
            for (j = 0; j < k; ++j) {
                increment += TABLEAU[k][j] * work[AT_STAGE_RATE(j) * n + i];
            }
            stage[i] = y[i] + h * increment;
        }
        f(context, s->t + NODE[k] * h, stage, rate);
        s->evaluations += 1;
        if (!all_finite(stage, n) || !all_finite(rate, n)) {
            *nonfinite = 1;
            return HUGE_VAL;
        }
    }
    for (i = 0; i < n; ++i) {
        double error = 0.0, r;
        for (j = 0; j < STAGES; ++j) {
            error += ERROR_WEIGHT[j] * work[AT_STAGE_RATE(j) * n + i];
        }
        r = scaled(h * error, tolerance(o, y[i], stage[i]));
        sum += r * r;
    }
    *nonfinite = 0;
    return sqrt(sum / (double)n);
}

/* Steps until the time reached is at least t_out (no step if it already is). */
static codegen_ode_status step_to(codegen_ode_rhs f, const void *context,
                                  const codegen_ode_options *o, codegen_ode_state *s,
                                  double *work, double t_out)
{
    const int n = s->n;
    /* After an accepted step the first stage slot still holds that step's first rate (for
     * output inside it); the next trial starts from its last rate (first same as last). */
    int stale = s->steps > 0, rejected_last = 0;
    while (s->t < t_out) {
        const double h = fmin(s->h, o->h_max);
        double error, factor;
        int nonfinite;
        if (s->steps + s->rejected >= o->max_steps) {
            return CODEGEN_ODE_BUDGET;
        }
        if (!(h > UNDERFLOW_ULPS * DBL_EPSILON * fabs(s->t))) {
            return s->last_nonfinite ? CODEGEN_ODE_NONFINITE : CODEGEN_ODE_STEP_UNDERFLOW;
        }
        if (stale) {
            copy(work + AT_STAGE_RATE(0) * n, work + AT_STAGE_RATE(STAGES - 1) * n, n);
            stale = 0;
        }
        error = trial_step(f, context, o, s, work, h, &nonfinite);
        s->last_nonfinite = nonfinite;
        if (!(error <= 1.0)) {
            factor = nonfinite ? NONFINITE_SHRINK
                               : fmax(SHRINK_LIMIT, SAFETY * pow(error, -EXPONENT));
            s->h = h * factor;
            s->rejected += 1;
            rejected_last = 1;
            continue;
        }
        factor = SAFETY * pow(fmax(error, 1e-10), -EXPONENT) * pow(s->error_old, MEMORY);
        factor = fmin(GROWTH_LIMIT, fmax(SHRINK_LIMIT, factor));
        if (rejected_last) {
            factor = fmin(factor, 1.0);
        }
        s->error_old = fmax(error, FIRST_ERROR_OLD);
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
static void interpolate(const codegen_ode_state *s, const double *work, double t_out, double *out)
{
    const int n = s->n;
    const double h = s->t - s->t_prev;
    double b[STAGES], theta;
    int i, j;
    if (t_out == s->t || h == 0.0) {
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
        double increment = 0.0;
        for (j = 0; j < STAGES; ++j) {
            increment += b[j] * work[AT_STAGE_RATE(j) * n + i];
        }
        out[i] = work[AT_Y_PREV * n + i] + h * increment;
    }
}

/* Whether the times are finite, non-decreasing and none before `earliest`. */
static int times_valid(double earliest, const double *times, size_t n_times)
{
    size_t i;
    for (i = 0; i < n_times; ++i) {
        if (!isfinite(times[i]) || times[i] < (i == 0 ? earliest : times[i - 1])) {
            return 0;
        }
    }
    return 1;
}

codegen_ode_status codegen_ode_advance(codegen_ode_rhs f, const void *context,
                                       const codegen_ode_options *options,
                                       codegen_ode_state *state, double *work,
                                       const double *times, size_t n_times, double *out,
                                       size_t *reached)
{
    size_t i;
    if (reached != NULL) {
        *reached = 0;
    }
    if (f == NULL || options == NULL || state == NULL || work == NULL
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
        const codegen_ode_status status = step_to(f, context, options, state, work, times[i]);
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

codegen_ode_status codegen_ode_solve(codegen_ode_rhs f, const void *context, int n,
                                     const double *y0, const double *times, size_t n_times,
                                     const codegen_ode_options *options,
                                     codegen_ode_state *state, double *work, double *out,
                                     size_t *reached)
{
    codegen_ode_status status;
    if (reached != NULL) {
        *reached = 0;
    }
    if (times == NULL || n_times < 1 || !times_valid(times[0], times, n_times)) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    status = codegen_ode_start(f, context, n, times[0], y0, options, state, work);
    if (status != CODEGEN_ODE_OK) {
        return status;
    }
    return codegen_ode_advance(f, context, options, state, work, times, n_times, out, reached);
}

codegen_ode_status codegen_ode_rk4_step(codegen_ode_rhs f, const void *context, int n, double t,
                                        const double *y, double h, double *work,
                                        double *y_next)
{
    static const double NODES[4] = {0.0, 0.5, 0.5, 1.0};
    static const double WEIGHTS[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
    double *stage;
    int i, k;
    if (f == NULL || y == NULL || work == NULL || y_next == NULL || n < 1 || !isfinite(t)
        || !isfinite(h) || !all_finite(y, n)) {
        return CODEGEN_ODE_BAD_INPUT;
    }
    stage = work + 4 * n;
    for (k = 0; k < 4; ++k) {
        double *rate = work + k * n;
        for (i = 0; i < n; ++i) {
            stage[i] = k == 0 ? y[i] : y[i] + NODES[k] * h * work[(k - 1) * n + i];
        }
        f(context, t + NODES[k] * h, stage, rate);
        if (!all_finite(rate, n)) {
            return CODEGEN_ODE_NONFINITE;
        }
    }
    for (i = 0; i < n; ++i) {
        double increment = 0.0;
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
