/*
 * codegen_roots.c -- real roots of a polynomial of any degree n in [1, CODEGEN_MAX_DEGREE],
 *     p(tau) = sum_{i=0}^{n} sigma_i tau^i,   tau = tan(theta / 2),
 * reported as angles theta = 2 atan(tau) in (-pi, pi] (see codegen_runtime.h for the contract).
 * Hand-written (not generated); shared by every generated library, whatever the mechanism.
 * Plain C99 + libm; no allocation, no mutable static state, no I/O.
 *
 * Why not companion-matrix eigenvalues (GSL, numpy.roots): they return complex approximations
 * and leave "is this root real?" to an arbitrary tolerance on the imaginary part, which fails
 * in exactly the cases that equilibrium polynomials produce (close pairs such as 5e-4 apart,
 * double roots). Here every real root is isolated by sign changes that are certified against a
 * rounding-error bound:
 *
 * 1. Two charts on bounded intervals, so no root bound is needed and tau = infinity is an
 *    ordinary point: chart A is p(tau) on [-1, 1] (|theta| <= 90 deg); chart B is the reversed
 *    polynomial q(u) = u^m p(1/u) on the open interval (-1, 1) (|theta| > 90 deg; u = 0 is
 *    theta = pi). Both use the input's coefficients unchanged. The seam tau = +-1 belongs to
 *    chart A: chart B takes its endpoint signs from it (q(1) = p(1), q(-1) = (-1)^m p(-1)) and
 *    leaves it any run of untrusted signs touching an endpoint, so a seam root is found once.
 *    A factor cos^2(theta) = ((1 - tau^2) / (1 + tau^2))^2, common in degenerate
 *    configurations of mechanisms, puts double roots exactly on the seam, and rounding in the
 *    coefficients moves f's critical point there a few ulps either way, possibly outside both
 *    charts. So chart A also applies rule 5 at the seam, to the critical point
 *    c = x - f'/f'' of f's quadratic model there when |c - x| <= CR_PAIR. Such a root is
 *    reported on the seam if f' may vanish there within 5(a)'s coefficient uncertainty, else
 *    at c; a split pair straddling the seam is one root.
 * 2. A power-of-two normalisation (exact) removes the overall magnitude; exactly zero low/high
 *    coefficients are stripped: a factor tau^k gives theta = 0, a degree drop (sigma_n = 0)
 *    theta = pi, each reported once whatever the multiplicity.
 * 3. Isolation by recursion on derivatives: the real roots of f' cut [-1, 1] into pieces on
 *    which f is monotone, so a piece holds at most one root, bracketed by a sign change and
 *    found by Newton safeguarded with bisection. Starting from the linear (m-1)-th derivative,
 *    each level's roots are the next level's critical points.
 * 4. Values come from the compensated Horner scheme, as accurate as Horner's rule in twice the
 *    working precision. Plain Horner is not enough: between roots of a close pair (0.03 deg
 *    apart, as real mechanisms produce) the extremum of f can be only ~1e-16..1e-13 of the
 *    terms summed, i.e. at plain Horner's error level, and merging such pairs would lose two
 *    equilibria. (The error-free transformations need IEEE double arithmetic: no -ffast-math,
 *    no x87 extended precision.) Plain Horner (with its rigorous error bound) is used only
 *    where that bound already certifies the outcome: a sign far from zero, or a point clearly
 *    not a root; anything closer is decided by the compensated values.
 * 5. A critical point (or the seam, see 1) is a multiple root (reported once; there is no
 *    sign change to bracket) if |f| there is within the compensated error bound plus f's
 *    variation over the point's own uncertainty, or if both (a) changing each coefficient by
 *    CR_ULPS ulps of the largest one can make f vanish there and (b) the two roots beside it
 *    (real or complex, |x - c| ~ sqrt(2|f|/|f''|)) lie within CR_PAIR of it. Such a pair
 *    cannot be told from a double root whose coefficients carry rounding errors: generated
 *    coefficients come from long expressions, and one that should vanish (from a factor such
 *    as sin^2(theta)) is a residue of terms as large as the other coefficients, hence (a) is
 *    norm-wise. With double roots' coefficients computed in double arithmetic, allowing 1 ulp
 *    missed or doubled 11% of them in trials at degree 12, 16 ulps 0.03%, 64 none; (b) keeps
 *    genuine close pairs separate (a pair 0.03 deg apart in theta is still ~25x farther apart
 *    than CR_PAIR).
 *    Runs of consecutive such points are one root.
 *
 * The degree is a run-time argument, and for every degree exactly sigma[0..degree] is read.
 * Working memory is the caller's (codegen_poly_real_roots_work, CODEGEN_ROOTS_WORK(degree)
 * values: O(degree), so a library of degree 12 needs 1.6 KB of stack in double, not what the
 * largest degree would), or an array of CODEGEN_ROOTS_WORK(CODEGEN_MAX_DEGREE) on the stack
 * (codegen_poly_real_roots).
 */
