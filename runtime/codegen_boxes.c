/*
 * codegen_boxes.c -- every zero of G: R^n -> R^n in a box, proven by Krawczyk's operator
 * (codegen_boxes.h). Hand-written (not generated). Plain C99 + libm; no allocation, no static
 * state, no I/O.
 */
#include "codegen_boxes.h"

#include <stddef.h>

/* Boxes narrower than this many ulps of their bounds in every direction are not split. */
#define RESOLUTION CODEGEN_R(16.0)
/* ... nor, where G is smooth on them but Krawczyk's test decides nothing, boxes narrower than
 * the square root of that (2^-26 of their bounds in double): near a point where G is not
 * smooth (a spring of zero length) the enclosures overestimate G by about the box's width
 * over its distance to that point, squared, and splitting on to the last ulps would take
 * ~10^15 boxes. Two zeros closer than this are reported together, as an undecided cluster. */
#define CLUSTER_RESOLUTION CODEGEN_SQRT_EPSILON
/* Where a box is halved: off its centre, so that splits avoid symmetric points where zeros
 * often sit exactly (0, the middle of the range). */
#define SPLIT CODEGEN_R(0.5078125)
/* K(X) inside X narrows X to K(X) when the widths shrink at least this much in all (else
 * X is halved); a root's box is tightened by K at most REFINE_STEPS times. */
#define NARROWING CODEGEN_R(0.5)
#define REFINE_STEPS 32
/* An epsilon-inflation tried where K(X) shrinks to this fraction of X but sticks out: the
 * zero may sit on X's face (Rump's "epsilon-inflation"). */
#define INFLATION CODEGEN_R(0.25)

typedef struct search {
    int n;
    codegen_box_enclosure enclose;
    const void *context;
    codegen_boxes *out;
    long boxes;
    /* scratch, each carved out of the caller's work: trial is the middle point's box, wide
     * an inflated box, small the box polish proves */
    codegen_iv *g, *jacobian, *g_mid, *k, *trial, *wide, *small, *proof;
    codegen_real *mid, *inverse;
    codegen_real *newton;  /* polish's Newton point, the zero to working precision */
    int converged;         /* whether that Newton iteration converged */
} search;

static codegen_real width(codegen_iv x)
{
    return x.hi - x.lo;
}

static codegen_real middle(codegen_iv x)
{
    const codegen_real m = x.lo + CODEGEN_R(0.5) * (x.hi - x.lo);
    return m < x.lo ? x.lo : m > x.hi ? x.hi : m;
}

static int enclose(search *s, const codegen_iv *x, codegen_iv *g, codegen_iv *jacobian, unsigned *flags)
{
    *flags = 0u;
    if (++s->boxes > CODEGEN_BOXES_MAX) {
        return CODEGEN_BOXES_BUDGET;
    }
    return s->enclose(s->context, x, g, jacobian, flags);
}

/* s->inverse (n x n) := the inverse of the Jacobian enclosure's midpoints, by Gauss-Jordan
 * elimination with partial pivoting on [J | I] (n x 2n); 0 where it is singular. */
static int invert_middle(search *s)
{
    const int n = s->n, w = 2 * n;
    codegen_real *a = s->inverse;
    int i, j, k;
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            a[i * w + j] = middle(s->jacobian[i * n + j]);
            a[i * w + n + j] = i == j ? 1 : 0;
        }
    }
    for (k = 0; k < n; ++k) {
        int pivot = k;
        codegen_real p;
        for (i = k + 1; i < n; ++i) {
            if (codegen_fabs(a[i * w + k]) > codegen_fabs(a[pivot * w + k])) {
                pivot = i;
            }
        }
        for (j = 0; j < w && pivot != k; ++j) {
            const codegen_real t = a[k * w + j];
            a[k * w + j] = a[pivot * w + j];
            a[pivot * w + j] = t;
        }
        p = a[k * w + k];
        if (!(p != 0) || !isfinite(p)) {
            return 0;
        }
        for (j = 0; j < w; ++j) {
            a[k * w + j] /= p;
        }
        for (i = 0; i < n; ++i) {
            const codegen_real f = a[i * w + k];
            if (i != k && f != 0) {
                for (j = 0; j < w; ++j) {
                    a[i * w + j] -= f * a[k * w + j];
                }
            }
        }
    }
    for (i = 0; i < n * w; ++i) {
        if (!isfinite(a[i])) {
            return 0;
        }
    }
    return 1;
}

