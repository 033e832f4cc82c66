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
 * rounding-error bound (1-5, the reference). A faster path is tried first (fast_roots, below):
 * all roots at once by the Ehrlich-Aberth iteration, proven by inclusion discs, real ones
 * refined as 3 refines them; it answers only where it can prove that 1-5 would report the same
 * roots, and leaves the rest (clusters, close or multiple roots) to them.
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

/* theta of a chart's x: 2 atan(tau), or for the reversed chart (x = u = 1/tau) 2 atan(1/u),
 * in [-pi, pi] (u -> 0 from below is -pi: a span's end, not pi). */
static codegen_real span_theta(codegen_real x, int reversed)
{
    return !reversed ? CODEGEN_R(2.0) * codegen_atan(x)
         : x >= 0 ? CODEGEN_R(2.0) * codegen_atan2((codegen_real)1, x)
                  : -CODEGEN_R(2.0) * codegen_atan2((codegen_real)1, -x);
}

/* theta = 2 atan(1/u) in (-pi, pi]; u = 0 (tau = infinity) is pi. */
static codegen_real theta_of_u(codegen_real u)
{
    const codegen_real t = span_theta(u, 1);
    return (t <= -CR_PI) ? CR_PI : t;
}

/* The isolation by derivatives in both charts (the reference the fast path answers for): the
 * roots of a (degree m >= 1) and of its reversal q as angles into out; returns their number.
 * r: room for m values; chart: CHART_WORK(m). */
static int isolated_roots(const codegen_real *a, const codegen_real *q, int m, codegen_real *out,
                          codegen_real *r, codegen_real *chart)
{
    int ends[2], ends_b[2], n = 0;
    const int na = chart_roots(a, m, NULL, ends, r, chart);
    for (int i = 0; i < na; ++i) {
        out[n++] = CODEGEN_R(2.0) * codegen_atan(r[i]);
    }
    ends_b[0] = (m % 2 != 0) ? -ends[0] : ends[0];
    ends_b[1] = ends[1];
    const int nb = chart_roots(q, m, ends_b, NULL, r, chart);
    for (int i = 0; i < nb; ++i) {
        out[n++] = theta_of_u(r[i]);
    }
    return n;
}

/* ------------------------------------------------------------------------------------------
 * The fast path, tried first: all m roots of the polynomial at once by the Ehrlich-Aberth
 * iteration, then proven by inclusion discs, and each real one refined by solve() in its chart.
 * It answers only where it can prove that the isolation above (the reference) would report
 * the same roots; anything else -- a cluster, a multiple or near-multiple root, a complex pair
 * within reach of rule 5, a failure to converge -- falls back to that isolation.
 *
 * Proof (Braess & Hadeler, 1973; the criterion MPSolve uses): for approximations z_1..z_m of
 * the roots of p = a_m prod (tau - zeta_k), the discs D_i = D(z_i, m |p(z_i)| / |a_m prod_{j!=i}
 * (z_i - z_j)|) hold every root, and a connected union of k of them holds exactly k. So when
 * the discs are pairwise disjoint, each holds one simple root: real if its centre is real (the
 * disc is its own mirror image, and a non-real root's conjugate would be a second root in it),
 * non-real if it misses the real axis. Every real root is then a real centre's, and each is
 * bracketed by its disc for solve().
 * ------------------------------------------------------------------------------------------ */

#define CR_NEAR_I CODEGEN_R(0.25)        /* |w| of the roots started near tau = +-i (aberth_start) */
#define CR_FAST_MAXIT 50                  /* Aberth sweeps before giving up (converged ones skip) */
#define CR_FAST_MARGIN (CODEGEN_R(4.0) * CR_PAIR)  /* in chart units: twice as far as rule 5 acts */
#define CR_ROT_C CODEGEN_R(-0.737368878078319901518240381368) /* cos and sin of the golden angle */
#define CR_ROT_S CODEGEN_R(0.675490294261523642344386198119)  /* pi (3 - sqrt 5): spread starts */

/* Smith's complex division (a / b), safe from the overflow of |b|^2; 0 if b = 0. */
static int cdiv(codegen_real ar, codegen_real ai, codegen_real br, codegen_real bi, codegen_real *qr,
                codegen_real *qi)
{
    if (codegen_fabs(br) >= codegen_fabs(bi)) {
        if (br == 0) {
            return 0;
        }
        const codegen_real t = bi / br, d = br + bi * t;
        *qr = (ar + ai * t) / d;
        *qi = (ai - ar * t) / d;
    } else {
        const codegen_real t = br / bi, d = bi + br * t;
        *qr = (ar * t + ai) / d;
        *qi = (ai * t - ar) / d;
    }
    return 1;
}

/* |x + iy|, as sqrt(x^2 + y^2) where the squares stay normal and else scaled by the larger
 * part: in float, |p(z)| ~ 1e-24 near a root of a small polynomial squares to 0, which made a
 * disc that must hold a root 4e4 times too small (a double root of doughty's sigma at
 * theta ~ 1e-9 rad, read as a complex pair: an equilibrium lost without a word). */
static codegen_real modulus(codegen_real x, codegen_real y)
{
    const codegen_real ax = codegen_fabs(x), ay = codegen_fabs(y);
    const codegen_real big = codegen_fmax(ax, ay), small = codegen_fmin(ax, ay);
    if (big * big >= CODEGEN_REAL_MIN / CODEGEN_EPSILON || big == 0) {
        return codegen_sqrt(x * x + y * y);
    }
    return big * codegen_sqrt(1 + (small / big) * (small / big));
}

/* p at the complex point x by Horner's rule, where p has the coefficients a[0..m], or a[m..0]
 * when reversed (the polynomial x^m p(1/x)); *mag receives sum |a_i| |x|^i. Complex Horner
 * is within 8 (m + 1) eps of *mag of the truth (each complex product and sum adds at most
 * (2 + sqrt 2) eps). */
static void chorner(const codegen_real *a, int m, int reversed, codegen_real xr, codegen_real xi,
                    codegen_real *s, codegen_real *mag)
{
    const codegen_real ax = modulus(xr, xi);
    const int step = reversed ? 1 : -1;                 /* from the top coefficient down */
    const codegen_real *c = reversed ? a : a + m;
    codegen_real sr = *c, si = 0;
    codegen_real g = codegen_fabs(sr);
    for (int k = m - 1; k >= 0; --k) {
        c += step;
        const codegen_real ur = sr * xr - si * xi + *c;
        si = sr * xi + si * xr;
        sr = ur;
        g = g * ax + codegen_fabs(*c);
    }
    s[0] = sr;
    s[1] = si;
    *mag = g;
}

#define CR_HORNER_ERR(m, mag) (CODEGEN_R(8.0) * (codegen_real)((m) + 1) * CODEGEN_EPSILON * (mag))

/* The chart for z: y = z where |z| <= 1, else y = 1/z, of the reversed polynomial
 * r(y) = y^m p(1/y) (nothing overflows, whatever |z|). Returns 1 in the second case. */
static int chart_point(codegen_real zr, codegen_real zi, codegen_real *yr, codegen_real *yi)
{
    const codegen_real z2 = zr * zr + zi * zi;
    const int reversed = z2 > 1;
    *yr = reversed ? zr / z2 : zr;
    *yi = reversed ? -zi / z2 : zi;
    return reversed;
}

/* chorner in the chart of z. Returns 1 where it took the reversed polynomial. */
static int chorner_at(const codegen_real *a, int m, codegen_real zr, codegen_real zi, codegen_real *s,
                      codegen_real *mag)
{
    codegen_real yr, yi;
    const int reversed = chart_point(zr, zi, &yr, &yi);
    chorner(a, m, reversed, yr, yi, s, mag);
    return reversed;
}