#include "codegen_runtime.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

#define CR_MAXN CODEGEN_MAX_DEGREE        /* the largest degree codegen_poly_real_roots accepts */
/* Working memory, in values, of level_roots and chart_roots for a chart of degree m; with the
 * coefficients (s, a, q), the roots (r) and the output (out) of codegen_poly_real_roots_work,
 * CODEGEN_ROOTS_WORK(m) = (m + 1) + 2 (m + 1) + m + (2 m + 2) + CHART_WORK(m) = 16 m + 16. */
#define LEVEL_WORK(m) (4 * ((m) + 2))
#define CHART_WORK(m) (3 * ((m) + 1) + 3 * (m) + LEVEL_WORK(m))
#define CR_PI CODEGEN_R(3.14159265358979323846264338327950288)
#define CR_ULPS CODEGEN_R(64.0)                       /* see 5(a) */
#define CR_PAIR CODEGEN_R(1e-5)                       /* see 5(b); in chart units (theta ~ 2 u) */
#define CR_MAXIT 400                       /* iteration cap: ~60 halvings reach full relative
                                              precision; only a root at 0 needs more, and there
                                              Newton converges (fast) */

/* One step s <- s x + a of the compensated Horner scheme below: s + c carries the value, m the
 * sum of |a_i||x|^i; xh + xl = x is x split by codegen_split. The product's rounding error pe
 * comes from fma where the hardware has it (CODEGEN_FAST_FMA); else from Dekker's TwoProduct,
 * equally exact (no overflow can occur here: |s| stays far below CODEGEN_SPLIT_MAX) and much
 * faster than a call to a software fma, around which every floating-point register must be
 * saved. */
static inline void cstep(codegen_real *s, codegen_real *c, codegen_real *m, codegen_real x, codegen_real xh, codegen_real xl,
                         codegen_real ax, codegen_real a)
{
    const codegen_real p = *s * x;
#ifdef CODEGEN_FAST_FMA
    const codegen_real pe = codegen_fma(*s, x, -p);                     /* s * x = p + pe exactly */
    (void)xh;
    (void)xl;
#else
    codegen_real sh, sl;
    codegen_split(*s, &sh, &sl);
    const codegen_real pe = codegen_product_error(p, sh, sl, xh, xl);       /* likewise */
#endif
    const codegen_real t = p + a;
    const codegen_real z = t - p;
    const codegen_real se = (p - (t - z)) + (a - z);           /* p + a = t + se exactly */
    *s = t;
    *c = *c * x + (pe + se);
    *m = *m * ax + codegen_fabs(a);
}

/* f(x) = sum a[i] x^i by the compensated Horner scheme (Graillat, Langlois & Louvet, 2005):
 * error-free transformations (TwoProduct for the product, see cstep; Knuth's TwoSum for the
 * sum) give |result - f(x)| <= u |f(x)| + gamma_{2n}^2 sum |a_i||x|^i. *mag receives
 * sum |a_i||x|^i. */
