/* Side-by-side timing driver for one generated library; no mechanism is named here.
 *
 * benchmarks/run.py (`make bench`) compiles it once per shipped mechanism, with
 *   -DPREFIX=doughty -DPREFIX_UPPER=DOUGHTY -DBENCH_HEADER='"doughty.h"'
 *   -DKERNELS_HEADER='"doughty_kernels.h"' -DTHETADDOT=doughty_angular_acceleration
 *   -DHAS_POLYNOMIAL=1
 * and links it with the library and with naive.c, which the runner writes: SymPy's ccode
 * (after sympy.cse) of the same thetaddot and sigma_i the library computes, as
 * naive_thetaddot() and naive_sigma(). The library is timed twice: through its public
 * functions, which validate every input on each call, and through the unchecked kernels
 * behind them (PREFIX_kernels.h), the like-for-like with naive code. Both sides loop over the same inputs, read from
 * files the runner writes:
 *
 *   bench PARAMS N_SETS STATES N_STATES REPEATS MIN_SECONDS OUT
 *
 * PARAMS holds N_SETS parameter structs (raw doubles, the C struct's layout), STATES
 * N_STATES (theta, theta_d) pairs (state i uses set i % N_SETS). The timings go to stdout
 * as one JSON object (each the median of REPEATS samples, every sample at least
 * MIN_SECONDS long); OUT receives the library's sigma of every set and its count of real
 * roots, for numpy.roots to be compared on the very same coefficients. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include BENCH_HEADER
#include KERNELS_HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define LIB(name) CAT(PREFIX, name)         /* LIB(_analyze): doughty_analyze */
#define SIZE(name) CAT(PREFIX_UPPER, name)  /* SIZE(_N_SIGMA): DOUGHTY_N_SIGMA */
#define THETADDOT_KERNEL CAT(THETADDOT, _kernel)

typedef LIB(_params) params_t;
typedef LIB(_analysis) analysis_t;

/* naive.c, written by the runner */
double naive_thetaddot(const params_t *p, double theta, double theta_d);
#if HAS_POLYNOMIAL
void naive_sigma(const params_t *p, double *sigma);
#define N_SIGMA SIZE(_N_SIGMA)
#endif

typedef struct bench_data {
    size_t n_sets, n_states;
    const params_t *params;
    const double *states;  /* theta, theta_d pairs */
    double *sigma;         /* n_sets x N_SIGMA, the library's (filled before the roots run) */
    double *bound;         /* n_sets x N_SIGMA, a bound on each coefficient's error */
    analysis_t *results;   /* n_sets results of _analyze (for the enclosures' pass) */
    analysis_t *analysis;  /* one result, reused */
    int repeats;           /* samples per timing */
    double min_seconds;    /* shortest sample */
} bench_data;

/* now(), median() and ns_per_item() over this driver's bench_data */
#include "timing.h"

static double pass_analyze(const bench_data *d)
{
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i)
        if (LIB(_analyze)(&d->params[i], d->analysis) == 0) sum += d->analysis->n_roots;
    return sum;
}

static double pass_isolate(const bench_data *d)
{
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i)
        if (LIB(_isolate)(&d->params[i], d->analysis) == 0) sum += d->analysis->n_roots;
    return sum;
}

static double pass_thetaddot_library(const bench_data *d)
{
    double sum = 0.0, out = 0.0;
    size_t i;
    for (i = 0; i < d->n_states; ++i) {
        THETADDOT(&d->params[i % d->n_sets], d->states[2 * i], d->states[2 * i + 1], &out);
        sum += out;
    }
    return sum;
}

static double pass_thetaddot_kernel(const bench_data *d)
{
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_states; ++i)
        sum += THETADDOT_KERNEL(&d->params[i % d->n_sets], d->states[2 * i], d->states[2 * i + 1]);
    return sum;
}

static double pass_thetaddot_naive(const bench_data *d)
{
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_states; ++i)
        sum += naive_thetaddot(&d->params[i % d->n_sets], d->states[2 * i], d->states[2 * i + 1]);
    return sum;
}

/* max |naive - library| / |library| over the states where the library succeeds */
static double thetaddot_difference(const bench_data *d)
{
    double worst = 0.0, out, naive;
    size_t i;
    for (i = 0; i < d->n_states; ++i) {
        const params_t *p = &d->params[i % d->n_sets];
        if (THETADDOT(p, d->states[2 * i], d->states[2 * i + 1], &out) != 0 || out == 0.0)
            continue;
        naive = naive_thetaddot(p, d->states[2 * i], d->states[2 * i + 1]);
        worst = fmax(worst, isfinite(naive) ? fabs(naive - out) / fabs(out) : INFINITY);
    }
    return worst;
}

#if HAS_POLYNOMIAL
typedef void (*sigma_fn)(const params_t *p, double *sigma);

/* A timed pass over every set through one sigma function (params, out): the checked entry
 * (its status ignored), its unchecked kernel, the working-precision kernel, naive_sigma. */