/* p and p' at x + iy in real arithmetic, for the iteration (Knuth 4.6.4): with
 * q(t) = t^2 - r t + n (r = 2x, n = x^2 + y^2), which vanishes at x + iy, B runs the division
 * of p by q (p(x + iy) = B_m - x B_{m-1} + i y B_{m-1}) and D, one coefficient behind, the
 * division of the quotient (p' = B_{m-1} - 2 y^2 D_{m-3} + 2 i y (D_{m-2} - x D_{m-3})): half
 * the operations of complex Horner, and a shorter chain. Its rounding is not bounded: the
 * iteration only steers, and the discs bound their values afresh (chorner). */
typedef struct steer {
    const codegen_real *c;          /* the next coefficient */
    int step;
    codegen_real x, y, r, n, ax;
    codegen_real b1, b2, d1, d2, g; /* B_k, B_{k-1}, D_{k-1}, D_{k-2}; sum |a_i| |x|^i */
} steer;

static void steer_start(steer *h, const codegen_real *a, int m, int reversed, codegen_real x,
                        codegen_real y)
{
    h->step = reversed ? 1 : -1;
    h->c = reversed ? a : a + m;
    h->x = x;
    h->y = y;
    h->r = 2 * x;
    h->n = x * x + y * y;
    h->ax = codegen_sqrt(h->n);
    h->b1 = *h->c;
    h->b2 = h->d1 = h->d2 = 0;
    h->g = codegen_fabs(*h->c);
}

static inline void steer_next(steer *h)
{
    h->c += h->step;
    const codegen_real dn = h->b2 + h->r * h->d1 - h->n * h->d2;
    h->d2 = h->d1;
    h->d1 = dn;
    const codegen_real bn = *h->c + h->r * h->b1 - h->n * h->b2;
    h->b2 = h->b1;
    h->b1 = bn;
    h->g = h->g * h->ax + codegen_fabs(*h->c);
}

/* out: p (2), p' (2), sum |a_i| |x|^i, the chart's point x + iy (2) */
#define STEER_VALUES 7
static void steer_end(const steer *h, codegen_real *out)
{
    out[0] = h->b1 - h->x * h->b2;
    out[1] = h->y * h->b2;
    out[2] = h->b2 - 2 * h->y * h->y * h->d2;
    out[3] = 2 * h->y * (h->d1 - h->x * h->d2);
    out[4] = h->g;
    out[5] = h->x;
    out[6] = h->y;
}

/* p and p' in the charts of two points at once: two independent chains (one where k < 0). */
static void steer_values(const codegen_real *a, int m, const codegen_real *zr, const codegen_real *zi,
                         int i, int k, int *reversed, codegen_real (*out)[STEER_VALUES])
{
    steer h[2];
    const int n = k < 0 ? 1 : 2;
    for (int t = 0; t < n; ++t) {
        const int j = t == 0 ? i : k;
        codegen_real yr, yi;
        reversed[t] = chart_point(zr[j], zi[j], &yr, &yi);
        steer_start(&h[t], a, m, reversed[t], yr, yi);
    }
    if (n == 2) {
        for (int s = 0; s < m; ++s) {
            steer_next(&h[0]);
            steer_next(&h[1]);
        }
    } else {
        for (int s = 0; s < m; ++s) {
            steer_next(&h[0]);
        }
    }
    for (int t = 0; t < n; ++t) {
        steer_end(&h[t], out[t]);
    }
}

/* The Newton correction N = p(z) / p'(z) as a fraction num / den, from steer_values' v in
 * z's chart; for |z| > 1 from r at y = 1/z (v's chart point): N = z r(y) / (m r(y) - y r'(y)).
 * Kept a fraction so that the Aberth step N / (1 - N S) = num / (den - num S) takes one complex
 * division, not three. Returns 1, and leaves num and den, where |p(z)| is within Horner's
 * error bound: z is a root to working precision. */
static int newton_parts(const codegen_real *v, int reversed, int m, codegen_real zr, codegen_real zi,
                        codegen_real *num, codegen_real *den)
{
    const codegen_real err = CR_HORNER_ERR(m, v[4]);
    if (v[0] * v[0] + v[1] * v[1] <= err * err) {
        return 1;
    }
    if (!reversed) {
        num[0] = v[0];
        num[1] = v[1];
        den[0] = v[2];
        den[1] = v[3];
    } else {
        const codegen_real yr = v[5], yi = v[6];
        num[0] = zr * v[0] - zi * v[1];
        num[1] = zr * v[1] + zi * v[0];
        den[0] = (codegen_real)m * v[0] - (yr * v[2] - yi * v[3]);
        den[1] = (codegen_real)m * v[1] - (yr * v[3] + yi * v[2]);
    }
    return 0;
}

/* log2 |x| (x not 0) to within 0.005: the binary exponent, and the mantissa's by a quadratic
 * through its ends and middle. Only +, *, frexp: the same value on every libm. */
static codegen_real rough_log2(codegen_real x)
{
    int e;
    const codegen_real t = 2 * codegen_frexp(codegen_fabs(x), &e) - 1; /* |x| = (1 + t) 2^(e - 1) */
    return (codegen_real)(e - 1) + t * (CODEGEN_R(1.3465) - CODEGEN_R(0.3465) * t);
}

/* 2^y to within 0.3 %, as rough_log2: the integer part by ldexp, the fraction by a quadratic. */
static codegen_real rough_exp2(codegen_real y)
{
    int n = (int)y;
    n -= (codegen_real)n > y;
    const codegen_real s = y - (codegen_real)n;          /* in [0, 1) */
    return codegen_ldexp(1 + s * (CODEGEN_R(0.6565) + CODEGEN_R(0.3435) * s), n);
}

/* lg[k] = log2 |c_k| to within 0.005 (rough_log2), or -CODEGEN_HUGE where c_k = 0. */
static void rough_logs(const codegen_real *c, int m, codegen_real *lg)
{
    for (int k = 0; k <= m; ++k) {
        lg[k] = c[k] != 0 ? rough_log2(c[k]) : -CODEGEN_HUGE;
    }
}

/* The vertices k of the upper convex hull of (k, lg[k]) over the k with c_k not 0 (rough_logs),
 * into hull (as reals); returns their count. */
static int newton_hull(const codegen_real *lg, int m, codegen_real *hull)
{
    int h = 0;
    for (int k = 0; k <= m; ++k) {
        if (!(lg[k] > -CODEGEN_HUGE)) {
            continue;
        }
        while (h >= 2) {                        /* drop the last vertex if not above the chord */
            const int k1 = (int)hull[h - 2], k2 = (int)hull[h - 1];
            if ((lg[k2] - lg[k1]) * (codegen_real)(k - k1) > (lg[k] - lg[k1]) * (codegen_real)(k2 - k1)) {
                break;
            }
            --h;
        }
        hull[h++] = (codegen_real)k;
    }
    return h;
}

/* The radius of the roots that an edge k1 < k2 of the Newton polygon stands for:
 * (|c_k1| / |c_k2|)^(1 / (k2 - k1)), to about 1 %. */
static codegen_real edge_radius(const codegen_real *lg, int k1, int k2)
{
    return rough_exp2((lg[k1] - lg[k2]) / (codegen_real)(k2 - k1));
}

/* The next point on the unit circle, turned by the golden angle from (*cr, *ci). */
static void golden_turn(codegen_real *cr, codegen_real *ci)
{
    const codegen_real nc = *cr * CR_ROT_C - *ci * CR_ROT_S;
    *ci = *cr * CR_ROT_S + *ci * CR_ROT_C;
    *cr = nc;
}

/* |c_j| (to within a factor sqrt 2: |Re| + |Im|) of c(w) = (w + 1)^m p(tau), tau = -i (w - 1) /
 * (w + 1): the polynomial in w = (1 + i tau) / (1 - i tau) = e^(i theta), whose roots near 0 and
 * infinity are p's near tau = i and -i. By Horner's rule on sum_k a_k u^k v^(m - k) (u = -i (w -
 * 1), v = w + 1): c <- c u + a_k v^(m - k), one pass per k from the top coefficient down (each
 * c_(j-1) read before it is overwritten). mag, im, v: m + 1 values each; mag receives |c_j|. */