static codegen_real eval(const codegen_real *a, int n, codegen_real x, codegen_real *mag)
{
    codegen_real s = a[n];
    codegen_real c = 0;
    codegen_real m = codegen_fabs(a[n]);
    const codegen_real ax = codegen_fabs(x);
    codegen_real xh, xl;
    codegen_split(x, &xh, &xl);
    for (int i = n - 1; i >= 0; --i) {
        cstep(&s, &c, &m, x, xh, xl, ax, a[i]);
    }
    *mag = m;
    return s + c;
}

/* f, f' and f'' (degrees n >= 1, n - 1, n - 2; f'' = 0 when n < 2) at x, each exactly as eval
 * computes it, in one loop so that the three independent recurrences overlap. */
static void eval3(const codegen_real *f, const codegen_real *df, const codegen_real *d2f, int n, codegen_real x,
                  codegen_real v[3], codegen_real mag[3])
{
    codegen_real s0 = f[n], s1 = df[n - 1], s2 = (n >= 2) ? d2f[n - 2] : 0;
    codegen_real c0 = 0, c1 = 0, c2 = 0;
    codegen_real m0 = codegen_fabs(s0), m1 = codegen_fabs(s1), m2 = codegen_fabs(s2);
    const codegen_real ax = codegen_fabs(x);
    codegen_real xh, xl;
    codegen_split(x, &xh, &xl);
    int i = n - 1;
    for (; i >= 2; --i) {
        cstep(&s0, &c0, &m0, x, xh, xl, ax, f[i]);
        cstep(&s1, &c1, &m1, x, xh, xl, ax, df[i - 1]);
        cstep(&s2, &c2, &m2, x, xh, xl, ax, d2f[i - 2]);
    }
    for (; i >= 1; --i) {
        cstep(&s0, &c0, &m0, x, xh, xl, ax, f[i]);
        cstep(&s1, &c1, &m1, x, xh, xl, ax, df[i - 1]);
    }
    cstep(&s0, &c0, &m0, x, xh, xl, ax, f[0]);
    v[0] = s0 + c0;
    v[1] = s1 + c1;
    v[2] = s2 + c2;
    mag[0] = m0;
    mag[1] = m1;
    mag[2] = m2;
}

/* f(x) and f'(x) (df: f's derivative, degree n - 1 >= 0) by Horner's rule, two independent
 * recurrences in one loop; each value is within gamma_{2n} <= 4 n eps times its magnitude sum
 * (below) of the truth (Higham, Accuracy and Stability of Numerical Algorithms, 5.1). A value
 * beyond PLAIN_OK's margin has a certain sign and a small relative error. */
#define PLAIN_OK(v, n, mag) (codegen_fabs(v) > CODEGEN_R(4.0) * (codegen_real)(n) * CODEGEN_EPSILON * (mag))
static inline codegen_real horner_fd(const codegen_real *a, const codegen_real *df, int n, codegen_real x, codegen_real *dv)
{
    codegen_real s = a[n], d = df[n - 1];
    for (int i = n - 1; i >= 1; --i) {
        s = s * x + a[i];
        d = d * x + df[i - 1];
    }
    *dv = d;
    return s * x + a[0];
}

/* sum |a_i| r^i: the magnitude sum at |x| = r, and a bound on it wherever |x| <= r. */
static inline codegen_real magnitude(const codegen_real *a, int n, codegen_real r)
{
    codegen_real m = codegen_fabs(a[n]);
    for (int i = n - 1; i >= 0; --i) {
        m = m * r + codegen_fabs(a[i]);
    }
    return m;
}

/* f, f' and f'' as eval3 takes them, by plain Horner's rule, with the sums mag as eval3 gives
 * them; each value is within gamma_{2n} times its mag of the truth (Higham, 5.1). */
