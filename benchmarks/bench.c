/* Times the generated library: ns per call of the main entry points, -O2, one core.
 * Built and run by benchmarks/run.py (`make bench`). Inputs vary per call so the compiler
 * cannot hoist the work; a checksum is printed so it cannot drop it. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <time.h>

#include "doughty.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#define TIME(label, calls, body)                                                        \
    do {                                                                                \
        long i_;                                                                        \
        double start_ = now(), ns_;                                                     \
        for (i_ = 0; i_ < (calls); ++i_) {                                              \
            const double x_ = 0.001 * (double)(i_ % 1000);                              \
            (void)x_;                                                                   \
            body;                                                                       \
        }                                                                               \
        ns_ = (now() - start_) * 1e9 / (double)(calls);                                 \
        printf("%-28s %10.1f ns/call\n", label, ns_);                                   \
    } while (0)

int main(void)
{
    doughty_params p = {0.18, 0.9, 0.135, 0.194, 0.143, 9.124, 3500.0, 875.0, 0.15, 110.0, 9.81};
    double sigma[DOUGHTY_N_SIGMA], e[DOUGHTY_N_REDUCED], m, b, k, g, scale;
    double roots[DOUGHTY_MAX_ROOTS];
    double sum = 0.0;
    int n;
    doughty_analysis analysis;
    TIME("doughty_check_params", 2000000, (p.F = 110.0 + x_, sum += doughty_check_params(&p)));
    TIME("doughty_sigma", 2000000, (p.F = 110.0 + x_, doughty_sigma(&p, sigma), sum += sigma[3]));
    TIME("doughty_reduced_coefficients", 2000000,
         (doughty_reduced_coefficients(&p, x_, e), sum += e[DOUGHTY_N_REDUCED - 1]));
    TIME("doughty_equilibrium_residual", 2000000,
         (doughty_equilibrium_residual(&p, x_, &g, &scale), sum += g + scale));
    TIME("doughty_linearisation", 2000000, (doughty_linearisation(&p, x_, &m, &b, &k), sum += k));
    TIME("doughty_poly_real_roots", 20000,
         (p.F = 110.0 + x_, doughty_sigma(&p, sigma), doughty_poly_real_roots(sigma, roots, &n),
          sum += roots[0]));
    TIME("doughty_analyze", 20000,
         (p.F = 110.0 + x_, doughty_analyze(&p, &analysis), sum += analysis.roots[0].K));
    printf("checksum %g\n", sum);
    return 0;
}
