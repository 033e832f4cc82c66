/* A driver for the runtime's analysis and time response (runtime/codegen_analysis.c,
 * codegen_simulation.c), used by tests/runtime_c/test_analysis_runtime.py, on a mechanism
 * written here by hand, with nothing generated: G(theta) = a cos(theta) + b sin(theta) + c,
 * constant M = m and B = d, over the circle centred on `centre`. Its polynomial in
 * tau = tan(theta/2) is (a + c) + 2 b tau + (c - a) tau^2. One command per line on stdin,
 * one answer line on stdout; doubles travel as C99 hex floats both ways.
 *
 *   analyze ROUTE CAPACITY A B C M D CENTRE
 *       ROUTE 0 (default) or 1 (isolation); CAPACITY: the result's roots (<= 4)
 *       -> STATUS N_ROOTS [THETA LO HI CERTIFIED GENUINE KIND RESIDUAL M B K OMEGA_RE
 *          OMEGA_IM ZETA_RE ZETA_IM EIG_RE0 EIG_IM0 EIG_RE1 EIG_IM1 STABILITY DAMPING]..
 *          N_UNCERTAIN [LO HI KIND].. SIGMA0 SIGMA1 SIGMA2
 *   simulate A B C M D THETA0 THETA_D0 COUNT T..   -> STATUS REACHED [THETA THETA_D]..
 *   rk4 A B C M D H THETA THETA_D                  -> STATUS THETA THETA_D
 *   null                                           -> the statuses of calls with NULL pointers
 *   modes A B C M D W X                            -> the isolation route on a two-mode model:
 *       mode 0's G as above, mode 1's a cos(theta) - b sin(theta) + c, and one assembly-mode
 *       condition, W on mode 0 and -W on mode 1 (W > 0: mode 0 is the declared one; W < 0:
 *       mode 1; W = 0: neither); X != 0: mode 0 exists nowhere (its values NaN, as a chain
 *       of dyads' mode is where its own radicand is negative)
 *       -> STATUS N_ROOTS [THETA KIND MODE GENUINE CERTIFIED]..
 */
#include "codegen_model.h"
#include "codegen_runtime.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ROOTS 4
#define MAX_UNCERTAIN 4
#define STATE 5
#define MODES_STATE 7 /* and G on both modes' branches */
#define ERR_MASS 12 /* this mechanism's own status: m must be positive */

typedef struct params {
    double a, b, c, m, d, centre, w, absent;
} params;

typedef struct analysis {
    double sigma[3];
    int n_roots;
    codegen_equilibrium roots[MAX_ROOTS];
    int n_singular;
    double singular_theta[MAX_ROOTS];
    int n_unassembled;
    double unassembled_theta[MAX_ROOTS];
    int n_uncertain;
    codegen_uncertain uncertain[MAX_UNCERTAIN];
} analysis;

typedef struct workspace {
    codegen_analysis_call call;
    analysis result;
    analysis polynomial;
    double roots[CODEGEN_ROOTS_WORK(2)];
    codegen_root_span spans[2];
    double sigma_bound[3];
    double theta[MAX_ROOTS];
    unsigned branches[MAX_ROOTS];
    codegen_iv slots[1];
    codegen_isolated found[MAX_ROOTS + MAX_UNCERTAIN];
    codegen_isolation_box boxes[CODEGEN_ISOLATE_DEPTH];
    double scratch[CODEGEN_ANALYSIS_SCRATCH(MODES_STATE, 2, 2, 1)];
} workspace;

typedef struct simulation {
    params params;
    codegen_ode_options options;
    codegen_ode_state state;
    unsigned signs;
    double work[CODEGEN_ODE_WORK(2)];
} simulation;

static int check_params(const void *p)
{
    const params *q = (const params *)p;
    if (!isfinite(q->a) || !isfinite(q->b) || !isfinite(q->c) || !isfinite(q->m)
        || !isfinite(q->d) || !isfinite(q->centre)) {
        return CODEGEN_ERR_NONFINITE_PARAM;
    }
    return q->m > 0 ? CODEGEN_OK : ERR_MASS;
}

static void equilibrium_state(const void *p, double theta, double *out)
{
    const params *q = (const params *)p;
    out[0] = q->a * cos(theta) + q->b * sin(theta) + q->c;
    out[1] = fabs(q->a * cos(theta)) + fabs(q->b * sin(theta)) + fabs(q->c);
    out[2] = q->m;
    out[3] = q->d;
    out[4] = -q->a * sin(theta) + q->b * cos(theta);
}