static void horner3(const codegen_real *f, const codegen_real *df, const codegen_real *d2f, int n, codegen_real x,
                    codegen_real v[3], codegen_real mag[3])
{
    codegen_real s0 = f[n], s1 = df[n - 1], s2 = (n >= 2) ? d2f[n - 2] : 0;
    codegen_real m0 = codegen_fabs(s0), m1 = codegen_fabs(s1), m2 = codegen_fabs(s2);
    const codegen_real ax = codegen_fabs(x);
    int i = n - 1;
    for (; i >= 2; --i) {
        s0 = s0 * x + f[i];
        s1 = s1 * x + df[i - 1];
        s2 = s2 * x + d2f[i - 2];
        m0 = m0 * ax + codegen_fabs(f[i]);
        m1 = m1 * ax + codegen_fabs(df[i - 1]);
        m2 = m2 * ax + codegen_fabs(d2f[i - 2]);
    }
    for (; i >= 1; --i) {
        s0 = s0 * x + f[i];
        s1 = s1 * x + df[i - 1];
        m0 = m0 * ax + codegen_fabs(f[i]);
        m1 = m1 * ax + codegen_fabs(df[i - 1]);
    }
    v[0] = s0 * x + f[0];
    v[1] = s1;
    v[2] = s2;
    mag[0] = m0 * ax + codegen_fabs(f[0]);
    mag[1] = m1;
    mag[2] = m2;
}

/* Root of f (degree n, derivative df) in (lo, hi), where f is monotone with the trusted sign
 * slo at lo and -slo at hi. Newton steps are taken only while they stay inside the bracket and
 * at least halve the step before last (the rule of Numerical Recipes' rtsafe); else bisect. A
 * Newton step below the resolution of x ends the search. f is evaluated by plain Horner where
 * that certifies its sign, else by the compensated scheme; f' only steers Newton, so plain
 * Horner serves. *del receives the uncertainty of the result: the last step plus the root's
 * sensitivity to a relative change ceps in each coefficient. */
static codegen_real solve(const codegen_real *f, const codegen_real *df, int n, codegen_real ceps, codegen_real lo,
                    codegen_real hi, int slo, codegen_real *del)
{
    codegen_real x = CODEGEN_R(0.5) * (lo + hi);
    codegen_real dx = hi - lo;
    codegen_real dv;
    /* The magnitude sum anywhere in the bracket is at most its value at the farther end: one
     * bound for every iteration; the sum at x itself is formed only where that bound is too
     * coarse to certify the sign. */
    const codegen_real bound = magnitude(f, n, codegen_fmax(codegen_fabs(lo), codegen_fabs(hi)));
    for (int it = 0;; ++it) {
        codegen_real v = horner_fd(f, df, n, x, &dv);
        if (!PLAIN_OK(v, n, bound) && !PLAIN_OK(v, n, magnitude(f, n, codegen_fabs(x)))) {
            codegen_real mag;
            v = eval(f, n, x, &mag);
        }
        if (v == 0) {
            dx = 0;
            break;
        }
        if ((v > 0) == (slo > 0)) {
            lo = x;
        } else {
            hi = x;
        }
        if (it == CR_MAXIT) {
            break;                        /* x, dv: the last point evaluated */
        }
        const codegen_real dxold = dx;
        if (dv != 0) {
            dx = v / dv;
            const codegen_real xn = x - dx;
            if (codegen_fabs(dx) <= CODEGEN_EPSILON * codegen_fabs(x) + CODEGEN_REAL_MIN) {
                /* Newton step below the resolution of x: converged (even if xn rounds onto or
                 * just past an end of the bracket, which the test below would reject). */
                if (xn > lo && xn < hi) {
                    x = xn;
                }
                break;
            }
            if (xn > lo && xn < hi && codegen_fabs(CODEGEN_R(2.0) * dx) <= codegen_fabs(dxold)) {
                x = xn;
                continue;
            }
        }
        dx = CODEGEN_R(0.5) * (hi - lo);
        x = lo + dx;
        if (codegen_fabs(dx) <= CODEGEN_EPSILON * codegen_fabs(x) + CODEGEN_REAL_MIN) {
            break;
        }
    }
    /* dv: from the last evaluation, at most a step below the resolution of x away. */
    codegen_real dmag = magnitude(df, n - 1, codegen_fabs(x));
    if (!PLAIN_OK(dv, n - 1, dmag)) {
        dv = eval(df, n - 1, x, &dmag);
    }
    dv = codegen_fabs(dv);
    const codegen_real mag = magnitude(f, n, codegen_fabs(x));
    *del = codegen_fabs(dx) + ((dv > 0) ? codegen_fmin(ceps * mag / dv, CR_PAIR) : CR_PAIR);
    return x;
}