/* Krawczyk's operator of the box x into s->k (s->jacobian must hold J(x)): 1 if computed,
 * 0 where it cannot be (G not smooth at the middle, or J's middle singular). */
static int krawczyk(search *s, const codegen_iv *x, int *status)
{
    const int n = s->n, w = 2 * n;
    unsigned flags;
    int i, j, l;
    for (i = 0; i < n; ++i) {
        s->mid[i] = middle(x[i]);
        s->trial[i] = codegen_iv_point(s->mid[i]);
    }
    *status = enclose(s, s->trial, s->g_mid, NULL, &flags);
    if (*status != 0 || flags != 0u || !invert_middle(s)) {
        return 0;
    }
    for (i = 0; i < n; ++i) {
        codegen_iv sum = codegen_iv_point(s->mid[i]);
        for (j = 0; j < n; ++j) {
            codegen_iv row = codegen_iv_point(i == j ? 1 : 0);
            const codegen_real y = s->inverse[i * w + n + j];
            sum = codegen_iv_sub(sum, codegen_iv_mul(codegen_iv_point(y), s->g_mid[j]));
            for (l = 0; l < n; ++l) { /* (I - Y J(x))_ij */
                row = codegen_iv_sub(row, codegen_iv_mul(codegen_iv_point(s->inverse[i * w + n + l]),
                                                         s->jacobian[l * n + j]));
            }
            sum = codegen_iv_add(sum, codegen_iv_mul(row, codegen_iv_sub(x[j], codegen_iv_point(s->mid[j]))));
        }
        s->k[i] = sum;
    }
    return 1;
}

/* How K(x) lies against x: 0 K misses x (no zero), 1 K inside x's interior (one zero), 2
 * otherwise; *shrunk whether every side of K is at most NARROWING of x's. */
static int compare(const search *s, const codegen_iv *x, int *shrunk)
{
    int i, inside = 1;
    *shrunk = 1;
    for (i = 0; i < s->n; ++i) {
        const codegen_iv k = s->k[i];
        if (!(k.lo <= x[i].hi && k.hi >= x[i].lo)) {
            return 0;
        }
        inside &= k.lo > x[i].lo && k.hi < x[i].hi;
        *shrunk &= width(k) <= NARROWING * width(x[i]);
    }
    return inside ? 1 : 2;
}

/* Whether box a (n sides) holds box b. */
static int holds(int n, const codegen_iv *a, const codegen_real *lo, const codegen_real *hi)
{
    int i;
    for (i = 0; i < n; ++i) {
        if (lo[i] < a[i].lo || hi[i] > a[i].hi) {
            return 0;
        }
    }
    return 1;
}

static int append(search *s, const codegen_iv *x, const codegen_real *point, codegen_box_kind kind)
{
    codegen_boxes *out = s->out;
    const int n = s->n;
    int i;
    if (kind != CODEGEN_BOX_ROOT && out->count > 0 && out->kind[out->count - 1] == kind) {
        /* an undecided box touching the last one (the subdivision's neighbour): their hull */
        codegen_real *lo = out->lo + (out->count - 1) * n, *hi = out->hi + (out->count - 1) * n;
        int touches = 1;
        for (i = 0; i < n; ++i) {
            touches &= x[i].lo <= hi[i] && x[i].hi >= lo[i];
        }
        if (touches) {
            for (i = 0; i < n; ++i) {
                lo[i] = codegen_fmin(lo[i], x[i].lo);
                hi[i] = codegen_fmax(hi[i], x[i].hi);
                out->point[(out->count - 1) * n + i] = CODEGEN_R(0.5) * lo[i] + CODEGEN_R(0.5) * hi[i];
            }
            return 0;
        }
    }
    if (out->count >= out->capacity) {
        return CODEGEN_BOXES_FULL;
    }
    for (i = 0; i < n; ++i) {
        out->lo[out->count * n + i] = x[i].lo;
        out->hi[out->count * n + i] = x[i].hi;
        out->point[out->count * n + i] = point != NULL ? point[i] : middle(x[i]);
    }
    out->kind[out->count++] = kind;
    return 0;
}