#define SIGMA_PASS(pass, call)                                   \
    static double pass(const bench_data *d)                      \
    {                                                            \
        double sum = 0.0, sigma[N_SIGMA];                        \
        size_t i;                                                \
        for (i = 0; i < d->n_sets; ++i) {                        \
            (void)call(&d->params[i], sigma);                    \
            sum += sigma[N_SIGMA / 2];                           \
        }                                                        \
        return sum;                                              \
    }
SIGMA_PASS(pass_sigma_library, LIB(_sigma))
SIGMA_PASS(pass_sigma_kernel, LIB(_sigma_kernel))
SIGMA_PASS(pass_sigma_fast, LIB(_sigma_fast_kernel))
SIGMA_PASS(pass_sigma_naive, naive_sigma)

/* max_i |other_i - library_i| / max_i |library_i| (other: naive_sigma or the working-precision
 * kernel): the coefficients span many orders of magnitude and cancel in the low ones, so
 * each is measured against the largest. */
static double sigma_difference(const bench_data *d, sigma_fn other)
{
    double worst = 0.0, library[N_SIGMA], theirs[N_SIGMA], size, diff;
    size_t i;
    int j;
    for (i = 0; i < d->n_sets; ++i) {
        if (LIB(_sigma)(&d->params[i], library) != 0) continue;
        other(&d->params[i], theirs);
        size = diff = 0.0;
        for (j = 0; j < N_SIGMA; ++j) {
            size = fmax(size, fabs(library[j]));
            diff = fmax(diff, isfinite(theirs[j]) ? fabs(theirs[j] - library[j]) : INFINITY);
        }
        if (size > 0.0) worst = fmax(worst, diff / size);
    }
    return worst;
}

static double pass_roots(const bench_data *d)
{
    double sum = 0.0, theta[SIZE(_MAX_ROOTS)];
    int n = 0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i)
        if (LIB(_poly_real_roots)(&d->sigma[i * N_SIGMA], theta, &n) == 0) sum += n;
    return sum;
}

/* ---- the certificate's parts (section 1's share): what the proof adds to an analysis ---- */

/* sigma by the double-double program with the running bound on each coefficient, which
 * the analysis runs; pass_sigma_kernel is the same program without the bound. The bounded
 * coefficients of every set are kept for pass_spans. */
static double pass_sigma_bounds(const bench_data *d)
{
    static LIB(_workspace) w;
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i) {
        LIB(_sigma_bounds_kernel_work)(&d->params[i], &d->sigma[i * N_SIGMA],
                                       &d->bound[i * N_SIGMA], w.sigma_values, w.sigma_errors);
        sum += d->bound[i * N_SIGMA];
    }
    return sum;
}

/* Every root of each polynomial in a disc, the discs that meet the axis as spans: the
 * certified root finding the analysis runs (pass_roots: the real roots without proof). */
static double pass_spans(const bench_data *d)
{
    static double work[CODEGEN_ROOTS_WORK(SIZE(_DEGREE))];
    codegen_root_span spans[SIZE(_DEGREE)];
    double sum = 0.0;
    int n = 0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i)
        if (codegen_poly_root_spans(&d->sigma[i * N_SIGMA], &d->bound[i * N_SIGMA], SIZE(_DEGREE),
                                    spans, &n, work) == CODEGEN_ROOTS_OK) sum += n;
    return sum;
}

/* The enclosures of G that decide the spans, as analyze_by_spans runs them for a simple
 * span: on the mode of the root found there, G over the span and at its two ends; on each
 * other mode (and on every mode for an extraneous root) G over the span alone. Run at the
 * intervals of the results of _analyze (d->results), which is what the proof evaluates,
 * after the operations of the parameters alone, once per set, as the analysis runs them. */
static double pass_enclosures(const bench_data *d)
{
    static codegen_iv slots[SIZE(_ENCLOSURE_SLOTS)];
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i) {
        const analysis_t *r = &d->results[i];
        int j;
        (void)LIB(_enclosure_prepare)(&d->params[i], slots);
        for (j = 0; j < r->n_roots; ++j) {
            const codegen_equilibrium *e = &r->roots[j];
            const int proven = e->kind == CODEGEN_EQUILIBRIUM || e->kind == CODEGEN_OTHER_ASSEMBLY;
            const unsigned own = e->kind == CODEGEN_OTHER_ASSEMBLY ? e->mode % SIZE(_N_MODES) : 0u;
            const codegen_iv span = codegen_iv_make(e->theta_lo, e->theta_hi);
            codegen_iv g;
            unsigned mode, flags;
            for (mode = 0u; mode < SIZE(_N_MODES); ++mode) {
                (void)LIB(_enclosure_kernel_prepared)(&d->params[i], mode, span, &g, NULL, &flags, slots);
                sum += g.hi;
                if (proven && mode == own) {
                    (void)LIB(_enclosure_kernel_prepared)(&d->params[i], mode, codegen_iv_point(e->theta_lo), &g, NULL, &flags, slots);
                    sum += g.hi;
                    (void)LIB(_enclosure_kernel_prepared)(&d->params[i], mode, codegen_iv_point(e->theta_hi), &g, NULL, &flags, slots);
                    sum += g.hi;
                }
            }
        }
    }
    return sum;
}