static int enclose(const void *context, unsigned mode, codegen_iv theta, codegen_iv *g,
                   codegen_iv *dg, unsigned *flags)
{
    const params *q = (const params *)((const codegen_enclosure_context *)context)->params;
    const codegen_iv c = codegen_iv_cos(theta), s = codegen_iv_sin(theta);
    if (mode != 0u) {
        return CODEGEN_ERR_ARGUMENT;
    }
    *flags = mode == 0u && q->absent != 0 ? CODEGEN_IV_OUTSIDE : 0u;
    *g = codegen_iv_add(codegen_iv_add(codegen_iv_mul(codegen_iv_point(q->a), c),
                                       codegen_iv_mul(codegen_iv_point(q->b), s)),
                        codegen_iv_point(q->c));
    if (dg != NULL) {
        *dg = codegen_iv_sub(codegen_iv_mul(codegen_iv_point(q->b), c),
                             codegen_iv_mul(codegen_iv_point(q->a), s));
    }
    return CODEGEN_OK;
}

/* The coefficients, each one rounding from the exact value (2 b exactly): bound u |out|,
 * raised a little to stay an upper bound. */
static int sigma(const void *p, double *out, double *bound, void *values, double *errors)
{
    const params *q = (const params *)p;
    int i;
    (void)values;
    (void)errors;
    out[0] = q->a + q->c;
    out[1] = 2 * q->b;
    out[2] = q->c - q->a;
    for (i = 0; bound != NULL && i < 3; ++i) {
        bound[i] = i == 1 ? 0 : 0x1.0000000000001p-53 * fabs(out[i]);
    }
    return CODEGEN_OK;
}

static double range_centre(const void *p)
{
    return ((const params *)p)->centre;
}

/* thetaddot of G = a cos + b sin + c; on sign choice 1 (the two-mode model's), b negated */
static double angular_acceleration(const void *p, unsigned signs, double theta, double theta_d)
{
    const params *q = (const params *)p;
    const double b = signs == 0u ? q->b : -q->b;
    return -(q->a * cos(theta) + b * sin(theta) + q->c + q->d * theta_d) / q->m;
}

static codegen_model model_with(int capacity)
{
    codegen_model m;
    memset(&m, 0, sizeof m);
    m.params_size = sizeof(params);
    m.n_modes = 1;
    m.n_branches = 1;
    m.max_roots = capacity;
    m.max_uncertain = MAX_UNCERTAIN;
    m.degree = 2;
    m.periodic = 1;
    m.state.size = STATE;
    m.state.scale = 1;
    m.state.m = 2;
    m.state.b = 3;
    m.state.k = 4;
    m.residual_failure = m.linearisation_failure = m.sigma_failure = CODEGEN_ERR_OVERFLOW;
    m.acceleration_failure = CODEGEN_ERR_OVERFLOW;
    m.check_params = check_params;
    m.equilibrium_state = equilibrium_state;
    m.enclose = enclose;
    m.sigma = sigma;
    m.range_centre = range_centre;
    m.angular_acceleration = angular_acceleration;
    m.analysis.size = sizeof(analysis);
    m.analysis.sigma = offsetof(analysis, sigma);
    m.analysis.n_roots = offsetof(analysis, n_roots);
    m.analysis.roots = offsetof(analysis, roots);
    m.analysis.n_singular = offsetof(analysis, n_singular);
    m.analysis.singular_theta = offsetof(analysis, singular_theta);
    m.analysis.n_unassembled = offsetof(analysis, n_unassembled);
    m.analysis.unassembled_theta = offsetof(analysis, unassembled_theta);
    m.analysis.n_uncertain = offsetof(analysis, n_uncertain);
    m.analysis.uncertain = offsetof(analysis, uncertain);
    m.workspace.call = offsetof(workspace, call);
    m.workspace.result = offsetof(workspace, result);
    m.workspace.polynomial = offsetof(workspace, polynomial);
    m.workspace.roots = offsetof(workspace, roots);
    m.workspace.spans = offsetof(workspace, spans);
    m.workspace.sigma_bound = offsetof(workspace, sigma_bound);
    m.workspace.theta = offsetof(workspace, theta);
    m.workspace.branches = offsetof(workspace, branches);
    m.workspace.enclosure_slots = offsetof(workspace, slots);
    m.workspace.found = offsetof(workspace, found);
    m.workspace.boxes = offsetof(workspace, boxes);
    m.workspace.scratch = offsetof(workspace, scratch);
    m.simulation.params = offsetof(simulation, params);
    m.simulation.options = offsetof(simulation, options);
    m.simulation.state = offsetof(simulation, state);
    m.simulation.work = offsetof(simulation, work);
    m.simulation.signs = offsetof(simulation, signs);
    return m;
}