/* Roots on [-1, 1] of f = d[k] (degree n = m - k; f', f'' follow), given the sorted roots
 * crit[0..nc) of f' with their uncertainties cdel. ceps: uncertainty of f's coefficients in
 * units of their size (5a). Writes sorted roots to rt, uncertainties to rdel; returns their
 * number (at most nc + 1). ends_in != NULL (chart B, level 0): endpoint signs are imposed,
 * and runs of untrusted signs touching an endpoint are left to chart A. ends_out != NULL
 * (chart A, level 0): the endpoints (the seam) are also tested by rule 5; their signs are
 * stored there. */
static int level_roots(const codegen_real *f, const codegen_real *df, const codegen_real *d2f, int n,
                       codegen_real ceps, const codegen_real *crit, const codegen_real *cdel, int nc,
                       const int *ends_in, int *ends_out, codegen_real *rt, codegen_real *rdel,
                       codegen_real *work)
{
    /* nc + 2 points each: where, f there, its uncertainty, and the trusted sign (-1, 1; 0 for
     * a root), in the caller's LEVEL_WORK(m) values */
    const int np = nc + 2;
    codegen_real *const px = work, *const pv = px + np, *const pd = pv + np, *const ps = pd + np;
    const codegen_real g = (codegen_real)n * CODEGEN_EPSILON;                /* gamma_{2n} */
    codegen_real amax = 0;                                       /* largest |coefficient| */
    for (int i = 0; i <= n; ++i) {
        amax = (codegen_fabs(f[i]) > amax) ? codegen_fabs(f[i]) : amax;
    }

    px[0] = -1;
    pd[0] = 0;
    for (int i = 0; i < nc; ++i) {
        px[i + 1] = crit[i];
        pd[i + 1] = cdel[i];
    }
    px[np - 1] = 1;
    pd[np - 1] = 0;

    for (int j = 0; j < np; ++j) {
        codegen_real pw = 0;                                     /* sum |x|^i */
        for (int i = 0; i <= n; ++i) {
            pw = pw * codegen_fabs(px[j]) + 1;
        }
        codegen_real vals[3], mags[3];
        const int inner = j > 0 && j < np - 1;
        if (inner || ends_out == NULL) {
            /* Fast path (all points but the seam's): if plain Horner's values, widened by their
             * error bounds (and a factor 2), show that neither the tolerance test below nor, at
             * a critical point, 5(a)-(b) can hold, the point has a trusted sign and nothing
             * else of it is used. Otherwise (the few points near a root of f) the compensated
             * values decide as below. */
            horner3(f, df, d2f, n, px[j], vals, mags);
            const codegen_real e0 = CODEGEN_R(4.0) * (codegen_real)n * CODEGEN_EPSILON * mags[0];
            const codegen_real vlo = codegen_fabs(vals[0]) - e0;
            const codegen_real d1up = codegen_fabs(vals[1]) + CODEGEN_R(4.0) * (codegen_real)n * CODEGEN_EPSILON * mags[1];
            const codegen_real d2up = codegen_fabs(vals[2]) + CODEGEN_R(4.0) * (codegen_real)n * CODEGEN_EPSILON * mags[2];
            const codegen_real tolup = CODEGEN_EPSILON * (codegen_fabs(vals[0]) + e0) + CODEGEN_R(2.0) * g * g * mags[0] +
                                 (d1up + CODEGEN_R(0.5) * d2up * pd[j]) * pd[j];
            if (vlo > CODEGEN_R(2.0) * tolup && (!inner || vlo > CODEGEN_R(2.0) * ceps * amax * pw ||
                                      vlo > d2up * CR_PAIR * CR_PAIR)) {
                pv[j] = vals[0];
                ps[j] = (vals[0] > 0) ? 1 : -1;
                continue;
            }
        }
        eval3(f, df, d2f, n, px[j], vals, mags);
        const codegen_real v = vals[0];
        const codegen_real mag = mags[0];
        const codegen_real d1s = vals[1];
        const codegen_real d2s = vals[2];
        const codegen_real d1 = codegen_fabs(d1s);
        const codegen_real d2 = codegen_fabs(d2s);
        /* Twice the compensated error bound, plus f's variation over the point's uncertainty. */
        codegen_real tol = CODEGEN_EPSILON * codegen_fabs(v) + CODEGEN_R(2.0) * g * g * mag + (d1 + CODEGEN_R(0.5) * d2 * pd[j]) * pd[j];
        int zero = codegen_fabs(v) <= tol;
        /* Rule 5 at a critical point; in chart A also at the seam, applied to the critical
         * point x + dc of f's quadratic model there (value fc), if it is within CR_PAIR. */
        const int seam = ends_out != NULL && (j == 0 || j == np - 1);
        const codegen_real dc = (seam && d2 > 0) ? -d1s / d2s : 0;
        codegen_real fc = v + CODEGEN_R(0.5) * d1s * dc;
        if (!zero && ((j > 0 && j < np - 1) || (seam && codegen_fabs(dc) <= CR_PAIR)) &&
            codegen_fabs(fc) <= ceps * amax * pw && CODEGEN_R(2.0) * codegen_fabs(fc) <= d2 * CR_PAIR * CR_PAIR) {
            zero = 1;                                        /* 5(a) and 5(b) */
            tol = ceps * amax * pw;
            if (seam && d1 > CODEGEN_R(0.5) * (codegen_real)n * tol) {   /* 5(a) for f' at |x| = 1 fails */
                px[j] += dc;
            } else if (seam) {
                fc = 0;                       /* on the seam: it stands for its run */
            }
        }
        pv[j] = fc;
        ps[j] = zero ? 0 : (v > 0 ? 1 : -1);
        /* Should the point stand for a root, how far that root may be from it. */
        codegen_real est = CR_PAIR;
        if (d1 > 0) {
            est = codegen_fmin(est, tol / d1);
        }
        if (d2 > 0) {
            est = codegen_fmin(est, codegen_sqrt(CODEGEN_R(2.0) * tol / d2));
        }
        pd[j] += est;
    }
    if (ends_in != NULL) {
        ps[0] = (codegen_real)ends_in[0];
        ps[np - 1] = (codegen_real)ends_in[1];
    }
    if (ends_out != NULL) {
        ends_out[0] = (int)ps[0];
        ends_out[1] = (int)ps[np - 1];
    }

    int nr = 0;
    int run_start = -1;          /* first index of the current run of untrusted signs */
    codegen_real best = 0;           /* smallest |f| in that run; its point represents the run */
    for (int j = 0; j < np; ++j) {
        if (ps[j] == 0) {
            if (run_start < 0) {
                run_start = j;
                best = codegen_fabs(pv[j]);
                rt[nr] = px[j];
                rdel[nr] = pd[j];
                ++nr;
            } else if (codegen_fabs(pv[j]) < best) {
                best = codegen_fabs(pv[j]);
                rt[nr - 1] = px[j];
                rdel[nr - 1] = pd[j];
            }
            continue;
        }
        if (run_start >= 0) {
            if (ends_in != NULL && run_start == 0) {
                --nr;            /* seam root already reported by chart A */
            }
            run_start = -1;
        } else if (j > 0 && ps[j - 1] == -ps[j]) {
            rt[nr] = solve(f, df, n, ceps, px[j - 1], px[j], (int)ps[j - 1], &rdel[nr]);
            ++nr;
        }
    }
    if (run_start >= 0 && ends_in != NULL) {
        --nr;                    /* run reaching the right endpoint: chart A's */
    }
    return nr;
}

