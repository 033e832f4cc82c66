/* Drives every entry point of the library over the Table 2 case and thousands of random and
 * hostile parameter sets and states (NaN, inf, zero, huge, denormal, negative), for
 * `make sanitize` (-fsanitize=address,undefined). It checks the library's contract as it goes:
 * a status in range, outputs untouched on failure, and no NaN behind DOUGHTY_OK.
 * Usage: sanitize_driver [count] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "doughty.h"

#define SENTINEL 12345.678

typedef struct rng {
    unsigned long long s;
} rng;

static double uniform(rng *r)
{
    r->s ^= r->s << 13;
    r->s ^= r->s >> 7;
    r->s ^= r->s << 17;
    return (double)(r->s >> 11) * (1.0 / 9007199254740992.0);
}

static double hostile(rng *r, double typical)
{
    static const double special[] = {0.0, -0.0, 1e308, -1e308, 1e-308, 4.9e-324, -1.0, 1e-12};
    const double u = uniform(r);
    if (u < 0.04) {
        return NAN;
    }
    if (u < 0.08) {
        return u < 0.06 ? INFINITY : -INFINITY;
    }
    if (u < 0.25) {
        return special[(int)(uniform(r) * 8.0) % 8];
    }
    return typical * (0.2 + 2.0 * uniform(r)) * (uniform(r) < 0.1 ? -1.0 : 1.0);
}

static int failures = 0;

static void expect(int ok, const char *what, int item)
{
    if (!ok) {
        ++failures;
        if (failures < 20) {
            fprintf(stderr, "contract broken: %s (item %d)\n", what, item);
        }
    }
}

/* On success every output is finite; on failure every output still holds the sentinel. */
static void check_outputs(doughty_status s, const double *out, int n, const char *what, int item)
{
    int i;
    expect((int)s >= 0 && (int)s <= DOUGHTY_ERR_B_NEGATIVE, what, item);
    expect(doughty_status_message(s) != NULL, what, item);
    for (i = 0; i < n; ++i) {
        expect(s == DOUGHTY_OK ? isfinite(out[i]) : out[i] == SENTINEL, what, item);
    }
}

static void fill(double *v, int n)
{
    int i;
    for (i = 0; i < n; ++i) {
        v[i] = SENTINEL;
    }
}