static void unit_circle_magnitudes(const codegen_real *a, int m, codegen_real *mag, codegen_real *im,
                                   codegen_real *v)
{
    codegen_real *const re = mag;
    re[0] = a[m];
    im[0] = 0;
    v[0] = 1;
    for (int k = m - 1, d = 0; k >= 0; --k, ++d) { /* c and v of degree d, then d + 1 */
        /* (c (w - 1))_j = c_(j-1) - c_j; times -i: (x + iy)(-i) = y - ix; plus a_k v_j */
        v[d + 1] = v[d];
        re[d + 1] = im[d] + a[k] * v[d + 1];
        im[d + 1] = -re[d];
        for (int j = d; j >= 1; --j) {
            const codegen_real at = re[j];
            v[j] += v[j - 1];
            re[j] = (im[j - 1] - im[j]) + a[k] * v[j];
            im[j] = at - re[j - 1];
        }
        const codegen_real at = re[0];                 /* v_0 stays 1 */
        re[0] = a[k] - im[0];
        im[0] = at;
    }
    for (int j = 0; j <= m; ++j) {
        mag[j] = codegen_fabs(re[j]) + codegen_fabs(im[j]);
    }
}

/* tau = -i (w - 1) / (w + 1) for w = rho (cr + i ci) (|cr + i ci| = 1, rho far from 1), from
 * 1 / w where rho > 1, so that nothing overflows. */
static void tau_of_w(codegen_real rho, codegen_real cr, codegen_real ci, codegen_real *tr, codegen_real *ti)
{
    const int far = rho > 1;
    const codegen_real r = far ? 1 / rho : rho, x = r * cr, y = far ? -r * ci : r * ci;
    const codegen_real d = (1 + x) * (1 + x) + y * y, up = 1 - r * r;  /* |1 + w|^2 (w or 1 / w) */
    *tr = (far ? -2 * y : 2 * y) / d;
    *ti = (far ? -up : up) / d;
}

/* Starting points: for each edge of the Newton polygon of p (the upper convex hull of (k, log2
 * |a_k|): its slopes give the roots' magnitudes), as many points as the edge is long, on the
 * circle of that radius, turned by the golden angle from one point to the next so that none
 * is symmetric to another about the real axis. Roots near tau = +-i (theta -> -+i infinity,
 * where sigma's outermost Fourier terms are small: a cluster the polygon cannot tell from the
 * roots of modulus 1) are seen by the Newton polygon of the same polynomial in w = e^(i theta)
 * (unit_circle_magnitudes) as roots near w = 0 and infinity: as many of p's points as it has
 * there (on edges of radius below CR_NEAR_I, or above its inverse) are moved from the circles
 * nearest |tau| = 1 to its circles, mapped back to tau. The radii are to about 1 % (rough_log2,
 * rough_exp2): the same starts on every libm. scratch: 3 (m + 1) values. */
static void aberth_start(const codegen_real *a, int m, codegen_real *zr, codegen_real *zi,
                         codegen_real *scratch)
{
    codegen_real *const lg = scratch, *const other = lg + (m + 1), *const hull = other + (m + 1);
    codegen_real cr = 1, ci = 0;
    int n = 0;
    rough_logs(a, m, lg);
    int h = newton_hull(lg, m, hull);
    for (int t = 0; t + 1 < h; ++t) {
        const int k1 = (int)hull[t], k2 = (int)hull[t + 1];
        const codegen_real rho = edge_radius(lg, k1, k2);
        for (int j = k1; j < k2; ++j) {
            golden_turn(&cr, &ci);
            zr[n] = rho * cr;
            zi[n] = rho * ci;
            ++n;
        }
    }
    unit_circle_magnitudes(a, m, lg, other, hull);
    rough_logs(lg, m, lg);
    h = newton_hull(lg, m, hull);
    codegen_real *const off = other;                   /* |log |tau|| grows with it; HUGE: moved */
    for (int i = 0; i < n; ++i) {
        const codegen_real r2 = zr[i] * zr[i] + zi[i] * zi[i];
        off[i] = r2 >= 1 ? r2 : 1 / r2;
    }
    for (int t = 0; t + 1 < h; ++t) {
        const int k1 = (int)hull[t], k2 = (int)hull[t + 1];
        const codegen_real rho = edge_radius(lg, k1, k2);
        if (!(rho >= CODEGEN_SQRT_EPSILON && rho <= CR_NEAR_I)
            && !(rho <= 1 / CODEGEN_SQRT_EPSILON && rho >= 1 / CR_NEAR_I)) {
            continue;
        }
        for (int j = k1; j < k2; ++j) { /* onto the point nearest |tau| = 1 not yet moved */
            int best = 0;
            for (int i = 1; i < n; ++i) {
                best = off[i] < off[best] ? i : best;
            }
            if (n == 0 || !(off[best] < CODEGEN_HUGE)) {
                return;
            }
            golden_turn(&cr, &ci);
            tau_of_w(rho, cr, ci, &zr[best], &zi[best]);
            off[best] = CODEGEN_HUGE;
        }
    }
}

/* S = sum_{j != i} 1 / (z_i - z_j) into (*sr, *si), the terms taken in pairs with one division
 * each, 1 / d + 1 / e = (conj(d) |e|^2 + conj(e) |d|^2) / (|d|^2 |e|^2), where that product is
 * normal and finite (else term by term). Returns 0 where two points coincide. */
static int repulsion(const codegen_real *zr, const codegen_real *zi, int m, int i, codegen_real *sr,
                     codegen_real *si)
{
    codegen_real r = 0, s = 0, pr = 0, pi = 0, pn = 0;
    int pending = 0;
    for (int j = 0; j < m; ++j) {
        if (j == i) {
            continue;
        }
        const codegen_real dr = zr[i] - zr[j], di = zi[i] - zi[j], n = dr * dr + di * di;
        if (!(n > 0)) {
            return 0;
        }
        if (!pending) {
            pr = dr;
            pi = di;
            pn = n;
            pending = 1;
            continue;
        }
        const codegen_real both = pn * n;
        if (both >= CODEGEN_REAL_MIN && both < CODEGEN_REAL_MAX) {
            const codegen_real inv = 1 / both;
            r += (pr * n + dr * pn) * inv;
            s -= (pi * n + di * pn) * inv;
        } else {
            r += pr / pn + dr / n;
            s -= pi / pn + di / n;
        }
        pending = 0;
    }
    if (pending) {
        r += pr / pn;
        s -= pi / pn;
    }
    *sr = r;
    *si = s;
    return 1;
}

/* Gauss-Seidel Ehrlich-Aberth sweeps: z_i -= N / (1 - N sum_{j != i} 1 / (z_i - z_j)), N the
 * Newton correction, until every z_i is a root to working precision or moves by less than its
 * resolution. Each z_i's values are taken together with those of the next z_k still moving,
 * which stays where it is until its own turn (the same iteration, two chains at once).
 * done: m values of scratch. Returns 1 when all converged. */
