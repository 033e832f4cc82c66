/*
 * codegen_runtime.h -- mechanism-independent runtime shared by the generated libraries.
 * Hand-written (not generated). Plain C99 + libm; no allocation, no mutable static state, no I/O.
 */
#ifndef CODEGEN_RUNTIME_H
#define CODEGEN_RUNTIME_H

#include <stddef.h>

#include "codegen_real.h"

#ifdef __cplusplus
extern "C" {
#endif

#ifndef CODEGEN_MAX_DEGREE
#define CODEGEN_MAX_DEGREE 64   /* largest degree the root finder accepts; its stack use grows in proportion */
#endif

/* Status of codegen_poly_real_roots. The values 0..3 deliberately equal the generated
 * libraries' generic status codes (OK, ERR_NULL_POINTER, ERR_NONFINITE, ERR_ZERO_POLYNOMIAL),
 * so a generated wrapper can pass them on unchanged; only CODEGEN_ROOTS_ERR_DEGREE (a wrong
 * degree, i.e. a bug in the caller, not bad input data) has no counterpart there. */
typedef enum codegen_roots_status {
    CODEGEN_ROOTS_OK = 0,
    CODEGEN_ROOTS_ERR_NULL_POINTER = 1,
    CODEGEN_ROOTS_ERR_NONFINITE = 2,
    CODEGEN_ROOTS_ERR_ZERO_POLYNOMIAL = 3,
    CODEGEN_ROOTS_ERR_DEGREE = 4,
    CODEGEN_ROOTS_UNPROVEN = 5  /* codegen_poly_root_spans only: no proof (see there) */
} codegen_roots_status;

/* Real roots of sum_{i=0}^{degree} sigma[i] tau^i as theta = 2 atan(tau) in (-pi, pi], ascending,
 * each distinct root once whatever its multiplicity. tau = infinity (sigma[degree] == 0, a degree
 * drop) is reported as theta = pi, tau = 0 (sigma[0] == 0) as theta = 0.
 *
 * sigma:   degree + 1 coefficients, lowest first; exactly sigma[0..degree] are read.
 * degree:  in [1, CODEGEN_MAX_DEGREE]; checked first, before any pointer is used.
 * theta:   room for degree values; receives *n_roots of them (at most degree).
 * n_roots: receives the number of roots.
 *
 * Checks, in this order: degree (CODEGEN_ROOTS_ERR_DEGREE), NULL pointers
 * (CODEGEN_ROOTS_ERR_NULL_POINTER), NaN or infinite coefficients (CODEGEN_ROOTS_ERR_NONFINITE),
 * all coefficients zero (CODEGEN_ROOTS_ERR_ZERO_POLYNOMIAL). On any error theta and *n_roots
 * are left untouched. The result does not depend on the coefficients' overall scale. Reentrant
 * and thread-safe; its working memory, CODEGEN_ROOTS_WORK(CODEGEN_MAX_DEGREE) values (8.3 KB
 * for 64 in double), is on the stack: codegen_poly_real_roots_work takes it from the caller. */
codegen_roots_status codegen_poly_real_roots(const codegen_real *sigma, int degree, codegen_real *theta,
                                             int *n_roots);

/* The values of working memory codegen_poly_real_roots_work needs for a degree. */
#define CODEGEN_ROOTS_WORK(degree) (16 * (degree) + 16)

/* codegen_poly_real_roots for any degree >= 1 (no upper bound), in the caller's working
 * memory: work has room for CODEGEN_ROOTS_WORK(degree) values (contents on return
 * unspecified). A NULL work is CODEGEN_ROOTS_ERR_NULL_POINTER. Same results, bit for bit. */
codegen_roots_status codegen_poly_real_roots_work(const codegen_real *sigma, int degree, codegen_real *theta,
                                                  int *n_roots, codegen_real *work);

/* The same contract, by the isolation on derivatives alone (codegen_roots.c, 1-5): the
 * reference that codegen_poly_real_roots_work's faster simultaneous iteration answers for,
 * which it falls back to wherever it cannot prove the same result. Slower; for tests and for
 * callers who want the one algorithm throughout. */
codegen_roots_status codegen_poly_real_roots_reference_work(const codegen_real *sigma, int degree,
                                                            codegen_real *theta, int *n_roots,
                                                            codegen_real *work);

/* Where the real roots of a polynomial known only to within bounds on its coefficients may
 * lie: an interval of angles theta = 2 atan(tau) [rad], lo <= hi, lo in (-pi - 1e-9, pi];
 * one that holds theta = pi has lo < pi < hi (hi up to lo + 2 pi): read hi - 2 pi beyond pi. */
typedef struct codegen_root_span {
    codegen_real lo, hi;
    codegen_real theta;  /* the simple root's approximation (where simple), in [lo, hi] */
    codegen_real free_lo, free_hi; /* around [lo, hi], within the gaps to the next spans;
                            where simple, no other root of any polynomial within the bounds
                            lies in it */
    codegen_real reach_lo, reach_hi; /* around [lo, hi], far enough out that G's signs at
                            its ends are decided next to a simple zero of G in the span
                            (~4e-7 rad in double); it may meet other spans */
    int simple;          /* 1: exactly one root lies in [lo, hi], real and simple; 0: any
                            number, none included (a cluster, or a complex pair near the axis) */
} codegen_root_span;

/* codegen_poly_real_roots_work on the sigma codegen_poly_root_spans last returned
 * CODEGEN_ROOTS_OK on, in the same work, unchanged since: the same results bit for bit,
 * without running again the iteration the spans ran where it is the one this would run (the
 * same polynomial in the same chart and scale). */
codegen_roots_status codegen_poly_real_roots_after_spans(const codegen_real *sigma, int degree,
                                                         codegen_real *theta, int *n_roots,
                                                         codegen_real *work);

/* The values of working memory codegen_poly_root_spans needs for a degree. */
#define CODEGEN_SPANS_WORK(degree) (16 * (degree) + 16)

/* Every real root of every polynomial sum c_i tau^i with |c_i - sigma[i]| <= bound[i], enclosed
 * in spans: the Ehrlich-Aberth iteration's approximations, then inclusion discs (Braess &
 * Hadeler; a connected union of k discs holds exactly k roots) widened by the coefficients'
 * bounds and by the evaluation's rounding, so that every polynomial within the bounds has all
 * its roots in them. A disc that misses the real axis proves that no real root lies there;
 * the discs that meet it give the spans, sorted by lo, disjoint on the circle; a span is
 * simple where it comes from one disc that meets no other, centred on the axis. theta = pi
 * (tau = infinity) is covered too: from the reversed polynomial's discs where the leading
 * coefficient may vanish. spans: room for degree; work: CODEGEN_SPANS_WORK(degree) values.
 * Returns CODEGEN_ROOTS_OK, CODEGEN_ROOTS_ERR_DEGREE (degree < 1), or
 * CODEGEN_ROOTS_UNPROVEN where it cannot prove its answer (the iteration does not converge;
 * the leading and the trailing coefficients may both vanish; a coefficient is not finite):
 * then nothing is meant by the spans. */
codegen_roots_status codegen_poly_root_spans(const codegen_real *sigma, const codegen_real *bound,
                                             int degree, codegen_root_span *spans, int *n_spans,
                                             codegen_real *work);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_RUNTIME_H */