static void exercise(const doughty_params *p, rng *r, int item)
{
    double q[DOUGHTY_N_COORDS], qd[DOUGHTY_N_COORDS], qdd[DOUGHTY_N_COORDS];
    double lam[DOUGHTY_N_CONSTRAINTS], out[64], roots[DOUGHTY_MAX_ROOTS];
    const double theta = hostile(r, 3.0), theta_d = hostile(r, 10.0);
    int i, n = -1;
    doughty_status s;
    doughty_analysis analysis;
    for (i = 0; i < DOUGHTY_N_COORDS; ++i) {
        q[i] = hostile(r, 1.0);
        qd[i] = hostile(r, 1.0);
        qdd[i] = hostile(r, 1.0);
    }
    for (i = 0; i < DOUGHTY_N_CONSTRAINTS; ++i) {
        lam[i] = hostile(r, 100.0);
    }
#define RUN(call, count) \
    (fill(out, 64), s = (call), check_outputs(s, out, (count), #call, item))
    RUN(doughty_position_constraints(p, q, out), DOUGHTY_N_CONSTRAINTS);
    RUN(doughty_constraint_jacobian(p, q, out), DOUGHTY_N_JACOBIAN);
    RUN(doughty_velocity_constraints(p, q, qd, out), DOUGHTY_N_CONSTRAINTS);
    RUN(doughty_acceleration_constraints(p, q, qd, qdd, out), DOUGHTY_N_CONSTRAINTS);
    RUN(doughty_point_kinematics(p, q, qd, out, out + 6), 12);
    RUN(doughty_energies(p, q, qd, out, out + 1, out + 2, out + 3), 4);
    RUN(doughty_lagrange_terms(p, q, qd, qdd, lam, out, out + 5, out + 10, out + 15, out + 20,
                               out + 25), 30);
    RUN(doughty_dependent_state(p, theta, theta_d, out, out + 5), 10);
    RUN(doughty_reduced_coefficients(p, theta, out), DOUGHTY_N_REDUCED);
    RUN(doughty_angular_acceleration(p, theta, theta_d, out), 1);
    RUN(doughty_equilibrium_residual(p, theta, out, out + 1), 2);
    RUN(doughty_equilibrium_branches(p, theta, out), DOUGHTY_N_BRANCHES);
    RUN(doughty_radicands(p, theta, out, out + DOUGHTY_N_ROOTS), 2 * DOUGHTY_N_ROOTS);
    RUN(doughty_linearisation(p, theta, out, out + 1, out + 2), 3);
    RUN(doughty_vibration(p, theta, out, out + 1), 2);
    RUN(doughty_sigma(p, out), DOUGHTY_N_SIGMA);
    if (s == DOUGHTY_OK) {
        fill(roots, DOUGHTY_MAX_ROOTS);
        s = doughty_poly_real_roots(out, roots, &n);
        expect(s == DOUGHTY_OK || s == DOUGHTY_ERR_ZERO_POLYNOMIAL, "poly_real_roots", item);
        expect(s != DOUGHTY_OK || (n >= 0 && n <= DOUGHTY_MAX_ROOTS), "root count", item);
        for (i = 0; s == DOUGHTY_OK && i < n; ++i) {
            expect(roots[i] > -3.1415926536 && roots[i] <= 3.1415926536, "root range", item);
        }
    }
    memset(&analysis, 0, sizeof analysis);
    analysis.n_roots = -7;
    s = doughty_analyze(p, &analysis);
    expect(s == DOUGHTY_OK ? analysis.n_roots >= 0 : analysis.n_roots == -7, "analyze", item);
    for (i = 0; s == DOUGHTY_OK && i < analysis.n_roots; ++i) {
        const doughty_equilibrium *e = &analysis.roots[i];
        expect(isfinite(e->theta) && isfinite(e->M) && isfinite(e->B) && isfinite(e->K)
               && !isnan(e->zeta[0]) && !isnan(e->zeta[1]) && isfinite(e->omega_n[0]),
               "analysis values", item);
    }
#undef RUN
}

int main(int argc, char **argv)
{
    const doughty_params table2 = {0.18, 0.9, 0.135, 0.194, 0.143, 9.124,
                                   3500.0, 875.0, 0.15, 110.0, 9.81};
    const int count = argc > 1 ? atoi(argv[1]) : 3000;
    rng r = {0x9E3779B97F4A7C15ULL};
    int item;
    doughty_params batch[4];
    doughty_status statuses[4];
    double out[4 * DOUGHTY_N_SIGMA];
    exercise(&table2, &r, -1);
    for (item = 0; item < count; ++item) {
        doughty_params p = table2;
        double *field = &p.H;
        int j;
        const int victim = (int)(uniform(&r) * DOUGHTY_N_PARAMS) % DOUGHTY_N_PARAMS;
        for (j = 0; j < DOUGHTY_N_PARAMS; ++j) {
            /* most items stay physical so the analysis paths run; every third has one hostile
             * parameter, every ninth has all of them hostile */
            const int bad = item % 9 == 0 || (item % 3 == 0 && j == victim);
            field[j] = bad ? hostile(&r, field[j]) : field[j] * (0.5 + uniform(&r));
        }
        exercise(&p, &r, item);
        batch[item % 4] = p;
        if (item % 4 == 3) {
            doughty_sigma_batch(4, batch, out, statuses);
        }
    }
    expect(doughty_check_params(NULL) == DOUGHTY_ERR_NULL_POINTER, "NULL params", -1);
    expect(doughty_sigma(&table2, NULL) == DOUGHTY_ERR_NULL_POINTER, "NULL output", -1);
    expect(doughty_analyze(NULL, NULL) == DOUGHTY_ERR_NULL_POINTER, "NULL analyze", -1);
    printf("%d parameter sets, %d failed\n", count + 1, failures);
    return failures != 0;
}