/* x := K(x) ∩ x until it stops shrinking (at most REFINE_STEPS times; s->k holds K(x)): x
 * keeps the zero. */
static int tighten(search *s, codegen_iv *x)
{
    const int n = s->n;
    int step, i, status = 0;
    unsigned flags;
    for (step = 0; step < REFINE_STEPS; ++step) {
        int shrunk = 0;
        for (i = 0; i < n; ++i) {
            const codegen_iv k = s->k[i];
            const codegen_iv next = codegen_iv_make(codegen_fmax(k.lo, x[i].lo), codegen_fmin(k.hi, x[i].hi));
            shrunk |= width(next) < width(x[i]);
            x[i] = next;
        }
        if (!shrunk) {
            break;
        }
        status = enclose(s, x, s->g, s->jacobian, &flags);
        if (status != 0 || flags != 0u || !krawczyk(s, x, &status)) {
            break;
        }
    }
    return status;
}

/* Newton's method from x's middle on G's point values (midpoints of their enclosures),
 * kept in x, into s->newton (s->converged says whether it converged); then the smallest box
 * around it, inside x, proven to hold a zero (K inside it) replaces x: x's only zero (a wide
 * box converges slowly by K alone). The boxes tried grow from a few ulps by factors of 8, as
 * far as the enclosures' rounding needs. x unchanged where none is proven. */
static int polish(search *s, codegen_iv *x)
{
    const int n = s->n, w = 2 * n;
    codegen_iv *z = s->small;
    unsigned flags;
    int i, j, iteration, status = 0, shrunk, widening;
    s->converged = 0;
    for (i = 0; i < n; ++i) {
        s->mid[i] = middle(x[i]);
    }
    for (iteration = 0; iteration < REFINE_STEPS; ++iteration) {
        codegen_real step = 0;
        for (i = 0; i < n; ++i) {
            z[i] = codegen_iv_point(s->mid[i]);
        }
        status = enclose(s, z, s->g, s->jacobian, &flags);
        if (status != 0 || flags != 0u || !invert_middle(s)) {
            return status;
        }
        for (i = 0; i < n; ++i) { /* mid -= J^-1 G, kept in x */
            codegen_real d = 0;
            for (j = 0; j < n; ++j) {
                d += s->inverse[i * w + n + j] * middle(s->g[j]);
            }
            z[i].lo = d;
            step = codegen_fmax(step, codegen_fabs(d) / codegen_fmax(codegen_fabs(s->mid[i]), (codegen_real)1));
        }
        for (i = 0; i < n; ++i) {
            const codegen_real next = s->mid[i] - z[i].lo;
            s->mid[i] = next < x[i].lo ? x[i].lo : next > x[i].hi ? x[i].hi : next;
        }
        if (!(step > 4 * CODEGEN_EPSILON)) {
            s->converged = 1;
            break;
        }
    }
    for (i = 0; i < n; ++i) {
        s->newton[i] = s->mid[i];
    }
    for (widening = 0; widening < 8 && status == 0; ++widening) {
        int inside = 1; /* the box around the Newton point, inside x: a few ulps, then wider */
        for (i = 0; i < n; ++i) {
            const codegen_real pad = (codegen_real)(8L << (3 * widening)) * CODEGEN_EPSILON
                                     * codegen_fmax(codegen_fabs(s->mid[i]), (codegen_real)1);
            z[i] = codegen_iv_make(codegen_fmax(s->mid[i] - pad, x[i].lo), codegen_fmin(s->mid[i] + pad, x[i].hi));
            inside &= z[i].lo > x[i].lo || z[i].hi < x[i].hi;
        }
        if (!inside) {
            break;  /* as wide as x: K on x itself decides */
        }
        status = enclose(s, z, s->g, s->jacobian, &flags);
        if (status == 0 && flags == 0u && krawczyk(s, z, &status) && compare(s, z, &shrunk) == 1) {
            for (i = 0; i < n; ++i) {
                x[i] = z[i];
            }
            return 0;
        }
    }
    if (status == 0) { /* K(x) again, for tighten */
        status = enclose(s, x, s->g, s->jacobian, &flags);
        if (status == 0 && (flags != 0u || !krawczyk(s, x, &status))) {
            for (i = 0; i < n; ++i) {
                s->k[i] = x[i];
            }
        }
    }
    return status;
}