/* The two-mode model: mode 1 is mode 0 with b negated. */
static double g_mode(const params *q, unsigned mode, double theta)
{
    return q->a * cos(theta) + (mode == 0u ? q->b : -q->b) * sin(theta) + q->c;
}

static void modes_state(const void *p, double theta, double *out)
{
    equilibrium_state(p, theta, out);
    out[5] = ((const params *)p)->absent != 0 ? NAN : g_mode((const params *)p, 0u, theta);
    out[6] = g_mode((const params *)p, 1u, theta);
}

static void modes_linearisation(const void *p, double theta, double *out)
{
    const params *q = (const params *)p;
    out[0] = out[1] = q->m;
    out[2] = out[3] = q->d;
    out[4] = -q->a * sin(theta) + q->b * cos(theta);
    out[5] = -q->a * sin(theta) - q->b * cos(theta);
    if (q->absent != 0) {
        out[0] = out[2] = out[4] = NAN;
    }
}

static int modes_enclose(const void *context, unsigned mode, codegen_iv theta, codegen_iv *g,
                         codegen_iv *dg, unsigned *flags)
{
    const params *q = (const params *)((const codegen_enclosure_context *)context)->params;
    const codegen_iv c = codegen_iv_cos(theta), s = codegen_iv_sin(theta);
    const double b = mode == 0u ? q->b : -q->b;
    if (mode > 1u) {
        return CODEGEN_ERR_ARGUMENT;
    }
    *flags = mode == 0u && q->absent != 0 ? CODEGEN_IV_OUTSIDE : 0u;
    *g = codegen_iv_add(codegen_iv_add(codegen_iv_mul(codegen_iv_point(q->a), c),
                                       codegen_iv_mul(codegen_iv_point(b), s)),
                        codegen_iv_point(q->c));
    if (dg != NULL) {
        *dg = codegen_iv_sub(codegen_iv_mul(codegen_iv_point(b), c),
                             codegen_iv_mul(codegen_iv_point(q->a), s));
    }
    return CODEGEN_OK;
}

/* The condition on each mode, then their scales. */
static void modes_conditions(const void *p, double theta, double *out)
{
    const params *q = (const params *)p;
    (void)theta;
    out[0] = q->w;
    out[1] = -q->w;
    out[2] = out[3] = fabs(q->w);
}

static unsigned modes_declared_signs(const void *p, double theta);

static codegen_model two_mode_model(void)
{
    static const unsigned identity[2] = {0u, 1u}, bit[1] = {0u};
    codegen_model m = model_with(MAX_ROOTS);
    m.n_modes = m.n_branches = 2;
    m.degree = 0;
    m.sigma = NULL;
    m.mode_of_branch = m.branch_of_mode = identity;
    m.n_conditions = 1;
    m.condition_bit = bit;
    m.state.size = MODES_STATE;
    m.state.branch_residuals = 5;
    m.mode_m = 0;
    m.mode_b = 2;
    m.mode_k = 4;
    m.mode_linearisation_failure = m.branches_failure = CODEGEN_ERR_OVERFLOW;
    m.equilibrium_state = modes_state;
    m.mode_linearisation = modes_linearisation;
    m.assembly_conditions = modes_conditions;
    m.declared_signs = modes_declared_signs;
    m.enclose = modes_enclose;
    return m;
}

static unsigned modes_declared_signs(const void *p, double theta)
{
    const codegen_model model = two_mode_model();
    double conditions[4];
    return codegen_declared_signs(&model, p, theta, conditions);
}

static double next(void)
{
    const char *word = strtok(NULL, " \n");
    return word != NULL ? strtod(word, NULL) : NAN;
}

static params read_params(int with_centre)
{
    params p;
    p.a = next();
    p.b = next();
    p.c = next();
    p.m = next();
    p.d = next();
    p.centre = with_centre ? next() : 0.0;
    p.w = p.absent = 0.0;
    return p;
}