static int aberth(const codegen_real *a, int m, codegen_real *zr, codegen_real *zi, codegen_real *done)
{
    int left = m;
    for (int i = 0; i < m; ++i) {
        done[i] = 0;
    }
    for (int it = 0; it < CR_FAST_MAXIT && left > 0; ++it) {
        codegen_real values[2][STEER_VALUES];
        int reversed[2], ahead = -1;
        for (int i = 0; i < m; ++i) {
            codegen_real num[2], den[2], sr, si, wr, wi;
            int t = 1;
            if (done[i] != 0) {
                continue;
            }
            if (i != ahead) {
                int k = i + 1;
                while (k < m && done[k] != 0) {
                    ++k;
                }
                ahead = k < m ? k : -1;
                steer_values(a, m, zr, zi, i, ahead, reversed, values);
                t = 0;
            }
            if (newton_parts(values[t], reversed[t], m, zr[i], zi[i], num, den)) {
                done[i] = 1;
                --left;
                continue;
            }
            if (!repulsion(zr, zi, m, i, &sr, &si)) {
                return 0;
            }
            if (!cdiv(num[0], num[1], den[0] - (num[0] * sr - num[1] * si),
                      den[1] - (num[0] * si + num[1] * sr), &wr, &wi)) {
                return 0;
            }
            zr[i] -= wr;
            zi[i] -= wi;
            if (!isfinite(zr[i]) || !isfinite(zi[i])) {
                return 0;
            }
            /* Convergence is cubic: after a step this small relative to |z|, the error is at
             * rounding level (and were it not, the discs below would only be wider). */
            if (codegen_fabs(wr) + codegen_fabs(wi) <= CODEGEN_SQRT_EPSILON * (codegen_fabs(zr[i]) + codegen_fabs(zi[i]))) {
                done[i] = 1;
                --left;
            }
        }
    }
    return left == 0;
}

/* The sum of bound[k] |x|^k for p's chart at z (bound[m - k] |y|^k, y = 1/z, where chorner_at
 * takes the reversed polynomial): what the coefficients' errors can add to |p(z)| there. */
static codegen_real bound_sum(const codegen_real *bound, int m, int reversed, codegen_real ax)
{
    codegen_real t = 0;
    for (int k = 0; k <= m; ++k) {
        t = t * ax + bound[reversed ? k : m - k];
    }
    return t;
}

/* The radius of D_i (above), an upper bound: |p(z_i)| bounded by value if it is not negative
 * (in the chart chorner_at takes), else by Horner's value plus its error bound; the product's
 * own rounding covered by a factor 2. For |z_i| > 1, |p(z_i)| = |z_i|^m
 * |r(1/z_i)|, the factors |z_i| taken one per quotient so that nothing overflows. bound: NULL,
 * or a bound on each coefficient's error, which then widens D_i to hold the roots of every
 * polynomial within those bounds (|p(z_i)| grows by at most sum bound_k |z_i|^k, and |a_m| is
 * at least |a_m| - bound_m, which the caller keeps positive). */
static codegen_real inclusion_radius(const codegen_real *a, const codegen_real *bound, int m,
                                     const codegen_real *zr, const codegen_real *zi, int i,
                                     codegen_real value)
{
    const codegen_real z2 = zr[i] * zr[i] + zi[i] * zi[i], az = modulus(zr[i], zi[i]);
    const int reversed = z2 > 1; /* the chart chorner_at takes (it runs only where no value is given) */
    const codegen_real ax = reversed ? 1 / az : az;
    const codegen_real widen = bound != NULL ? bound_sum(bound, m, reversed, ax) * (1 + CODEGEN_EPSILON) : 0;
    const codegen_real lead = bound != NULL ? codegen_fabs(a[m]) - bound[m] : codegen_fabs(a[m]);
    if (!(value >= 0)) {
        codegen_real s[2], mag;
        (void)chorner_at(a, m, zr[i], zi[i], s, &mag);
        value = modulus(s[0], s[1]) + CR_HORNER_ERR(m, mag);
    }
    codegen_real t = (codegen_real)m * (value + widen) / lead;
    /* prod_j (f / |z_i - z_j|), f = |z_i| or 1, as one over the square root of the product of
     * |z_i - z_j|^2 / f^2 (one division and one square root, not m - 1: products in two chains,
     * every other factor in each) where every factor and partial product stays normal and
     * finite, so that each operation keeps its relative rounding (the factor 2 below covers
     * them); else factor by factor */
    const codegen_real f2 = reversed ? az * az : 1, shrink = 1 / f2;
    codegen_real even = 1, odd = 1;
    int normal = f2 < CODEGEN_REAL_MAX;
    for (int j = 0; j < m && normal; ++j) {
        if (j != i) {
            const codegen_real dr = zr[i] - zr[j], di = zi[i] - zi[j], d2 = dr * dr + di * di;
            const codegen_real q = d2 * shrink;
            if (j & 1) {
                odd = odd * q;
            } else {
                even = even * q;
            }
            normal = d2 >= CODEGEN_REAL_MIN && q >= CODEGEN_REAL_MIN && q < CODEGEN_REAL_MAX
                  && even >= CODEGEN_REAL_MIN && even < CODEGEN_REAL_MAX
                  && odd >= CODEGEN_REAL_MIN && odd < CODEGEN_REAL_MAX;
        }
    }
    const codegen_real squares = even * odd;
    normal = normal && squares >= CODEGEN_REAL_MIN && squares < CODEGEN_REAL_MAX;
    if (normal) {
        t = t / codegen_sqrt(squares);
    } else {
        for (int j = 0; j < m; ++j) {
            if (j != i) {
                const codegen_real dr = zr[i] - zr[j], di = zi[i] - zi[j];
                t = t * (reversed ? az : 1) / codegen_sqrt(dr * dr + di * di);
            }
        }
    }
    t = CODEGEN_R(2.0) * (reversed ? t * az : t) + CODEGEN_REAL_MIN;
    return (t == t && lead > 0) ? t : CODEGEN_HUGE;
}

/* Sign of f at x if certain, else 0: from plain Horner (the value alone: horner_fd's slope
 * would cost soft-float firmware as much again) where its error bound decides, else from the
 * compensated value (as level_roots trusts it). */
static int certain_sign(const codegen_real *f, int n, codegen_real x)
{
    codegen_real mag = magnitude(f, n, codegen_fabs(x));
    codegen_real v = f[n];
    for (int i = n - 1; i >= 0; --i) {
        v = v * x + f[i];
    }
    if (PLAIN_OK(v, n, mag)) {
        return v > 0 ? 1 : -1;
    }
    v = eval(f, n, x, &mag);
    const codegen_real g = (codegen_real)n * CODEGEN_EPSILON;
    const codegen_real tol = CODEGEN_EPSILON * codegen_fabs(v) + CODEGEN_R(2.0) * g * g * mag;
    return codegen_fabs(v) > CODEGEN_R(2.0) * tol ? (v > 0 ? 1 : -1) : 0;
}

/* The real roots of a (degree m >= 1, a[0] and a[m] nonzero; q its reversal) as angles into
 * theta (room for m), or 0 if the fast path cannot vouch for them (then nothing is meant by
 * theta). work: 7 m + 1 values. */
