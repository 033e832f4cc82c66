/* Timing driver for one generated library of a mechanism with n coordinates (a multibody
 * library: templates/multibody.h.j2); no mechanism is named here.
 *
 * benchmarks/multibody.py (section 8 of `make bench`) compiles it once per such mechanism,
 * with
 *   -DPREFIX=double_pendulum -DPREFIX_UPPER=DOUBLE_PENDULUM
 *   -DBENCH_HEADER='"double_pendulum.h"'
 * and links it with the library (generated/NAME/NAME.c and every .c of generated/runtime):
 *
 *   multibody_bench PARAMS N_SETS REPEATS MIN_SECONDS OUT
 *
 * PARAMS holds N_SETS parameter structs (raw doubles, the C struct's layout). Timed, each the
 * median of REPEATS samples, every sample at least MIN_SECONDS long (ns per item):
 *
 *   analyze_ns    PREFIX_analyze, per parameter set;
 *   modes_ns      PREFIX_modes (the checked entry: M, B and K at theta, then the modes) at
 *                 every equilibrium analyze found, per call (their mean);
 *   modes_max_ns  the same at the slowest single equilibrium (each timed alone, samples of
 *                 MIN_SECONDS / 10);
 *   mb_modes_ns   the runtime's codegen_mb_modes on M, B and K computed beforehand, per call.
 *
 * The timings go to stdout as one JSON object; OUT receives what PREFIX_analyze found for
 * each set, as doubles, one record per set:
 *   status, n_equilibria, n_uncertain, theta[MAX_EQ * N], lo[MAX_EQ * N], hi[MAX_EQ * N],
 *   omega_squared[MAX_EQ * N], stability[MAX_EQ], uncertain_lo[MAX_UNC * N],
 *   uncertain_hi[MAX_UNC * N]
 * (N = N_DOF, MAX_EQ = MAX_EQUILIBRIA, MAX_UNC = MAX_UNCERTAIN; unused entries NaN). */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include BENCH_HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define LIB(name) CAT(PREFIX, name)         /* LIB(_analyze): double_pendulum_analyze */
#define SIZE(name) CAT(PREFIX_UPPER, name)  /* SIZE(_N_DOF): DOUBLE_PENDULUM_N_DOF */
#define N SIZE(_N_DOF)
#define N_MATRIX SIZE(_N_MATRIX)
#define N_EIG SIZE(_N_EIGENVALUES)
#define MAX_EQ SIZE(_MAX_EQUILIBRIA)
#define MAX_UNC SIZE(_MAX_UNCERTAIN)
#define RECORD (3 + 4 * MAX_EQ * N + MAX_EQ + 2 * MAX_UNC * N)
#define MODES_WORK (CODEGEN_DAMPED_EIGENVALUES_WORK(N) + CODEGEN_MODES_WORK(N))

typedef LIB(_params) params_t;
typedef LIB(_analysis) analysis_t;

/* One equilibrium: its parameter set, its coordinates, and M, B, K there. */
typedef struct point {
    const params_t *params;
    double theta[N];
    double M[N_MATRIX], B[N_MATRIX], K[N_MATRIX];
} point;

typedef struct bench_data {
    size_t n_sets, n_points;
    const params_t *params;
    analysis_t *analysis;  /* one result, reused */
    const point *points;   /* every equilibrium of every set (or one, timed alone) */
    int repeats;
    double min_seconds;
} bench_data;

/* now(), median() and ns_per_item() over this driver's bench_data */
#include "timing.h"

static double pass_analyze(const bench_data *d)
{
    double sum = 0.0;
    size_t i;
    for (i = 0; i < d->n_sets; ++i)
        if (LIB(_analyze)(&d->params[i], d->analysis) == 0) sum += d->analysis->n_equilibria;
    return sum;
}

static double pass_modes(const bench_data *d)
{
    double sum = 0.0, omega_squared[N], shapes[N_MATRIX], s_re[N_EIG], s_im[N_EIG],
           zeta[N_EIG], modal[N];
    int stability = 0;
    size_t i;
    for (i = 0; i < d->n_points; ++i)
        if (LIB(_modes)(d->points[i].params, d->points[i].theta, omega_squared, shapes, s_re,
                        s_im, zeta, modal, &stability) == 0)
            sum += omega_squared[0] + s_re[0] + stability;
    return sum;
}

static double pass_mb_modes(const bench_data *d)
{
    double sum = 0.0, omega_squared[N], shapes[N_MATRIX], s_re[N_EIG], s_im[N_EIG],
           zeta[N_EIG], modal[N], work[MODES_WORK];
    int stability = 0;
    size_t i;
    for (i = 0; i < d->n_points; ++i) {
        const point *p = &d->points[i];
        if (codegen_mb_modes(N, p->M, p->B, p->K, omega_squared, shapes, s_re, s_im, zeta,
                             modal, &stability, work) == 0)
            sum += omega_squared[0] + s_re[0] + stability;
    }
    return sum;
}

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
        fprintf(stderr, "multibody_bench: cannot read %zu bytes from %s\n", size, path);
        exit(2);
    }
    fclose(in);
    return data;
}

