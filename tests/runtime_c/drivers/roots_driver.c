/* Drives codegen_poly_real_roots (runtime/codegen_roots.c) for every degree 1 ..
 * CODEGEN_MAX_DEGREE under AddressSanitizer + UBSan (see
 * tests/runtime_c/test_runtime_roots.py). The coefficients and the outputs live in heap blocks of exactly degree + 1, degree and 1 elements,
 * so any read of sigma beyond sigma[degree] (or before sigma[0]), or any write past theta's
 * degree values, is reported by ASan. Inputs: random dense coefficients (fixed-seed LCG), wide
 * magnitudes with exact zeros, products of known real roots with complex pairs, close pairs and
 * double roots, zero or few-ulp leading/trailing coefficients, and a few extreme vectors.
 * Checked: status OK, 0 <= n_roots <= degree, roots ascending in (-pi, pi], no NaN; the same
 * roots from codegen_poly_real_roots_reference_work (the fast path falls back to it); the error
 * statuses for a bad degree (with NULL pointers: nothing may be read) and a NaN in sigma[degree].
 * Usage: roots_driver [trials per degree]; prints "ok <calls>" and exits 0 on success. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen_runtime.h"

#define PI 3.14159265358979323846

static unsigned long long lcg_state = 0x2545F4914F6CDD1DULL;

static double uniform(void)                      /* in [0, 1) */
{
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(lcg_state >> 11) * (1.0 / 9007199254740992.0);
}

static double symmetric(void)                    /* in [-1, 1) */
{
    return 2.0 * uniform() - 1.0;
}

static int failures = 0;
static long calls = 0;

static void fail(const char *what, int degree, int trial)
{
    ++failures;
    if (failures <= 20) {
        fprintf(stderr, "FAIL: %s (degree %d, trial %d)\n", what, degree, trial);
    }
}

/* c (degree d) times (a tau + b): c must have room for d + 2 values; returns d + 1. */
static int mul_linear(double *c, int d, double a, double b)
{
    c[d + 1] = a * c[d];
    for (int i = d; i >= 1; --i) {
        c[i] = a * c[i - 1] + b * c[i];
    }
    c[0] = b * c[0];
    return d + 1;
}

/* c (degree d) times (tau^2 + p tau + q): room for d + 3 values; returns d + 2. */
static int mul_quadratic(double *c, int d, double p, double q)
{
    c[d + 2] = 0.0;
    c[d + 1] = 0.0;
    for (int i = d; i >= 0; --i) {
        c[i + 2] += c[i];
        c[i + 1] += p * c[i];
        c[i] *= q;
    }
    return d + 2;
}

/* Fill sigma[0..degree] (a block of exactly degree + 1 doubles) by one of several kinds. */
static void fill(double *sigma, int degree, int kind)
{
    double c[CODEGEN_MAX_DEGREE + 3];
    int d = 0;
    switch (kind) {
    case 0:                                      /* dense random */
        for (int i = 0; i <= degree; ++i) {
            sigma[i] = symmetric();
        }
        return;
    case 1:                                      /* wide magnitudes, some exact zeros */
        for (int i = 0; i <= degree; ++i) {
            const double u = uniform();
            sigma[i] = (u < 0.15) ? 0.0 : ldexp(symmetric(), (int)(120.0 * uniform()) - 60);
        }
        if (sigma[degree / 2] == 0.0) {
            sigma[degree / 2] = 1.0;
        }
        return;
    default:                                     /* products of known roots */
        break;
    }
    c[0] = ldexp(1.0 + uniform(), (int)(40.0 * uniform()) - 20);
    while (d < degree) {
        const double u = uniform();
        const int room = degree - d;
        if (room >= 2 && u < 0.3) {              /* complex pair re +- i im */
            const double re = 3.0 * symmetric(), im = 0.05 + 2.0 * uniform();
            d = mul_quadratic(c, d, -2.0 * re, re * re + im * im);
        } else if (room >= 2 && u < 0.45) {      /* double root, or a close pair */
            const double t = tan(0.5 * PI * symmetric());
            const double gap = (kind == 3) ? 1e-4 * (0.5 + uniform()) : 0.0;
            d = mul_linear(c, d, 1.0, -t);
            d = mul_linear(c, d, 1.0, -(t + gap));
        } else if (u < 0.5) {                    /* root on the seam tau = +-1 */
            d = mul_linear(c, d, 1.0, (uniform() < 0.5) ? 1.0 : -1.0);
        } else if (u < 0.55) {                   /* tau = 0 */
            d = mul_linear(c, d, 1.0, 0.0);
        } else if (u < 0.6) {                    /* tau = infinity: degree drop */
            d = mul_linear(c, d, 0.0, 1.0);
        } else {                                 /* simple real root at a random angle */
            const double th = PI * symmetric();
            d = mul_linear(c, d, cos(0.5 * th), -sin(0.5 * th));
        }
    }
    for (int i = 0; i <= degree; ++i) {
        sigma[i] = c[i];
    }
    if (kind == 4) {                             /* few-ulp residues where zeros should be */
        double big = 0.0;
        for (int i = 0; i <= degree; ++i) {
            big = fmax(big, fabs(sigma[i]));
        }
        for (int i = 0; i <= degree; ++i) {
            if (sigma[i] == 0.0 && uniform() < 0.7) {
                sigma[i] = 8.0 * symmetric() * 2.220446049250313e-16 * big;
            }
        }
    }
}