static int fast_roots(const codegen_real *a, const codegen_real *q, int m, codegen_real *theta, int *n,
                      codegen_real *work, const codegen_real *iterated)
{
    codegen_real *const zr = work, *const zi = zr + m, *const rad = zi + m, *const scratch = rad + m;
    codegen_real *const da = scratch + (m + 1), *const dq = da + m;   /* scratch: the starts', then done */
    if (iterated != NULL) { /* the iteration's result on this same a, from the spans */
        for (int i = 0; i < 2 * m; ++i) {
            zr[i] = iterated[i];
        }
    } else {
        aberth_start(a, m, zr, zi, scratch);
        if (!aberth(a, m, zr, zi, scratch)) {
            return 0;
        }
    }
    /* Centres within rounding of the real axis are moved onto it (any centres would do: the
     * discs are sized afterwards; a complex pair so moved gives two overlapping discs). */
    for (int i = 0; i < m; ++i) {
        if (codegen_fabs(zi[i]) <= CODEGEN_SQRT_EPSILON * codegen_fabs(zr[i])) {
            zi[i] = 0;
        }
    }
    for (int i = 0; i < m; ++i) {
        rad[i] = inclusion_radius(a, NULL, m, zr, zi, i, -1);
    }
    /* Disjoint discs; real roots, and non-real ones from the axis, farther apart in chart
     * units (distances over max(1, |tau|)^2 are at most those in u = 1 / tau) than rule 5's
     * reach, so that the isolation would see no multiple root either. */
    for (int i = 0; i < m; ++i) {
        const codegen_real si = codegen_fmax((codegen_real)1, codegen_sqrt(zr[i] * zr[i] + zi[i] * zi[i]) + rad[i]);
        if (zi[i] != 0 && !((codegen_fabs(zi[i]) - rad[i]) / (si * si) > CR_FAST_MARGIN)) {
            return 0;
        }
        for (int j = i + 1; j < m; ++j) {
            const codegen_real dr = zr[i] - zr[j], di = zi[i] - zi[j];
            const codegen_real gap = codegen_sqrt(dr * dr + di * di) - rad[i] - rad[j];
            if (!(gap > 0)) {
                return 0;
            }
            if (zi[i] == 0 && zi[j] == 0) {
                const codegen_real sj = codegen_fmax((codegen_real)1, codegen_fabs(zr[j]) + rad[j]);
                const codegen_real s = codegen_fmax(si, sj);
                if (!(gap / (s * s) > CR_FAST_MARGIN)) {
                    return 0;
                }
            }
        }
    }
    /* Each real root refined in its chart (as the isolation reports it) within its disc. */
    derivative(a, m, 1, da);
    derivative(q, m, 1, dq);
    int count = 0;
    for (int i = 0; i < m; ++i) {
        if (zi[i] != 0) {
            continue;
        }
        const codegen_real c = zr[i], r = rad[i];
        const int chart_a = codegen_fabs(c) <= 1;
        if (!chart_a && !(r < CODEGEN_R(0.5) * codegen_fabs(c))) {
            return 0;
        }
        const codegen_real *f = chart_a ? a : q, *df = chart_a ? da : dq;
        const codegen_real x1 = chart_a ? c - r : 1 / (c - r), x2 = chart_a ? c + r : 1 / (c + r);
        const codegen_real lo = codegen_fmin(x1, x2), hi = codegen_fmax(x1, x2);
        const int slo = certain_sign(f, m, lo), shi = certain_sign(f, m, hi);
        if (slo == 0 || shi != -slo) {
            return 0;
        }
        codegen_real del;
        const codegen_real x = solve(f, df, m, CR_ULPS * CODEGEN_EPSILON, lo, hi, slo, &del);
        theta[count++] = chart_a ? CODEGEN_R(2.0) * codegen_atan(x) : theta_of_u(x);
    }
    *n = count;
    return 1;
}

/* ------------------------------------------------------------------------------------------
 * Spans: where the real roots of every polynomial within bounds on its coefficients may lie
 * (codegen_runtime.h). The same iteration and discs as the fast path, the discs widened by the
 * coefficients' bounds; nothing is refined, nothing falls back: the caller decides what each
 * span holds (the analysis, by enclosures of G on it).
 * ------------------------------------------------------------------------------------------ */

/* How far a span's ends are moved out [rad, relative to |theta| + 1]: atan and atan2 within a
 * few ulps (the libms the library supports are within one or two). */
#define SPAN_WIDEN (CODEGEN_R(16.0) * CODEGEN_EPSILON)

/* How far [rad, relative to |theta| + 1] a span that is not simple reaches out on each side
 * for the isolation that searches it: a zero of G within a span of rounding width (a root of
 * the polynomial that is double because two branches vanish there, as at theta = pi where a
 * force balances gravity) is proven by G's signs this far from it. */
#define SPAN_REACH (CODEGEN_R(16.0) * CODEGEN_SQRT_EPSILON)

/* Where codegen_poly_root_spans leaves its iteration's result in work (as it was when the
 * iteration stopped: real parts, then imaginary), beyond its own arrays (13 degree + 4) and
 * everything real_roots' fast path writes before reading it (fast_roots' arrays and
 * aberth_start's scratch end below 12 degree + 9). */
#define SPANS_ITERATED(work, degree) ((work) + 14 * (degree) + 16)

static codegen_real span_reach_lo(const codegen_root_span *s)
{
    return s->simple ? s->lo : s->lo - SPAN_REACH * (codegen_fabs(s->lo) + 1);
}

static codegen_real span_reach_hi(const codegen_root_span *s)
{
    return s->simple ? s->hi : s->hi + SPAN_REACH * (codegen_fabs(s->hi) + 1);
}

/* b (moved by shift) joined to a: one span, not simple. */
static void join_spans(codegen_root_span *a, const codegen_root_span *b, codegen_real shift)
{
    a->lo = codegen_fmin(a->lo, b->lo + shift);
    a->hi = codegen_fmax(a->hi, b->hi + shift);
    a->simple = 0;
}

/* A real root's approximation x of f (degree n >= 1; |x| <= 1 in the caller's chart) polished
 * by Newton's method on compensated values while |f| falls: to rounding, so that its disc is
 * as narrow as the coefficients' bounds allow (the iteration stops at plain Horner's error,
 * or where a step no longer moves x). *value and *mag: eval's at the x returned. */
static codegen_real polish_real(const codegen_real *f, const codegen_real *df, int n, codegen_real x,
                                codegen_real *value, codegen_real *mag)
{
    codegen_real v = eval(f, n, x, mag), dmag;
    for (int it = 0; it < 4 && v != 0; ++it) {
        const codegen_real d = eval(df, n - 1, x, &dmag);
        if (d == 0) {
            break;
        }
        const codegen_real xn = x - v / d;
        if (xn == x) {
            break;
        }
        codegen_real nmag;
        const codegen_real vn = eval(f, n, xn, &nmag);
        if (!(codegen_fabs(vn) < codegen_fabs(v))) {
            break;
        }
        const int last = codegen_fabs(xn - x) <= CODEGEN_R(4.0) * CODEGEN_EPSILON * codegen_fabs(x);
        x = xn;
        v = vn;
        *mag = nmag;
        if (last) { /* a step of a few ulps: x was already a root to rounding */
            break;
        }
    }
    *value = v;
    return x;
}

/* An upper bound on |f(x)| from its compensated value v and magnitude sum mag (see eval: within
 * u |f| + gamma_2n^2 of the magnitude sum; gamma_2n <= 2 n eps here, and the sum's own
 * rounding a factor 2). */
static codegen_real real_value_bound(codegen_real v, codegen_real mag, int n)
{
    const codegen_real g = CODEGEN_R(2.0) * (codegen_real)n * CODEGEN_EPSILON;
    return (codegen_fabs(v) + CODEGEN_R(2.0) * g * g * mag) * (1 + CODEGEN_R(2.0) * CODEGEN_EPSILON)
           + CODEGEN_REAL_MIN;
}

/* [*tlo, *thi]: the angles of the chart interval [lo, hi], moved out by SPAN_WIDEN; one that
 * holds theta = pi (u = 0 in the reversed chart) has *tlo < pi < *thi. */
static void chart_to_theta(codegen_real lo, codegen_real hi, int reversed, codegen_real *tlo,
                           codegen_real *thi)
{
    if (!reversed) {
        *tlo = span_theta(lo, 0);
        *thi = span_theta(hi, 0);
    } else if (lo > 0 || hi < 0) { /* theta falls as u rises, on either side of u = 0 */
        *tlo = span_theta(hi, 1);
        *thi = span_theta(lo, 1);
    } else { /* across u = 0: theta = pi */
        *tlo = hi > 0 ? span_theta(hi, 1) : CR_PI;
        *thi = lo < 0 ? span_theta(lo, 1) + CODEGEN_R(2.0) * CR_PI : CR_PI;
    }
    *tlo -= SPAN_WIDEN * (codegen_fabs(*tlo) + 1);
    *thi += SPAN_WIDEN * (codegen_fabs(*thi) + 1);
}