static void analyze(void)
{
    const int route = (int)next(), capacity = (int)next();
    const params p = read_params(1);
    const codegen_model model = model_with(capacity);
    analysis result;
    workspace ws;
    int i, status;
    memset(&result, 0, sizeof result);
    status = codegen_analysis_run(&model, route == 1 ? CODEGEN_ROUTE_ISOLATION : CODEGEN_ROUTE_DEFAULT,
                                  &p, &result, &ws);
    printf("%d %d", status, result.n_roots);
    for (i = 0; i < result.n_roots; ++i) {
        const codegen_equilibrium *e = &result.roots[i];
        printf(" %a %a %a %d %d %d %a %a %a %a %a %a %a %a %a %a %a %a %d %d", e->theta, e->theta_lo,
               e->theta_hi, e->certified, e->genuine, (int)e->kind, e->residual, e->M, e->B, e->K,
               e->omega_n[0], e->omega_n[1], e->zeta[0], e->zeta[1], e->eigen_re[0],
               e->eigen_im[0], e->eigen_re[1], e->eigen_im[1], (int)e->stability, (int)e->damping);
    }
    printf(" %d", result.n_uncertain);
    for (i = 0; i < result.n_uncertain; ++i) {
        printf(" %a %a %d", result.uncertain[i].lo, result.uncertain[i].hi, (int)result.uncertain[i].kind);
    }
    printf(" %a %a %a\n", result.sigma[0], result.sigma[1], result.sigma[2]);
}

static void modes(void)
{
    const codegen_model model = two_mode_model();
    params p = read_params(0);
    analysis result;
    workspace ws;
    int i, status;
    p.w = next();
    p.absent = next();
    memset(&result, 0, sizeof result);
    status = codegen_analysis_run(&model, CODEGEN_ROUTE_ISOLATION, &p, &result, &ws);
    printf("%d %d", status, result.n_roots);
    for (i = 0; i < result.n_roots; ++i) {
        const codegen_equilibrium *e = &result.roots[i];
        printf(" %a %d %u %d %d", e->theta, (int)e->kind, e->mode, e->genuine, e->certified);
    }
    printf("\n");
}

/* simulate (one mode) or simulate_modes (the two-mode model, its condition w after the
 * parameters) */
static void simulate(int two_modes)
{
    static double times[64], theta[64], theta_d[64];
    params p = read_params(0);
    const double w = two_modes ? next() : 0.0, theta0 = next(), theta_d0 = next();
    const codegen_model model = two_modes ? two_mode_model() : model_with(MAX_ROOTS);
    const int count = (int)next();
    simulation s;
    size_t reached = 0, i;
    int status, k;
    p.w = w;
    for (k = 0; k < count && k < 64; ++k) {
        times[k] = next();
    }
    status = codegen_simulate(&model, &s, &p, theta0, theta_d0, times, (size_t)k, NULL, theta,
                              theta_d, &reached);
    printf("%d %d", status, (int)reached);
    for (i = 0; i < reached; ++i) {
        printf(" %a %a", theta[i], theta_d[i]);
    }
    printf("\n");
}

static void rk4(void)
{
    const params p = read_params(0);
    const double h = next(), theta = next(), theta_d = next();
    const codegen_model model = model_with(MAX_ROOTS);
    double out = NAN, out_d = NAN;
    const int status = codegen_rk4_step(&model, &p, h, theta, theta_d, &out, &out_d);
    printf("%d %a %a\n", status, out, out_d);
}

static void null_pointers(void)
{
    const codegen_model model = model_with(MAX_ROOTS);
    const params p = {1, 0, 0, 1, 1, 0, 0, 0};
    analysis result;
    workspace ws;
    simulation s;
    double t = 0, y = 0;
    printf("%d %d %d %d %d\n", codegen_analysis_run(&model, CODEGEN_ROUTE_DEFAULT, NULL, &result, &ws),
           codegen_analysis_run(&model, CODEGEN_ROUTE_DEFAULT, &p, NULL, &ws),
           codegen_analysis_run(&model, CODEGEN_ROUTE_ISOLATION, &p, &result, NULL),
           codegen_simulation_start(&model, NULL, &p, 0, 0, 0, NULL),
           codegen_simulate(&model, &s, &p, 0, 0, &t, 1, NULL, NULL, &y, NULL));
}

int main(void)
{
    char line[4096];
    while (fgets(line, sizeof line, stdin) != NULL) {
        const char *command = strtok(line, " \n");
        if (command == NULL) {
            printf("?\n");
        } else if (strcmp(command, "analyze") == 0) {
            analyze();
        } else if (strcmp(command, "simulate") == 0) {
            simulate(0);
        } else if (strcmp(command, "simulate_modes") == 0) {
            simulate(1);
        } else if (strcmp(command, "rk4") == 0) {
            rk4();
        } else if (strcmp(command, "modes") == 0) {
            modes();
        } else if (strcmp(command, "null") == 0) {
            null_pointers();
        } else {
            printf("?\n");
        }
        fflush(stdout);
    }
    return 0;
}