/* A root proven in x (K(x) inside x, in s->k): tightened, then reported unless a root
 * already reported lies in x (the same zero: x holds only one). x is overwritten. */
static int proven(search *s, codegen_iv *x)
{
    const int n = s->n;
    int i, r, status;
    for (r = 0; r < s->out->count; ++r) {
        if (s->out->kind[r] == CODEGEN_BOX_ROOT && holds(n, x, s->out->lo + r * n, s->out->hi + r * n)) {
            return 0;
        }
    }
    for (i = 0; i < n; ++i) {
        s->proof[i] = x[i];
    }
    status = polish(s, s->proof);
    for (i = 0; i < n && status == 0; ++i) {
        x[i] = s->proof[i];
    }
    if (status == 0) {
        status = tighten(s, x);
    }
    for (i = 0; i < n; ++i) { /* the zero to working precision: the Newton point, in x */
        s->mid[i] = s->converged && s->newton[i] >= x[i].lo && s->newton[i] <= x[i].hi
                    ? s->newton[i] : middle(x[i]);
    }
    return status != 0 ? status : append(s, x, s->mid, CODEGEN_BOX_ROOT);
}

/* K(x) sticks out of x though it shrinks it a lot: the zero may lie on x's face. Try the box
 * around K(x) widened by INFLATION of its sides: 1 (and the root handled) if proven there. */
static int inflated(search *s, int *status)
{
    const int n = s->n;
    codegen_iv *z = s->wide;
    unsigned flags;
    int i, shrunk;
    for (i = 0; i < n; ++i) {
        const codegen_real pad = INFLATION * width(s->k[i]) + CODEGEN_EPSILON * codegen_fmax(codegen_fabs(s->k[i].lo), codegen_fabs(s->k[i].hi)) + CODEGEN_REAL_MIN;
        z[i] = codegen_iv_make(s->k[i].lo - pad, s->k[i].hi + pad);
    }
    *status = enclose(s, z, s->g, s->jacobian, &flags);
    if (*status != 0 || flags != 0u || !krawczyk(s, z, status) || compare(s, z, &shrunk) != 1) {
        return 0;
    }
    *status = proven(s, z);
    return 1;
}

/* Whether x is narrower than resolution (relative to its bounds, at least 1) on every side. */
static int resolved(const search *s, const codegen_iv *x, codegen_real resolution)
{
    int i;
    for (i = 0; i < s->n; ++i) {
        const codegen_real scale = codegen_fmax(codegen_fmax(codegen_fabs(x[i].lo), codegen_fabs(x[i].hi)), (codegen_real)1);
        if (width(x[i]) > resolution * scale) {
            return 0;
        }
    }
    return 1;
}

enum { DISCARD, DONE, NARROW, HALVE };

/* One box: what becomes of it (DISCARD: no zero; DONE: reported; NARROW: x replaced by
 * K(x) ∩ x; HALVE: split). */