static void check_call(const double *sigma, int degree, int trial)
{
    double *theta = malloc((size_t)degree * sizeof *theta);
    int *n_roots = malloc(sizeof *n_roots);
    if (theta == NULL || n_roots == NULL) {
        fail("malloc", degree, trial);
        free(theta);
        free(n_roots);
        return;
    }
    *n_roots = -1;
    ++calls;
    const codegen_roots_status s = codegen_poly_real_roots(sigma, degree, theta, n_roots);
    if (s != CODEGEN_ROOTS_OK) {
        fail("status not OK", degree, trial);
    } else if (*n_roots < 0 || *n_roots > degree) {
        fail("n_roots out of [0, degree]", degree, trial);
    } else {
        for (int i = 0; i < *n_roots; ++i) {
            if (isnan(theta[i]) || !(theta[i] > -PI && theta[i] <= PI)) {
                fail("root NaN or outside (-pi, pi]", degree, trial);
            }
            if (i > 0 && !(theta[i - 1] < theta[i])) {
                fail("roots not ascending", degree, trial);
            }
        }
    }
    /* The same call in caller-given working memory of exactly CODEGEN_ROOTS_WORK(degree)
     * values (on the heap: the sanitizer sees any access beyond): the same bits. */
    double *work = malloc((size_t)CODEGEN_ROOTS_WORK(degree) * sizeof *work);
    double *theta_w = malloc((size_t)degree * sizeof *theta_w);
    int n_w = -1;
    if (work == NULL || theta_w == NULL) {
        fail("malloc", degree, trial);
    } else if (codegen_poly_real_roots_work(sigma, degree, theta_w, &n_w, work) != s ||
               (s == CODEGEN_ROOTS_OK &&
                (n_w != *n_roots || memcmp(theta_w, theta, (size_t)n_w * sizeof *theta) != 0))) {
        fail("_work differs from codegen_poly_real_roots", degree, trial);
    }
    /* The reference (isolation by derivatives alone), in the same working memory: the fast
     * path answers only where it finds what the reference finds -- the same count, each root
     * within the 4 eps at which the finder itself merges values (its own refinement starts
     * from another bracket, so the last bit may differ). */
    if (work != NULL && theta_w != NULL && s == CODEGEN_ROOTS_OK) {
        n_w = -1;
        if (codegen_poly_real_roots_reference_work(sigma, degree, theta_w, &n_w, work) != s) {
            fail("reference status differs", degree, trial);
        } else if (n_w != *n_roots) {
            fail("reference count differs", degree, trial);
        } else {
            for (int i = 0; i < n_w; ++i) {
                if (!(fabs(theta_w[i] - theta[i]) <= 4.0 * DBL_EPSILON * fmax(1.0, fabs(theta[i])))) {
                    fail("reference roots differ", degree, trial);
                    break;
                }
            }
        }
    }
    free(work);
    free(theta_w);
    free(theta);
    free(n_roots);
}

static void extremes(int degree)
{
    double *sigma = malloc((size_t)(degree + 1) * sizeof *sigma);
    if (sigma == NULL) {
        fail("malloc", degree, -1);
        return;
    }
    const double specials[] = {4.9e-324, 1e-300, 1e300, 1.7976931348623157e308};
    for (int k = 0; k < 4; ++k) {
        for (int i = 0; i <= degree; ++i) {
            sigma[i] = (i % 2 == 0 ? 1.0 : -1.0) * specials[k];
        }
        check_call(sigma, degree, -1 - k);
        for (int i = 0; i <= degree; ++i) {                  /* a single nonzero term */
            sigma[i] = (i == (k * degree) / 3) ? specials[k] : 0.0;
        }
        check_call(sigma, degree, -5 - k);
    }
    /* NaN in the last coefficient that may be read. */
    double theta_dummy = 0.0;
    int n_dummy = -1;
    for (int i = 0; i <= degree; ++i) {
        sigma[i] = 1.0;
    }
    sigma[degree] = NAN;
    if (degree >= 1 && codegen_poly_real_roots(sigma, degree, &theta_dummy, &n_dummy) !=
                           CODEGEN_ROOTS_ERR_NONFINITE) {
        fail("NaN in sigma[degree] not reported", degree, -9);
    }
    free(sigma);
}

int main(int argc, char **argv)
{
    const int trials = (argc > 1) ? atoi(argv[1]) : 100;
    int n = -1;
    double th[1];

    /* A bad degree is reported before anything is read or written. */
    if (codegen_poly_real_roots(NULL, 0, NULL, NULL) != CODEGEN_ROOTS_ERR_DEGREE ||
        codegen_poly_real_roots(NULL, -1, NULL, NULL) != CODEGEN_ROOTS_ERR_DEGREE ||
        codegen_poly_real_roots(NULL, CODEGEN_MAX_DEGREE + 1, th, &n) !=
            CODEGEN_ROOTS_ERR_DEGREE ||
        n != -1) {
        fail("bad degree not reported first", 0, -1);
    }
    if (codegen_poly_real_roots_work(NULL, 0, NULL, NULL, NULL) != CODEGEN_ROOTS_ERR_DEGREE ||
        codegen_poly_real_roots_work(th, 1, th, &n, NULL) != CODEGEN_ROOTS_ERR_NULL_POINTER ||
        n != -1) {
        fail("_work: bad degree or no working memory not reported", 0, -1);
    }
    for (int degree = 1; degree <= CODEGEN_MAX_DEGREE; ++degree) {
        for (int t = 0; t < trials; ++t) {
            double *sigma = malloc((size_t)(degree + 1) * sizeof *sigma);
            if (sigma == NULL) {
                fail("malloc", degree, t);
                continue;
            }
            fill(sigma, degree, t % 5);
            check_call(sigma, degree, t);
            free(sigma);
        }
        extremes(degree);
    }
    if (failures != 0) {
        fprintf(stderr, "%d failures in %ld calls\n", failures, calls);
        return 1;
    }
    printf("ok %ld\n", calls);
    return 0;
}