/* The k-th derivative of c[0..m] into dk[0..m-k]: dk[i] = (i+1) (i+2) ... (i+k) c[i+k], the
 * factors applied from (i+k) down, i.e. bit for bit what differentiating k times one after the
 * other gives. Computed afresh per level (O(m k) products) so that only three derivatives are
 * held at a time: O(m) stack instead of a table of O(m^2). */
static void derivative(const codegen_real *c, int m, int k, codegen_real *dk)
{
    for (int i = 0; i <= m - k; ++i) {
        codegen_real v = c[i + k];
        for (int j = k; j >= 1; --j) {
            v = (codegen_real)(i + j) * v;
        }
        dk[i] = v;
    }
}

/* Roots of c[0..m] (m >= 1) in [-1, 1] (or (-1, 1) when ends_in != NULL), sorted, into roots
 * (room for m values; at most m are written); work: CHART_WORK(m) values. */
static int chart_roots(const codegen_real *c, int m, const int *ends_in, int *ends_out, codegen_real *roots,
                       codegen_real *work)
{
    /* Derivatives k, k+1 and k+2 of the level in hand, rotated as k goes down. */
    codegen_real *f = work, *df = f + (m + 1), *d2f = df + (m + 1);
    codegen_real *const cdel = d2f + (m + 1), *const rt = cdel + m, *const rdel = rt + m;
    codegen_real *const level = rdel + m;      /* LEVEL_WORK(m) */
    codegen_real *crit = roots;                /* each level's roots are the next one's critical points */
    int nc = 0;

    derivative(c, m, m, df);                   /* d2f is first read at k = m - 2 */
    for (int k = m - 1; k >= 0; --k) {
        derivative(c, m, k, f);
        /* d[k]'s coefficients: the input's uncertainty plus one ulp per differentiation. */
        const codegen_real ceps = (CR_ULPS + (codegen_real)k) * CODEGEN_EPSILON;
        const int nr = level_roots(f, df, (k + 2 <= m) ? d2f : df, m - k, ceps, crit, cdel, nc,
                                   k == 0 ? ends_in : NULL, k == 0 ? ends_out : NULL,
                                   rt, rdel, level);
        for (int i = 0; i < nr; ++i) {
            crit[i] = rt[i];
            cdel[i] = rdel[i];
        }
        nc = nr;
        codegen_real *const spare = d2f;         /* d[k+2] is done with */
        d2f = df;
        df = f;
        f = spare;
    }
    return nc;
}