/* Analyse every set once: its record into OUT, its equilibria (with M, B, K) into points.
 * Returns the number of equilibria, or -1 on an I/O failure. */
static long collect(const bench_data *d, point *points, const char *path)
{
    double record[RECORD];
    long count = 0;
    size_t i;
    int r, k, failed = 0;
    FILE *out = fopen(path, "wb");
    if (out == NULL) return -1;
    for (i = 0; i < d->n_sets; ++i) {
        const analysis_t *a = d->analysis;
        const int status = LIB(_analyze)(&d->params[i], d->analysis);
        double *theta = record + 3, *lo = theta + MAX_EQ * N, *hi = lo + MAX_EQ * N;
        double *omega_squared = hi + MAX_EQ * N, *stability = omega_squared + MAX_EQ * N;
        double *u_lo = stability + MAX_EQ, *u_hi = u_lo + MAX_UNC * N;
        for (k = 0; k < RECORD; ++k) record[k] = NAN;
        record[0] = status;
        record[1] = status == 0 ? a->n_equilibria : 0;
        record[2] = status == 0 ? a->n_uncertain : 0;
        if (status == 0) {
            for (r = 0; r < a->n_equilibria; ++r) {
                point *p = &points[count++];
                p->params = &d->params[i];
                for (k = 0; k < N; ++k) {
                    theta[r * N + k] = p->theta[k] = a->theta[r * N + k];
                    lo[r * N + k] = a->lo[r * N + k];
                    hi[r * N + k] = a->hi[r * N + k];
                    omega_squared[r * N + k] = a->omega_squared[r * N + k];
                }
                stability[r] = a->stability[r];
                failed |= LIB(_mass_matrix)(p->params, p->theta, p->M) != 0
                          || LIB(_damping_matrix)(p->params, p->theta, p->B) != 0
                          || LIB(_stiffness_matrix)(p->params, p->theta, p->K) != 0;
            }
            for (r = 0; r < a->n_uncertain; ++r)
                for (k = 0; k < N; ++k) {
                    u_lo[r * N + k] = a->uncertain_lo[r * N + k];
                    u_hi[r * N + k] = a->uncertain_hi[r * N + k];
                }
        }
        fwrite(record, sizeof(double), RECORD, out);
    }
    if (fclose(out) != 0 || failed) return -1;
    return count;
}

int main(int argc, char **argv)
{
    bench_data d, one;
    point *points;
    long count;
    size_t i;
    double slowest = 0.0;
    if (argc != 6) {
        fprintf(stderr, "usage: %s PARAMS N_SETS REPEATS MIN_SECONDS OUT\n", argv[0]);
        return 2;
    }
    d.n_sets = (size_t)strtoul(argv[2], NULL, 10);
    d.repeats = atoi(argv[3]);
    d.min_seconds = atof(argv[4]);
    if (d.n_sets == 0 || d.repeats < 1 || d.repeats > MAX_REPEATS) {
        fprintf(stderr, "multibody_bench: need N_SETS > 0 and 1 <= REPEATS <= %d\n",
                MAX_REPEATS);
        return 2;
    }
    d.params = read_file(argv[1], d.n_sets * sizeof(params_t));
    d.analysis = malloc(sizeof *d.analysis);
    points = malloc(d.n_sets * MAX_EQ * sizeof *points);
    if (d.analysis == NULL || points == NULL) return 2;
    count = collect(&d, points, argv[5]);
    if (count < 0) {
        fprintf(stderr, "multibody_bench: cannot write %s, or M, B, K failed\n", argv[5]);
        return 2;
    }
    d.points = points;
    d.n_points = (size_t)count;
    printf("{\n");
    member("analyze_ns", ns_per_item(pass_analyze, &d, d.n_sets), 0);
    member("equilibria", (double)count, 0);
    if (count > 0) {
        member("modes_ns", ns_per_item(pass_modes, &d, d.n_points), 0);
        member("mb_modes_ns", ns_per_item(pass_mb_modes, &d, d.n_points), 0);
        one = d;
        one.n_points = 1;
        one.min_seconds = d.min_seconds / 10;
        for (i = 0; i < d.n_points; ++i) {
            one.points = &points[i];
            slowest = fmax(slowest, ns_per_item(pass_modes, &one, 1));
        }
        member("modes_max_ns", slowest, 0);
    }
    member("checksum", checksum, 1);
    printf("}\n");
    return 0;
}