static int examine(search *s, codegen_iv *x, int *outcome)
{
    const int n = s->n;
    unsigned flags;
    int status, shrunk, i;
    *outcome = DISCARD;
    status = enclose(s, x, s->g, s->jacobian, &flags);
    if (status != 0 || (flags & CODEGEN_IV_OUTSIDE)) {
        return status;
    }
    for (i = 0; i < n; ++i) {
        if (!codegen_iv_has_zero(s->g[i])) {
            return 0;
        }
    }
    if (flags & (CODEGEN_IV_POLE | CODEGEN_IV_EDGE)) {
        *outcome = resolved(s, x, RESOLUTION * CODEGEN_EPSILON) ? DONE : HALVE;
        return *outcome == DONE ? append(s, x, NULL, CODEGEN_BOX_SINGULAR) : 0;
    }
    if (krawczyk(s, x, &status)) {
        const int relation = compare(s, x, &shrunk);
        if (relation == 0) {
            return 0;
        }
        if (relation == 1) {
            *outcome = DONE;
            return proven(s, x);
        }
        if (shrunk && inflated(s, &status)) {
            /* every zero of x lies in K(x), inside the inflated box, which holds one: x is
             * accounted for */
            *outcome = DONE;
            return status;
        }
        if (status != 0) {
            return status;
        }
        if (shrunk) {
            for (i = 0; i < n; ++i) {
                x[i] = codegen_iv_make(codegen_fmax(s->k[i].lo, x[i].lo), codegen_fmin(s->k[i].hi, x[i].hi));
            }
            *outcome = NARROW;
            return 0;
        }
    } else if (status != 0) {
        return status;
    }
    if (resolved(s, x, CLUSTER_RESOLUTION)) {
        *outcome = DONE;
        return append(s, x, NULL, CODEGEN_BOX_CLUSTER);
    }
    *outcome = HALVE;
    return 0;
}

int codegen_isolate_boxes(int n, codegen_box_enclosure enclose_box, const void *context,
                          const codegen_real *lo, const codegen_real *hi, codegen_boxes *out,
                          codegen_real *work)
{
    const int depth = CODEGEN_BOXES_DEPTH(n);
    search s;
    codegen_iv *stack;
    int top = 0, status = 0, i;
    if (n < 1 || enclose_box == NULL || lo == NULL || hi == NULL || out == NULL || work == NULL
        || out->lo == NULL || out->hi == NULL || out->point == NULL || out->kind == NULL) {
        return CODEGEN_BOXES_BAD_INPUT;
    }
    for (i = 0; i < n; ++i) {
        if (!isfinite(lo[i]) || !isfinite(hi[i]) || lo[i] > hi[i]) {
            return CODEGEN_BOXES_BAD_INPUT;
        }
    }
    stack = (codegen_iv *)work;
    s.n = n;
    s.enclose = enclose_box;
    s.context = context;
    s.out = out;
    s.boxes = 0;
    s.g = stack + n * depth;
    s.jacobian = s.g + n;
    s.g_mid = s.jacobian + n * n;
    s.k = s.g_mid + n;
    s.trial = s.k + n;
    s.wide = s.trial + n;
    s.small = s.wide + n;
    s.proof = s.small + n;
    s.mid = (codegen_real *)(s.proof + n);
    s.inverse = s.mid + n;               /* n x 2n */
    s.newton = s.inverse + 2 * n * n;
    s.converged = 0;
    out->count = 0;
    for (i = 0; i < n; ++i) {
        stack[i] = codegen_iv_make(lo[i], hi[i]);
    }
    top = 1;
    while (top > 0 && status == 0) {
        codegen_iv *x = stack + (top - 1) * n;
        int outcome, widest = 0;
        status = examine(&s, x, &outcome);
        if (status != 0 || outcome == DISCARD || outcome == DONE) {
            --top;
            continue;
        }
        if (outcome == NARROW) {
            continue; /* examined again, narrowed */
        }
        if (top + 1 > depth) { /* cannot happen above RESOLUTION; never drop a box */
            status = append(&s, x, NULL, CODEGEN_BOX_CLUSTER);
            --top;
            continue;
        }
        for (i = 1; i < n; ++i) { /* halve across the widest side, relative to its size */
            const codegen_real a = width(x[i]) / codegen_fmax(codegen_fmax(codegen_fabs(x[i].lo), codegen_fabs(x[i].hi)), (codegen_real)1);
            const codegen_real b = width(x[widest]) / codegen_fmax(codegen_fmax(codegen_fabs(x[widest].lo), codegen_fabs(x[widest].hi)), (codegen_real)1);
            if (a > b) {
                widest = i;
            }
        }
        {
            codegen_iv *upper = x + n;
            const codegen_real cut = (1 - SPLIT) * x[widest].lo + SPLIT * x[widest].hi;
            for (i = 0; i < n; ++i) {
                upper[i] = x[i];
            }
            upper[widest].lo = cut;
            x[widest].hi = cut;
            ++top; /* the upper half on top: examined first */
        }
    }
    return status;
}