/* The library's sigma of every set (NaN where it fails), then its count of real roots of
 * each (-1 where the root finder fails), as doubles. */
static int write_roots(bench_data *d, const char *path)
{
    double theta[SIZE(_MAX_ROOTS)], count;
    int n = 0;
    size_t i;
    FILE *out = fopen(path, "wb");
    if (out == NULL) return 1;
    for (i = 0; i < d->n_sets; ++i)
        if (LIB(_sigma)(&d->params[i], &d->sigma[i * N_SIGMA]) != 0)
            d->sigma[i * N_SIGMA] = NAN;
    fwrite(d->sigma, sizeof(double), d->n_sets * N_SIGMA, out);
    for (i = 0; i < d->n_sets; ++i) {
        count = LIB(_poly_real_roots)(&d->sigma[i * N_SIGMA], theta, &n) == 0 ? n : -1;
        fwrite(&count, sizeof count, 1, out);
    }
    return fclose(out) != 0;
}
#endif

/* A JSON member; a non-finite value is null (JSON has no NaN). */
static void member(const char *name, double value, int last)
{
    if (isfinite(value)) printf("  \"%s\": %.17g%s\n", name, value, last ? "" : ",");
    else printf("  \"%s\": null%s\n", name, last ? "" : ",");
}

static void *read_file(const char *path, size_t size)
{
    void *data = malloc(size);
    FILE *in = fopen(path, "rb");
    if (data == NULL || in == NULL || fread(data, 1, size, in) != size) {
        fprintf(stderr, "bench: cannot read %zu bytes from %s\n", size, path);
        exit(2);
    }
    fclose(in);
    return data;
}

int main(int argc, char **argv)
{
    bench_data d;
    if (argc != 8) {
        fprintf(stderr, "usage: %s PARAMS N_SETS STATES N_STATES REPEATS MIN_SECONDS OUT\n",
                argv[0]);
        return 2;
    }
    d.n_sets = (size_t)strtoul(argv[2], NULL, 10);
    d.n_states = (size_t)strtoul(argv[4], NULL, 10);
    d.repeats = atoi(argv[5]);
    d.min_seconds = atof(argv[6]);
    if (d.n_sets == 0 || d.n_states == 0 || d.repeats < 1 || d.repeats > MAX_REPEATS) {
        fprintf(stderr, "bench: need N_SETS, N_STATES > 0 and 1 <= REPEATS <= %d\n", MAX_REPEATS);
        return 2;
    }
    d.params = read_file(argv[1], d.n_sets * sizeof(params_t));
    d.states = read_file(argv[3], d.n_states * 2 * sizeof(double));
    d.analysis = malloc(sizeof *d.analysis);
    d.sigma = NULL;
    if (d.analysis == NULL) return 2;
    printf("{\n");
    member("analyze_ns", ns_per_item(pass_analyze, &d, d.n_sets), 0);
    member("isolate_ns", ns_per_item(pass_isolate, &d, d.n_sets), 0);
    member("thetaddot_library_ns", ns_per_item(pass_thetaddot_library, &d, d.n_states), 0);
    member("thetaddot_kernel_ns", ns_per_item(pass_thetaddot_kernel, &d, d.n_states), 0);
    member("thetaddot_naive_ns", ns_per_item(pass_thetaddot_naive, &d, d.n_states), 0);
    member("thetaddot_max_rel_diff", thetaddot_difference(&d), 0);
#if HAS_POLYNOMIAL
    d.sigma = malloc(d.n_sets * N_SIGMA * sizeof(double));
    if (d.sigma == NULL || write_roots(&d, argv[7]) != 0) return 2;
    member("sigma_library_ns", ns_per_item(pass_sigma_library, &d, d.n_sets), 0);
    member("sigma_kernel_ns", ns_per_item(pass_sigma_kernel, &d, d.n_sets), 0);
    member("sigma_fast_ns", ns_per_item(pass_sigma_fast, &d, d.n_sets), 0);
    member("sigma_naive_ns", ns_per_item(pass_sigma_naive, &d, d.n_sets), 0);
    member("sigma_max_rel_diff", sigma_difference(&d, naive_sigma), 0);
    member("sigma_fast_max_rel_diff", sigma_difference(&d, LIB(_sigma_fast_kernel)), 0);
    member("roots_ns", ns_per_item(pass_roots, &d, d.n_sets), 0);
    d.bound = malloc(d.n_sets * N_SIGMA * sizeof(double));
    d.results = malloc(d.n_sets * sizeof *d.results);
    if (d.bound == NULL || d.results == NULL) return 2;
    for (size_t i = 0; i < d.n_sets; ++i)
        if (LIB(_analyze)(&d.params[i], &d.results[i]) != 0) d.results[i].n_roots = 0;
    member("sigma_bounds_ns", ns_per_item(pass_sigma_bounds, &d, d.n_sets), 0);
    member("spans_ns", ns_per_item(pass_spans, &d, d.n_sets), 0);
    member("enclosures_ns", ns_per_item(pass_enclosures, &d, d.n_sets), 0);
#endif
    member("checksum", checksum, 1);
    printf("}\n");
    return 0;
}
