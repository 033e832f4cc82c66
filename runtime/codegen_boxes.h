/*
 * codegen_boxes.h -- every zero of G: R^n -> R^n in a box, each proven, by subdivision and
 * Krawczyk's operator: the certified isolation of the equilibria of a mechanism with n
 * coordinates (G the generalised forces, its Jacobian the stiffness), as codegen_isolate is
 * for one coordinate.
 *
 * For a box X with midpoint m, Y an approximate inverse of the Jacobian at m and J(X) an
 * enclosure of the Jacobian over X, Krawczyk's operator
 *     K(X) = m - Y G(m) + (I - Y J(X)) (X - m)
 * holds every zero of G in X; where K(X) lies inside X's interior, X holds exactly one zero
 * (Krawczyk 1969, Moore 1977, Rump 1983). A box whose G is kept away from 0, or whose K(X)
 * misses it, holds none. The rest is narrowed to K(X) where that shrinks it, else halved
 * across its widest side, down to what working precision resolves; what is left then is
 * reported as undecided (a cluster, or singular where G is not smooth), never dropped. A zero
 * on a face between two halves is proven from the box inflated around it (Rump's
 * epsilon-inflation), and each zero is reported once.
 *
 * Hand-written (not generated), written once for every library. Plain C99 + libm; no
 * allocation, no static state, no I/O: the caller passes the results and a work array of
 * CODEGEN_BOXES_WORK(n) reals.
 */
#ifndef CODEGEN_BOXES_H
#define CODEGEN_BOXES_H

#include "codegen_interval.h"
#include "codegen_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/* G and its Jacobian enclosed over the box x[0..n): g[0..n), and unless jacobian is NULL
 * jacobian[i * n + k] = dG_i/dx_k; the flags its operations raised (CODEGEN_IV_POLE, _EDGE,
 * _OUTSIDE). Returns 0, or a status codegen_isolate_boxes passes on unchanged. */
typedef int (*codegen_box_enclosure)(const void *context, const codegen_iv *x, codegen_iv *g,
                                     codegen_iv *jacobian, unsigned *flags);

typedef enum codegen_box_kind {
    CODEGEN_BOX_ROOT = 0,     /* exactly one zero of G in the box (Krawczyk) */
    CODEGEN_BOX_CLUSTER = 1,  /* G smooth but the box too small to decide: a multiple zero,
                                 zeros closer than working precision separates, or none */
    CODEGEN_BOX_SINGULAR = 2  /* G undefined or not smooth somewhere inside: undecided */
} codegen_box_kind;

/* The results: entry r's box is lo[r * n + k] <= x_k <= hi[r * n + k], its point (the zero to
 * working precision for a root, else the middle) point[r * n + k], its kind kind[r]. */
typedef struct codegen_boxes {
    int capacity;   /* entries the arrays hold */
    int count;      /* entries written */
    codegen_real *lo, *hi, *point;
    codegen_box_kind *kind;
} codegen_boxes;

/* Boxes waiting to be examined at most (a depth-first subdivision: each halving adds one). */
#define CODEGEN_BOXES_DEPTH(n) (64 * (n) + 8)
#define CODEGEN_BOXES_WORK(n) (2 * (n) * CODEGEN_BOXES_DEPTH(n) + 8 * (n) * (n) + 16 * (n))

/* Returned besides 0 and the enclosure's own statuses. */
#define CODEGEN_BOXES_FULL (-1)    /* more results than capacity */
#define CODEGEN_BOXES_BUDGET (-2)  /* more than CODEGEN_BOXES_MAX boxes examined */
#define CODEGEN_BOXES_BAD_INPUT (-3) /* n < 1, a NULL pointer, a box not finite or reversed */

#ifndef CODEGEN_BOXES_MAX
#define CODEGEN_BOXES_MAX 400000L
#endif

/* Every zero of G in the box lo[k] <= x_k <= hi[k] (finite, spanning few binades), each in a
 * reported box: proven roots once each, and what cannot be decided as clusters or singular
 * boxes. Adjacent undecided boxes are reported as their hull. */
int codegen_isolate_boxes(int n, codegen_box_enclosure enclose, const void *context,
                          const codegen_real *lo, const codegen_real *hi, codegen_boxes *out,
                          codegen_real *work);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_BOXES_H */