/* theta = 2 atan(1/u) in (-pi, pi]; u = 0 (tau = infinity) is pi. The two branches avoid the
 * cancellation of subtracting 2 pi. */
static codegen_real theta_of_u(codegen_real u)
{
    const codegen_real t = (u >= 0) ? CODEGEN_R(2.0) * codegen_atan2((codegen_real)1, u) : -CODEGEN_R(2.0) * codegen_atan2((codegen_real)1, -u);
    return (t <= -CR_PI) ? CR_PI : t;
}

/* The contracts are in codegen_runtime.h. Outputs are written only on success. */
codegen_roots_status codegen_poly_real_roots(const codegen_real *sigma, int degree, codegen_real *theta,
                                             int *n_roots)
{
    codegen_real work[CODEGEN_ROOTS_WORK(CR_MAXN)];
    if (degree < 1 || degree > CR_MAXN) {
        return CODEGEN_ROOTS_ERR_DEGREE;
    }
    return codegen_poly_real_roots_work(sigma, degree, theta, n_roots, work);
}

codegen_roots_status codegen_poly_real_roots_work(const codegen_real *sigma, int degree, codegen_real *theta,
                                                  int *n_roots, codegen_real *work)
{
    codegen_real amax = 0;
    int nout = 0;
    int e;

    /* The degree first: it says how much of sigma may be read. */
    if (degree < 1) {
        return CODEGEN_ROOTS_ERR_DEGREE;
    }
    if (sigma == NULL || theta == NULL || n_roots == NULL || work == NULL) {
        return CODEGEN_ROOTS_ERR_NULL_POINTER;
    }
    codegen_real *const s = work, *const out = s + (degree + 1);
    codegen_real *const a = out + (2 * degree + 2), *const q = a + (degree + 1), *const r = q + (degree + 1);
    codegen_real *const chart = r + degree;     /* CHART_WORK(degree) */
    for (int i = 0; i <= degree; ++i) {
        if (!isfinite(sigma[i])) {
            return CODEGEN_ROOTS_ERR_NONFINITE;
        }
        amax = codegen_fmax(amax, codegen_fabs(sigma[i]));
    }
    if (amax == 0) {
        return CODEGEN_ROOTS_ERR_ZERO_POLYNOMIAL;
    }

    /* Power-of-two scaling is exact: results do not depend on the overall magnitude. */
    (void)codegen_frexp(amax, &e);
    for (int i = 0; i <= degree; ++i) {
        s[i] = codegen_ldexp(sigma[i], -e);
    }
    int lo = 0;
    int hi = degree;
    while (s[lo] == 0) {                /* stops: some s[i] != 0 since amax > 0 */
        ++lo;
    }
    while (s[hi] == 0) {
        --hi;
    }
    if (lo > 0) {
        out[nout++] = 0;                /* factor tau^lo */
    }
    if (hi < degree) {
        out[nout++] = CR_PI;              /* degree drop: roots at tau = infinity */
    }
    const int m = hi - lo;
    if (m > 0) {
        int ends[2], ends_b[2];
        for (int i = 0; i <= m; ++i) {
            a[i] = s[lo + i];
            q[m - i] = s[lo + i];
        }
        const int na = chart_roots(a, m, NULL, ends, r, chart);
        for (int i = 0; i < na; ++i) {
            out[nout++] = CODEGEN_R(2.0) * codegen_atan(r[i]);
        }
        ends_b[0] = (m % 2 != 0) ? -ends[0] : ends[0];
        ends_b[1] = ends[1];
        const int nb = chart_roots(q, m, ends_b, NULL, r, chart);
        for (int i = 0; i < nb; ++i) {
            out[nout++] = theta_of_u(r[i]);
        }
    }

    /* Insertion sort; then merge values equal to working precision (also across the wrap at
     * +-pi): the same root seen by both charts, or roots no double can tell apart. */
    for (int i = 1; i < nout; ++i) {
        const codegen_real t = out[i];
        int j = i - 1;
        while (j >= 0 && out[j] > t) {
            out[j + 1] = out[j];
            --j;
        }
        out[j + 1] = t;
    }
    const codegen_real tiny = CODEGEN_R(4.0) * CODEGEN_EPSILON;
    int n = 0;
    for (int i = 0; i < nout; ++i) {
        if (n == 0 || out[i] - out[n - 1] > tiny) {
            out[n++] = out[i];
        }
    }
    if (n > 1 && out[0] + CODEGEN_R(2.0) * CR_PI - out[n - 1] <= tiny) {
        for (int i = 1; i < n; ++i) {
            out[i - 1] = out[i];
        }
        --n;
    }
    /* Never reached in exact arithmetic (a polynomial of degree n has at most n roots on the
     * projective line, tau = 0 and tau = infinity included); keeps the output within the
     * caller's degree values should rounding ever make the charts disagree. */
    if (n > degree) {
        n = degree;
    }
    for (int i = 0; i < n; ++i) {
        theta[i] = out[i];
    }
    *n_roots = n;
    return CODEGEN_ROOTS_OK;
}