/* Starting points for all m roots: aberth_start's, then any left (roots at 0, where trailing
 * coefficients vanish) on a small circle. scratch: 3 (m + 1) values. */
static void span_start(const codegen_real *b, int m, codegen_real *zr, codegen_real *zi,
                       codegen_real *scratch)
{
    int first = 0;
    codegen_real cr = 1, ci = 0;
    while (b[first] == 0) {
        ++first;
    }
    aberth_start(b, m, zr, zi, scratch);
    for (int n = m - first; n < m; ++n) {
        golden_turn(&cr, &ci);
        zr[n] = CODEGEN_R(0x1p-20) * cr;
        zi[n] = CODEGEN_R(0x1p-20) * ci;
    }
}

/* ---- clusters of centres ----
 * Braess & Hadeler's discs hold for any m distinct nodes, but a disc's radius divides by the
 * distances to the other nodes: k centres of a multiple root, or of roots closer than the
 * coefficients' bounds resolve, lie so close together that their discs cover the whole plane
 * (a four-bar's change point: a four-fold root of sigma at theta = 0 gave discs of radius 48 in
 * tau, one span of every angle). Such a cluster's k nodes are moved onto a circle of radius rho
 * around their centroid, rho chosen to make the cluster's discs smallest: their radii are then
 * ~ (m / k) rho, and the discs still hold every root (the theorem asks nothing of the nodes). */
#define CLUSTER_GAP CODEGEN_R(16.0)   /* a cluster's centres: this much closer than any other */
#define CLUSTER_TRIES 48              /* radii rho tried, doubling */

/* cos and sin of 2 pi t for 0 <= t < 1, from + and * alone (the same nodes on every libm);
 * to ~1e-8, which is all a node's place needs. */
static void unit_turn(codegen_real t, codegen_real *c, codegen_real *s)
{
    const codegen_real x = CODEGEN_R(2.0) * CR_PI * (t > CODEGEN_R(0.5) ? t - 1 : t), x2 = x * x;
    codegen_real cs = 0, sn = 0;
    for (int k = 9; k >= 1; --k) { /* Horner on the Taylor series to x^18 and x^19 */
        cs = 1 - x2 * cs / (codegen_real)((2 * k - 1) * (2 * k));
        sn = 1 - x2 * sn / (codegen_real)((2 * k) * (2 * k + 1));
    }
    *c = cs;
    *s = x * sn;
}

/* The k nearest centres to z_i (k >= 2, as few as possible) that lie CLUSTER_GAP times closer
 * to their centroid than any other centre: their indices first in order[], their centroid
 * (real where they straddle the axis), their spread (the farthest from the centroid) and the
 * gap (the nearest other centre). Returns k, or 0 where no such cluster exists. */
static int cluster_at(const codegen_real *zr, const codegen_real *zi, int m, int i,
                      codegen_real *dist, codegen_real *order, codegen_real *cr, codegen_real *ci,
                      codegen_real *spread, codegen_real *gap)
{
    for (int j = 0; j < m; ++j) { /* by distance from z_i (insertion sort: m is small) */
        const codegen_real d = codegen_fabs(zr[j] - zr[i]) + codegen_fabs(zi[j] - zi[i]);
        int at = j;
        while (at > 0 && dist[at - 1] > d) {
            dist[at] = dist[at - 1];
            order[at] = order[at - 1];
            --at;
        }
        dist[at] = d;
        order[at] = (codegen_real)j;
    }
    for (int k = 2; k < m; ++k) {
        codegen_real sr = 0, si = 0, far = 0, near = CODEGEN_HUGE;
        for (int j = 0; j < k; ++j) {
            sr += zr[(int)order[j]];
            si += zi[(int)order[j]];
        }
        sr /= (codegen_real)k;
        si /= (codegen_real)k;
        for (int j = 0; j < m; ++j) {
            const int n = (int)order[j];
            const codegen_real dr = zr[n] - sr, di = zi[n] - si, d = codegen_sqrt(dr * dr + di * di);
            if (j < k) {
                far = codegen_fmax(far, d);
            } else {
                near = codegen_fmin(near, d);
            }
        }
        if (near > CLUSTER_GAP * far) {
            *cr = sr;
            *ci = codegen_fabs(si) <= far ? 0 : si;
            *spread = far;
            *gap = near;
            return k;
        }
    }
    return 0;
}

/* The cluster's k nodes (indices in order[]) on the circle of radius rho around c, turned by
 * half a step so that no node is real for even k (a real node would be polished as a root);
 * the largest reach rho + radius of their discs. */
static codegen_real place_cluster(const codegen_real *a, const codegen_real *bound, int m,
                                  codegen_real *zr, codegen_real *zi, codegen_real *rad,
                                  const codegen_real *order, int k, codegen_real cr, codegen_real ci,
                                  codegen_real rho)
{
    codegen_real reach = 0;
    for (int j = 0; j < k; ++j) {
        codegen_real c, s;
        unit_turn(((codegen_real)j + CODEGEN_R(0.5)) / (codegen_real)k, &c, &s);
        zr[(int)order[j]] = cr + rho * c;
        zi[(int)order[j]] = ci + rho * s;
    }
    for (int j = 0; j < k; ++j) {
        const int n = (int)order[j];
        rad[n] = inclusion_radius(a, bound, m, zr, zi, n, -1);
        reach = codegen_fmax(reach, rho + rad[n]);
    }
    return reach;
}

/* Every cluster of centres whose discs reach beyond half the distance to their nearest
 * neighbour, spread out (above) where that makes its discs smaller; then every disc's radius
 * afresh, since each depends on every node. value[i]: the bound on |p(z_i)| the caller
 * computed for a real centre (else -1). in[], dist[], order[]: m values each; keep[]: 2 m. */
static void spread_clusters(const codegen_real *a, const codegen_real *bound, int m,
                            codegen_real *zr, codegen_real *zi, codegen_real *rad,
                            codegen_real *value, codegen_real *in, codegen_real *dist,
                            codegen_real *order, codegen_real *keep)
{
    int moved = 0;
    for (int i = 0; i < m; ++i) {
        in[i] = 0;
    }
    for (int i = 0; i < m; ++i) {
        codegen_real nearest = CODEGEN_HUGE, cr, ci, spread, gap;
        for (int j = 0; j < m; ++j) {
            if (j != i) {
                nearest = codegen_fmin(nearest, codegen_fabs(zr[j] - zr[i]) + codegen_fabs(zi[j] - zi[i]));
            }
        }
        if (in[i] != 0 || !(rad[i] > CODEGEN_R(0.5) * nearest)) {
            continue;
        }
        const int k = cluster_at(zr, zi, m, i, dist, order, &cr, &ci, &spread, &gap);
        int member = 0;
        for (int j = 0; j < k; ++j) {
            member |= in[(int)order[j]] != 0;
        }
        if (k == 0 || member) {
            continue;
        }
        codegen_real before = 0, best = CODEGEN_HUGE, best_rho = 0;
        for (int j = 0; j < k; ++j) {
            const int n = (int)order[j];
            keep[2 * j] = zr[n];
            keep[2 * j + 1] = zi[n];
            before = codegen_fmax(before, codegen_sqrt((zr[n] - cr) * (zr[n] - cr) + (zi[n] - ci) * (zi[n] - ci)) + rad[n]);
        }
        codegen_real rho = codegen_fmax(spread, CODEGEN_EPSILON * codegen_fmax(codegen_fabs(cr) + codegen_fabs(ci), 1));
        for (int t = 0; t < CLUSTER_TRIES && CODEGEN_R(4.0) * rho < gap; ++t, rho *= 2) {
            const codegen_real reach = place_cluster(a, bound, m, zr, zi, rad, order, k, cr, ci, rho);
            if (reach < best) {
                best = reach;
                best_rho = rho;
            }
        }
        if (best < before && best < CODEGEN_R(0.5) * gap) {
            (void)place_cluster(a, bound, m, zr, zi, rad, order, k, cr, ci, best_rho);
            for (int j = 0; j < k; ++j) {
                in[(int)order[j]] = 1;
                value[(int)order[j]] = -1;
            }
            moved = 1;
        } else {
            for (int j = 0; j < k; ++j) {
                zr[(int)order[j]] = keep[2 * j];
                zi[(int)order[j]] = keep[2 * j + 1];
            }
        }
    }
    for (int i = 0; i < m && moved; ++i) {
        rad[i] = inclusion_radius(a, bound, m, zr, zi, i, value[i]);
    }
}

/* The label of i's set (union-find over discs that meet, labels stored as reals). */
static int span_find(codegen_real *label, int i)
{
    while ((int)label[i] != i) {
        label[i] = label[(int)label[i]];
        i = (int)label[i];
    }
    return i;
}

codegen_roots_status codegen_poly_root_spans(const codegen_real *sigma, const codegen_real *bound,
                                             int degree, codegen_root_span *spans, int *n_spans,
                                             codegen_real *work)
{
    const codegen_real two_pi = CODEGEN_R(2.0) * CR_PI;
    const int m = degree;
    codegen_real amax = 0;
    int e, n = 0;
    if (degree < 1) {
        return CODEGEN_ROOTS_ERR_DEGREE;
    }
    if (sigma == NULL || bound == NULL || spans == NULL || n_spans == NULL || work == NULL) {
        return CODEGEN_ROOTS_ERR_NULL_POINTER;
    }
    codegen_real *const b = work, *const db = b + (m + 1), *const zr = db + (m + 1), *const zi = zr + m;
    codegen_real *const rad = zi + m, *const scratch = rad + m, *const label = scratch + (m + 1);
    codegen_real *const seg_lo = label + m, *const seg_hi = seg_lo + m, *const seg_of = seg_hi + m;
    codegen_real *const q = seg_of + m, *const dp = q + (m + 1), *const dq = dp + m;
    for (int i = 0; i <= m; ++i) {
        if (!isfinite(sigma[i]) || !isfinite(bound[i]) || !(bound[i] >= 0)) {
            return CODEGEN_ROOTS_UNPROVEN;
        }
        amax = codegen_fmax(amax, codegen_fabs(sigma[i]));
    }
    if (amax == 0) {
        return CODEGEN_ROOTS_UNPROVEN;
    }
    /* The chart whose leading coefficient is certainly not 0: tau, or u = 1/tau. Scaled by a
     * power of two (exact; a bound that would lose bits below the smallest normal is raised). */
    (void)codegen_frexp(amax, &e);
    const int reversed = !(codegen_fabs(sigma[m]) > CODEGEN_R(2.0) * bound[m]);
    if (reversed && !(codegen_fabs(sigma[0]) > CODEGEN_R(2.0) * bound[0])) {
        return CODEGEN_ROOTS_UNPROVEN;
    }
    for (int i = 0; i <= m; ++i) {
        const int k = reversed ? m - i : i;
        b[i] = codegen_ldexp(sigma[k], -e);
        db[i] = bound[k] > 0 ? codegen_ldexp(bound[k], -e) + CODEGEN_REAL_MIN : 0;
    }
    span_start(b, m, zr, zi, scratch);
    if (!aberth(b, m, zr, zi, scratch)) {
        return CODEGEN_ROOTS_UNPROVEN;
    }
    for (int i = 0; i < m; ++i) { /* for codegen_poly_real_roots_after_spans */
        SPANS_ITERATED(work, m)[i] = zr[i];
        SPANS_ITERATED(work, m)[m + i] = zi[i];
    }
    /* A coefficient exactly 0 with no error at the chart's origin is an exact root there (theta
     * = 0, or pi in the reversed chart): Aberth leaves it at 0 with an imaginary part of 1e-291
     * or so, which the test below cannot call real, and its tiny disc then missed the axis. */
    int exact_zeros = 0, at_zero = 0;
    while (exact_zeros < m && b[exact_zeros] == 0 && db[exact_zeros] == 0) {
        ++exact_zeros;
    }
    for (int i = 0; i < m; ++i) {
        at_zero += zr[i] == 0 && zi[i] == 0;
    }
    for (; at_zero < exact_zeros; ++at_zero) {   /* two or more: equal centres, unproven */
        int nearest = -1;
        for (int i = 0; i < m; ++i) {
            if ((zr[i] != 0 || zi[i] != 0)
                && (nearest < 0 || codegen_fabs(zr[i]) + codegen_fabs(zi[i])
                                   < codegen_fabs(zr[nearest]) + codegen_fabs(zi[nearest]))) {
                nearest = i;
            }
        }
        zr[nearest] = zi[nearest] = 0;
    }
    for (int i = 0; i < m; ++i) {
        if (codegen_fabs(zi[i]) <= CODEGEN_SQRT_EPSILON * codegen_fabs(zr[i])) {
            zi[i] = 0; /* (any centres would do: a pair so moved gives two discs that meet) */
        }
    }
    derivative(b, m, 1, dp);
    for (int i = 0; i <= m; ++i) {
        q[m - i] = b[i];
    }
    derivative(q, m, 1, dq);
    for (int i = 0; i < m; ++i) {
        codegen_real value = -1;
        if (zi[i] == 0) { /* polished, and its value bounded, in the chart of inclusion_radius */
            const int far = codegen_fabs(zr[i]) > 1;
            codegen_real v, mag;
            const codegen_real x = polish_real(far ? q : b, far ? dq : dp, m, far ? 1 / zr[i] : zr[i],
                                               &v, &mag);
            const codegen_real moved = far ? 1 / x : x;
            codegen_real nearest = CODEGEN_HUGE;
            for (int j = 0; j < m; ++j) {
                if (j != i) {
                    nearest = codegen_fmin(nearest, codegen_fabs(zr[j] - zr[i]) + codegen_fabs(zi[j]));
                }
            }
            /* kept where it stays closer to its start than to any other centre (the two halves
             * of a double root would otherwise meet, and a disc needs distinct centres) */
            zr[i] = codegen_fabs(moved - zr[i]) < CODEGEN_R(0.25) * nearest ? moved : zr[i];
            const codegen_real at = far ? 1 / zr[i] : zr[i];
            if (at != x) { /* where the centre stayed, or 1 / (1 / x) is not x */
                v = eval(far ? q : b, m, at, &mag);
            }
            value = real_value_bound(v, mag, m);
        }
        rad[i] = inclusion_radius(b, db, m, zr, zi, i, value);
        seg_lo[i] = value;
    }
    spread_clusters(b, db, m, zr, zi, rad, seg_lo, label, seg_hi, seg_of, dp);
    for (int i = 0; i < m; ++i) {
        if (!(rad[i] < CODEGEN_HUGE) || !isfinite(zr[i]) || !isfinite(zi[i])) {
            return CODEGEN_ROOTS_UNPROVEN;
        }
        label[i] = (codegen_real)i;
    }
    for (int i = 0; i < m; ++i) { /* discs that meet, one set */
        for (int j = i + 1; j < m; ++j) {
            const codegen_real dr = zr[i] - zr[j], di = zi[i] - zi[j];
            if (codegen_sqrt(dr * dr + di * di) <= (rad[i] + rad[j]) * (1 + CODEGEN_EPSILON)) {
                label[span_find(label, i)] = (codegen_real)span_find(label, j);
            }
        }
    }
    /* The real segments of the discs that reach the axis, sorted by their low ends. */
    for (int i = 0; i < m; ++i) {
        if (codegen_fabs(zi[i]) <= rad[i]) {
            int j = n++;
            const codegen_real lo = zr[i] - rad[i];
            while (j > 0 && seg_lo[j - 1] > lo) {
                seg_lo[j] = seg_lo[j - 1];
                seg_hi[j] = seg_hi[j - 1];
                seg_of[j] = seg_of[j - 1];
                --j;
            }
            seg_lo[j] = lo;
            seg_hi[j] = zr[i] + rad[i];
            seg_of[j] = (codegen_real)i;
        }
    }
    /* Overlapping segments, one span; each in theta, its ends moved out. */
    int count = 0;
    for (int i = 0; i < n;) {
        const int disc = (int)seg_of[i];
        codegen_real lo = seg_lo[i], hi = seg_hi[i];
        int discs = 1, alone = 1;
        for (++i; i < n && seg_lo[i] <= hi; ++i, ++discs) {
            hi = codegen_fmax(hi, seg_hi[i]);
        }
        for (int j = 0; j < m && alone; ++j) {
            alone = j == disc || span_find(label, j) != span_find(label, disc);
        }
        codegen_root_span *sp = &spans[count++];
        sp->simple = discs == 1 && alone && zi[disc] == 0;
        chart_to_theta(lo, hi, reversed, &sp->lo, &sp->hi);
        sp->theta = reversed ? theta_of_u(zr[disc]) : span_theta(zr[disc], 0);
        sp->free_lo = sp->lo;
        sp->free_hi = sp->hi;
        if (sp->simple) { /* the disc grown to half its distance from every other disc */
            codegen_real grown = CODEGEN_HUGE;
            for (int j = 0; j < m; ++j) {
                if (j != disc) {
                    const codegen_real dr = zr[disc] - zr[j], di = zi[disc] - zi[j];
                    grown = codegen_fmin(grown, CODEGEN_R(0.5) * (codegen_sqrt(dr * dr + di * di) - rad[j]));
                }
            }
            grown = codegen_fmin(grown, codegen_fmax((codegen_real)1, codegen_fabs(zr[disc])));
            if (grown > rad[disc]) {
                chart_to_theta(zr[disc] - grown, zr[disc] + grown, reversed, &sp->free_lo, &sp->free_hi);
            }
        }
        if (sp->lo <= -CR_PI) { /* written across pi */
            sp->lo += two_pi;
            sp->hi += two_pi;
        }
        { /* the grown span written as this one is (either may be written across pi) */
            codegen_real shift = 0;
            while (sp->free_lo + shift > sp->lo) {
                shift -= two_pi;
            }
            while (sp->free_lo + shift + two_pi <= sp->lo) {
                shift += two_pi;
            }
            sp->free_lo += shift;
            sp->free_hi += shift;
        }
        if (sp->theta < sp->lo) {
            sp->theta += two_pi;
        }
        sp->theta = codegen_fmin(codegen_fmax(sp->theta, sp->lo), sp->hi);
        sp->free_lo = codegen_fmin(sp->free_lo, sp->lo);
        sp->free_hi = codegen_fmax(sp->free_hi, sp->hi);
    }
    /* Sorted by lo (the reversed chart's and the moved ones are out of order), then spans
     * that meet, on the circle too, made one. */
    for (int i = 1; i < count; ++i) {
        const codegen_root_span t = spans[i];
        int j = i - 1;
        while (j >= 0 && spans[j].lo > t.lo) {
            spans[j + 1] = spans[j];
            --j;
        }
        spans[j + 1] = t;
    }
    /* Spans whose reaches meet are one (not simple); a span that is not simple reaches out by
     * SPAN_REACH, so that the isolation of its free interval meets no other span. */
    n = count;
    for (int merged = 1; merged && n > 0;) {
        merged = 0;
        for (int i = 0; i + 1 < n && !merged; ++i) {
            merged = span_reach_hi(&spans[i]) >= span_reach_lo(&spans[i + 1]);
            if (merged) {
                join_spans(&spans[i], &spans[i + 1], 0);
                for (int j = i + 2; j < n; ++j) {
                    spans[j - 1] = spans[j];
                }
                --n;
            }
        }
        if (!merged && n > 1 && span_reach_lo(&spans[0]) + two_pi <= span_reach_hi(&spans[n - 1])) {
            join_spans(&spans[n - 1], &spans[0], two_pi); /* across pi */
            for (int j = 1; j < n; ++j) {
                spans[j - 1] = spans[j];
            }
            --n;
            merged = 1;
        }
    }
    for (int i = 0; i < n; ++i) { /* each grown simple span within its neighbours' gaps */
        const codegen_root_span *below = &spans[i > 0 ? i - 1 : n - 1], *above = &spans[i + 1 < n ? i + 1 : 0];
        codegen_root_span *sp = &spans[i];
        const codegen_real floor = n == 1 ? sp->hi - two_pi : i > 0 ? below->hi : below->hi - two_pi;
        const codegen_real ceiling = n == 1 ? sp->lo + two_pi : i + 1 < n ? above->lo : above->lo + two_pi;
        sp->reach_lo = sp->lo - SPAN_REACH * (codegen_fabs(sp->lo) + 1);
        sp->reach_hi = sp->hi + SPAN_REACH * (codegen_fabs(sp->hi) + 1);
        if (!sp->simple) {
            sp->free_lo = sp->reach_lo;
            sp->free_hi = sp->reach_hi;
        } else {
            sp->free_lo = codegen_fmax(sp->free_lo, CODEGEN_R(0.5) * (floor + sp->lo));
            sp->free_hi = codegen_fmin(sp->free_hi, CODEGEN_R(0.5) * (sp->hi + ceiling));
        }
    }
    *n_spans = n;
    return CODEGEN_ROOTS_OK;
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

/* Every entry point: fast = 1 tries fast_roots before the isolation by derivatives;
 * after_spans = 1 starts fast_roots from the iteration codegen_poly_root_spans left in work
 * where its polynomial is the one fast_roots would iterate on (see below). */
static codegen_roots_status real_roots(const codegen_real *sigma, int degree, codegen_real *theta,
                                       int *n_roots, codegen_real *work, int fast,
                                       int after_spans)
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

    /* Power-of-two scaling is exact: results do not depend on the overall magnitude. The
     * spans keep their scaled polynomial where s goes: each coefficient is compared before
     * it is overwritten. */
    (void)codegen_frexp(amax, &e);
    for (int i = 0; i <= degree; ++i) {
        const codegen_real scaled = codegen_ldexp(sigma[i], -e);
        after_spans = after_spans && s[i] == scaled;
        s[i] = scaled;
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
        for (int i = 0; i <= m; ++i) {
            a[i] = s[lo + i];
            q[m - i] = s[lo + i];
        }
        int found;
        /* the spans' polynomial in the same chart and scale, with neither end coefficient 0
         * (m == degree): the very iteration fast_roots would run */
        const codegen_real *iterated = after_spans && m == degree ? SPANS_ITERATED(work, degree) : NULL;
        if (!(fast && fast_roots(a, q, m, out + nout, &found, chart, iterated))) {
            found = isolated_roots(a, q, m, out + nout, r, chart);
        }
        nout += found;
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

codegen_roots_status codegen_poly_real_roots_work(const codegen_real *sigma, int degree, codegen_real *theta,
                                                  int *n_roots, codegen_real *work)
{
    return real_roots(sigma, degree, theta, n_roots, work, 1, 0);
}

codegen_roots_status codegen_poly_real_roots_after_spans(const codegen_real *sigma, int degree,
                                                         codegen_real *theta, int *n_roots,
                                                         codegen_real *work)
{
    return real_roots(sigma, degree, theta, n_roots, work, 1, 1);
}

codegen_roots_status codegen_poly_real_roots_reference_work(const codegen_real *sigma, int degree,
                                                            codegen_real *theta, int *n_roots,
                                                            codegen_real *work)
{
    return real_roots(sigma, degree, theta, n_roots, work, 0, 0);
}
