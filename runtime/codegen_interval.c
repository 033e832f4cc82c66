/*
 * codegen_interval.c -- sin and cos of intervals, and certified isolation of zeros
 * (see codegen_interval.h). Hand-written; plain C99 + libm.
 */
#include "codegen_interval.h"

#include <stddef.h>

/* ---- sin, cos ---- */

#define TWO_PI CODEGEN_R(6.283185307179586)
#define HALF_PI CODEGEN_R(1.5707963267948966)

/* Whether phase + 2 pi k lies in [lo - slack, hi + slack] for some integer k; slack covers
 * the rounding of phase + 2 pi k and of 2 pi itself at this magnitude. */
static int holds_phase(codegen_iv a, codegen_real phase)
{
    const codegen_real slack = CODEGEN_R(8.0) * CODEGEN_EPSILON * (codegen_fabs(a.lo) + codegen_fabs(a.hi) + 1);
    const codegen_real k = codegen_ceil((a.lo - slack - phase) / TWO_PI);
    int j;
    for (j = -1; j <= 1; ++j) {
        const codegen_real x = phase + (k + (codegen_real)j) * TWO_PI;
        if (x >= a.lo - slack && x <= a.hi + slack) {
            return 1;
        }
    }
    return 0;
}

/* sin (is_sin) or cos over a: its values at the ends, widened by two ulps for libm's error,
 * and the extremes +-1 where a holds a crest (max_phase) or trough (min_phase). */
static codegen_iv periodic(codegen_iv a, int is_sin, codegen_real max_phase, codegen_real min_phase)
{
    codegen_real at_lo, at_hi, lo, hi;
    /* beyond 2^50 rad the doubles are too sparse to place a crest: the whole range */
    if (!(a.hi - a.lo < CODEGEN_R(6.0)) || !(codegen_fabs(a.lo) < CODEGEN_R(0x1p50)) || !(codegen_fabs(a.hi) < CODEGEN_R(0x1p50))) {
        return codegen_iv_make(-1, 1);
    }
    at_lo = is_sin ? codegen_sin(a.lo) : codegen_cos(a.lo);
    at_hi = a.hi == a.lo ? at_lo : is_sin ? codegen_sin(a.hi) : codegen_cos(a.hi); /* a point: once */
    lo = codegen_iv_down(codegen_iv_down(at_lo < at_hi ? at_lo : at_hi));
    hi = codegen_iv_up(codegen_iv_up(at_lo > at_hi ? at_lo : at_hi));
    if (holds_phase(a, max_phase)) {
        hi = 1;
    }
    if (holds_phase(a, min_phase)) {
        lo = -1;
    }
    return codegen_iv_make(lo < -1 ? -1 : lo, hi > 1 ? 1 : hi);
}

codegen_iv codegen_iv_cos(codegen_iv a)
{
    return periodic(a, 0, 0, TWO_PI / CODEGEN_R(2.0));
}

codegen_iv codegen_iv_sin(codegen_iv a)
{
    return periodic(a, 1, HALF_PI, -HALF_PI);
}

void codegen_iv_run(const codegen_iv_instruction *program, size_t count,
                    const codegen_iv *constants, codegen_iv *v, unsigned *flags)
{
    size_t i;
    for (i = 0; i < count; ++i) {
        const codegen_iv_instruction op = program[i];
        codegen_iv r;
        switch ((codegen_iv_operation)op.operation) {
        case CODEGEN_IV_CONST:
            r = constants[op.left];
            break;
        case CODEGEN_IV_ADD:
            r = codegen_iv_add(v[op.left], v[op.right]);
            break;
        case CODEGEN_IV_SUB:
            r = codegen_iv_sub(v[op.left], v[op.right]);
            break;
        case CODEGEN_IV_MUL:
            r = codegen_iv_mul(v[op.left], v[op.right]);
            break;
        case CODEGEN_IV_DIV:
            r = codegen_iv_div(v[op.left], v[op.right], flags);
            break;
        case CODEGEN_IV_NEG:
            r = codegen_iv_neg(v[op.left]);
            break;
        case CODEGEN_IV_POW:
            r = codegen_iv_pow(v[op.left], (int)op.right);
            break;
        case CODEGEN_IV_SQRT:
            r = codegen_iv_sqrt(v[op.left], flags);
            break;
        case CODEGEN_IV_SIN:
            r = codegen_iv_sin(v[op.left]);
            break;
        case CODEGEN_IV_ABS:
            r = codegen_iv_abs(v[op.left]);
            break;
        default: /* CODEGEN_IV_COS */
            r = codegen_iv_cos(v[op.left]);
            break;
        }
        v[op.destination] = r; /* after the operands are read: they may be the same slot */
    }
}

/* ---- isolation ---- */

#define SMOOTHNESS_FLAGS (CODEGEN_IV_POLE | CODEGEN_IV_EDGE)
/* Boxes narrower than this many ulps of their ends are not split further. */
#define RESOLUTION CODEGEN_R(16.0)
/* Refinement steps (safeguarded Newton: ~5 usually reach rounding). */
#define REFINE_STEPS 100
#define UNKNOWN_SIGN 2
/* Where a box is split: off its centre, so that splits avoid the symmetric angles (0, pi/2,
 * the range's centre) where zeros often sit exactly. */
#define SPLIT CODEGEN_R(0.5078125)

typedef struct isolation {
    codegen_enclosure enclose;
    const void *context;
    unsigned mode;
    codegen_isolated *out;
    int capacity, count;
    long boxes;
    int pending;              /* a run of unresolved boxes waiting to be merged */
    codegen_real pending_lo, pending_hi;
    unsigned pending_flags;
} isolation;

typedef codegen_isolation_box box;

static int enclose_box(isolation *s, codegen_real lo, codegen_real hi, codegen_iv *g, codegen_iv *dg,
                   unsigned *flags)
{
    *flags = 0u;
    if (++s->boxes > CODEGEN_ISOLATE_MAX_BOXES) {
        return CODEGEN_ISOLATE_BUDGET;
    }
    return s->enclose(s->context, s->mode, codegen_iv_make(lo, hi), g, dg, flags);
}

/* G's sign at theta, if the enclosure decides it (else 0), and G and G' there (midpoints of
 * their enclosures); a point where G is not smooth or the mechanism may not exist is
 * undecided. */
static int probe(isolation *s, codegen_real theta, int *sign, codegen_real *value, codegen_real *slope)
{
    codegen_iv g = {0, 0}, dg = {0, 0};
    unsigned flags;
    const int status = enclose_box(s, theta, theta, &g, &dg, &flags);
    *sign = 0;
    *value = CODEGEN_R(0.5) * g.lo + CODEGEN_R(0.5) * g.hi;
    *slope = CODEGEN_R(0.5) * dg.lo + CODEGEN_R(0.5) * dg.hi;
    if (status == 0 && !(flags & (SMOOTHNESS_FLAGS | CODEGEN_IV_OUTSIDE))) {
        *sign = g.lo > 0 ? 1 : g.hi < 0 ? -1 : 0;
    }
    return status;
}

static int sign_at(isolation *s, codegen_real theta, int *sign)
{
    codegen_real value, slope;
    return probe(s, theta, sign, &value, &slope);
}

static int known_sign(isolation *s, codegen_real theta, int *sign)
{
    return *sign != UNKNOWN_SIGN ? 0 : sign_at(s, theta, sign);
}

/* G's sign at both ends of b, each probed only if not yet known. */
static int end_signs(isolation *s, box *b)
{
    const int status = known_sign(s, b->lo, &b->sign_lo);
    return status != 0 ? status : known_sign(s, b->hi, &b->sign_hi);
}

static int append(isolation *s, codegen_real lo, codegen_real hi, codegen_real theta, codegen_isolated_kind kind,
                  int sign_change)
{
    codegen_isolated *r;
    if (s->count >= s->capacity) {
        return CODEGEN_ISOLATE_FULL;
    }
    r = &s->out[s->count++];
    r->lo = lo;
    r->hi = hi;
    r->theta = theta;
    r->kind = kind;
    r->sign_change = sign_change;
    return 0;
}

/* theta's sign is within rounding: the bracket [*lo, *hi] closes in on it from both sides,
 * with steps growing eightfold from a few ulps, as far as signs are decided there. */
static int tighten(isolation *s, codegen_real theta, codegen_real *lo, codegen_real *hi, int sign_lo)
{
    codegen_real step;
    int sign, status = 0, left = 0, right = 0;
    for (step = CODEGEN_R(4.0) * CODEGEN_EPSILON * codegen_fmax(codegen_fabs(theta), (codegen_real)1); status == 0 && !(left && right)
         && step < *hi - *lo; step *= CODEGEN_R(8.0)) {
        if (!left && theta - step > *lo) {
            status = sign_at(s, theta - step, &sign);
            if (sign == sign_lo) {
                *lo = theta - step;
                left = 1;
            }
        }
        if (status == 0 && !right && theta + step < *hi) {
            status = sign_at(s, theta + step, &sign);
            if (sign == -sign_lo) {
                *hi = theta + step;
                right = 1;
            }
        }
    }
    return status;
}

/* [lo, hi] holds one simple zero (G monotone, signs at the ends opposite): narrow it by
 * Newton's method, each step kept inside the bracket (else a bisection), the bracket kept
 * proven by deciding each new point's sign with the enclosure, until a point's sign is
 * within rounding (that point is the zero to working precision; tighten then closes the
 * bracket around it) or the bracket reaches adjacent doubles. */
static int refine(isolation *s, codegen_real lo, codegen_real hi, int sign_lo)
{
    codegen_real theta = lo + CODEGEN_R(0.5) * (hi - lo);
    int sign, status = 0, i;
    for (i = 0; i < REFINE_STEPS; ++i) {
        codegen_real value, slope, next;
        status = probe(s, theta, &sign, &value, &slope);
        if (status == 0 && sign == 0) {
            status = tighten(s, theta, &lo, &hi, sign_lo);
            /* G's rounding hides the sign here, but its midpoint still points at the zero:
             * one last Newton step, kept inside the proven bracket */
            next = theta - value / slope;
            theta = next >= lo && next <= hi ? next : theta;
        }
        if (status != 0 || sign == 0) {
            break;
        }
        if (sign == sign_lo) {
            lo = theta;
        } else {
            hi = theta;
        }
        next = theta - value / slope;
        if (!(next > lo && next < hi)) {
            next = lo + CODEGEN_R(0.5) * (hi - lo);
        }
        if (!(next > lo && next < hi)) {
            break; /* lo and hi are adjacent doubles; theta is one of them */
        }
        theta = next;
    }
    return status != 0 ? status : append(s, lo, hi, theta, CODEGEN_ISOLATED_ROOT, 1);
}

/* Whether [lo, hi] is decided as a whole: 1 in *decided if it holds no zero or one, 0 if the
 * enclosures cannot tell; *zero = 1 if one, proven (G monotone, opposite signs at the ends). */
static int judge(isolation *s, box *b, codegen_iv dg, unsigned flags, int *decided, int *zero)
{
    int status;
    *decided = *zero = 0;
    if ((flags & SMOOTHNESS_FLAGS) || codegen_iv_has_zero(dg)) {
        return 0;
    }
    status = end_signs(s, b);
    if (status != 0 || b->sign_lo == 0 || b->sign_hi == 0) {
        return status;
    }
    *decided = 1;
    *zero = b->sign_lo != b->sign_hi;
    return 0;
}

/* The pending run of unresolved boxes, merged: certified if the merged interval now
 * decides (a zero on a split point lands here), else a cluster or a singular interval.
 * (Nothing is pending while it is decided: no recursion, so the stack it takes is bounded.) */
static int flush(isolation *s)
{
    box b;
    codegen_iv g, dg;
    unsigned flags;
    int status, decided = 0, zero = 0;
    if (!s->pending) {
        return 0;
    }
    s->pending = 0;
    b.lo = s->pending_lo;
    b.hi = s->pending_hi;
    b.sign_lo = b.sign_hi = UNKNOWN_SIGN;
    status = enclose_box(s, b.lo, b.hi, &g, &dg, &flags);
    if (status == 0) {
        status = judge(s, &b, dg, flags | s->pending_flags, &decided, &zero);
    }
    if (status != 0 || decided) {
        return status != 0 || !zero ? status : refine(s, b.lo, b.hi, b.sign_lo);
    }
    status = end_signs(s, &b);
    return status != 0 ? status
         : append(s, b.lo, b.hi, CODEGEN_R(0.5) * b.lo + CODEGEN_R(0.5) * b.hi,
                  ((flags | s->pending_flags) & SMOOTHNESS_FLAGS) != 0u ? CODEGEN_ISOLATED_SINGULAR
                                                                         : CODEGEN_ISOLATED_CLUSTER,
                  b.sign_lo * b.sign_hi < 0);
}

/* judge, and a proven zero refined after the unresolved boxes to its left. */
static int decide(isolation *s, box *b, codegen_iv dg, unsigned flags, int *decided)
{
    int zero;
    int status = judge(s, b, dg, flags, decided, &zero);
    if (status != 0 || !zero) {
        return status;
    }
    status = flush(s);
    return status != 0 ? status : refine(s, b->lo, b->hi, b->sign_lo);
}

static int unresolved(isolation *s, const box *b, unsigned flags)
{
    if (s->pending && s->pending_hi == b->lo) {
        s->pending_hi = b->hi;
        s->pending_flags |= flags;
        return 0;
    }
    {
        const int status = flush(s);
        s->pending = 1;
        s->pending_lo = b->lo;
        s->pending_hi = b->hi;
        s->pending_flags = flags;
        return status;
    }
}

/* Whether G is not smooth (or the mechanism may not exist) at theta itself, enclosed as a point:
 * within rounding of a pole or a square root's zero. */
static int rough_at(isolation *s, codegen_real theta, int *rough)
{
    codegen_iv g, dg;
    unsigned flags;
    const int status = enclose_box(s, theta, theta, &g, &dg, &flags);
    *rough = status == 0 && (flags & SMOOTHNESS_FLAGS) != 0u && !(flags & CODEGEN_IV_OUTSIDE);
    return status;
}

/* Whether b is as narrow as double resolves (absolute for |theta| < 1), or, where G is
 * smooth, G's sign is within rounding at both ends and the middle: splitting cannot decide
 * more (a fold, or a zero where G's rounding spreads wide). A box where G is not smooth is split
 * down to the resolution (its ends may lie outside the mechanism's domain, its middle not),
 * unless it is narrow (SQRT_EPSILON of its angle) and G is not smooth even at its ends and its
 * middle as points: a square root whose argument only touches zero (a four-bar's change point)
 * stays within rounding of zero over ~1e-7 rad, which would take ~1e8 boxes of the resolution. */
static int hopeless(isolation *s, box *b, codegen_real mid, codegen_iv g_mid, unsigned flags,
                    int *result)
{
    const codegen_real scale = codegen_fmax(codegen_fmax(codegen_fabs(b->lo), codegen_fabs(b->hi)), (codegen_real)1);
    int status = 0;
    *result = b->hi - b->lo <= RESOLUTION * CODEGEN_EPSILON * scale || !(mid > b->lo && mid < b->hi);
    if (*result) {
        return 0;
    }
    if (flags & SMOOTHNESS_FLAGS) {
        int rough = b->hi - b->lo <= CODEGEN_SQRT_EPSILON * scale;
        if (rough) {
            status = rough_at(s, b->lo, &rough);
        }
        if (status == 0 && rough) {
            status = rough_at(s, b->hi, &rough);
        }
        if (status == 0 && rough) {
            status = rough_at(s, mid, &rough);
        }
        *result = status == 0 && rough;
        return status;
    }
    if (!codegen_iv_has_zero(g_mid)) {
        return 0;
    }
    status = end_signs(s, b);
    *result = status == 0 && b->sign_lo == 0 && b->sign_hi == 0;
    return status;
}

/* Where to split [lo, hi]: off-centre (SPLIT); across many binades at their geometric middle
 * (or at 0 when the box holds it), so that reaching a zero near 1 from 1e300 takes ~10
 * splits, not ~1000, and the stack suffices. */
static codegen_real split_point(codegen_real lo, codegen_real hi)
{
    const codegen_real wide = CODEGEN_R(64.0);
    if (lo < 0 && hi > 0 && (hi > wide || -lo > wide)) {
        return 0;
    }
    if (lo >= 0 && hi > wide * codegen_fmax(lo, (codegen_real)1)) {
        return codegen_sqrt(codegen_fmax(lo, (codegen_real)1)) * codegen_sqrt(hi);
    }
    if (hi <= 0 && -lo > wide * codegen_fmax(-hi, (codegen_real)1)) {
        return -codegen_sqrt(codegen_fmax(-hi, (codegen_real)1)) * codegen_sqrt(-lo);
    }
    return (1 - SPLIT) * lo + SPLIT * hi; /* (hi - lo may overflow) */
}

/* One box of the subdivision: 0 and *split = 1 when its halves must be examined. */
static int examine(isolation *s, box *b, codegen_real *mid, int *mid_sign, int *split)
{
    codegen_iv g, dg, g_mid, dg_mid;
    unsigned flags, mid_flags = 0u;
    int status, decided, stop;
    *split = 0;
    *mid = split_point(b->lo, b->hi);
    *mid_sign = UNKNOWN_SIGN;
    status = enclose_box(s, b->lo, b->hi, &g, &dg, &flags);
    if (status != 0 || (flags & CODEGEN_IV_OUTSIDE) || !codegen_iv_has_zero(g)) {
        return status; /* no state of the mechanism, or G kept away from 0 */
    }
    g_mid = codegen_iv_whole();
    if (!(flags & SMOOTHNESS_FLAGS)) {
        /* mean-value form: G(box) lies in G(mid) + G'(box) (box - mid) */
        status = enclose_box(s, *mid, *mid, &g_mid, &dg_mid, &mid_flags);
        if (status != 0) {
            return status;
        }
        if (!mid_flags) {
            const codegen_iv offset = codegen_iv_make(b->lo - *mid, b->hi - *mid);
            *mid_sign = g_mid.lo > 0 ? 1 : g_mid.hi < 0 ? -1 : 0;
            if (!codegen_iv_has_zero(codegen_iv_add(g_mid, codegen_iv_mul(dg, offset)))) {
                return 0;
            }
        }
        status = decide(s, b, dg, flags, &decided);
        if (status != 0 || decided) {
            return status;
        }
    }
    status = hopeless(s, b, *mid, g_mid, flags, &stop);
    if (status != 0) {
        return status;
    }
    if (stop) {
        return unresolved(s, b, flags);
    }
    *split = 1;
    return 0;
}

static void start(isolation *s, codegen_enclosure enclose, const void *context, unsigned mode,
                  codegen_isolated *out, int capacity)
{
    s->enclose = enclose;
    s->context = context;
    s->mode = mode;
    s->out = out;
    s->capacity = capacity;
    s->count = 0;
    s->boxes = 0;
    s->pending = 0;
    s->pending_lo = s->pending_hi = 0;
    s->pending_flags = 0u;
}

int codegen_isolate(codegen_enclosure enclose, const void *context, unsigned mode, codegen_real lo,
                    codegen_real hi, codegen_isolated *out, int capacity, int *count)
{
    box stack[CODEGEN_ISOLATE_DEPTH];
    return codegen_isolate_work(enclose, context, mode, lo, hi, out, capacity, count, stack);
}

int codegen_isolate_work(codegen_enclosure enclose, const void *context, unsigned mode,
                         codegen_real lo, codegen_real hi, codegen_isolated *out, int capacity,
                         int *count, codegen_isolation_box *stack)
{
    isolation s;
    int top = 0, status = 0;
    start(&s, enclose, context, mode, out, capacity);
    stack[top].lo = lo;
    stack[top].hi = hi;
    stack[top].sign_lo = stack[top].sign_hi = UNKNOWN_SIGN;
    ++top;
    while (top > 0 && status == 0) {
        box b = stack[--top];
        codegen_real mid;
        int mid_sign, split;
        status = examine(&s, &b, &mid, &mid_sign, &split);
        if (status != 0 || !split) {
            continue;
        }
        if (top + 2 > CODEGEN_ISOLATE_DEPTH) { /* cannot happen above RESOLUTION; never drop a box */
            status = unresolved(&s, &b, 0u);
            continue;
        }
        /* the right half below the left, so boxes leave the stack in ascending order */
        stack[top].lo = mid;
        stack[top].hi = b.hi;
        stack[top].sign_lo = mid_sign;
        stack[top].sign_hi = b.sign_hi;
        ++top;
        stack[top].lo = b.lo;
        stack[top].hi = mid;
        stack[top].sign_lo = b.sign_lo;
        stack[top].sign_hi = mid_sign;
        ++top;
    }
    if (status == 0) {
        status = flush(&s);
    }
    *count = s.count;
    return status;
}

int codegen_certify(codegen_enclosure enclose, const void *context, unsigned mode, codegen_real lo,
                    codegen_real hi, int *certified)
{
    isolation s;
    box b;
    codegen_iv g, dg;
    unsigned flags;
    codegen_isolated found;
    int status;
    start(&s, enclose, context, mode, &found, 1);
    *certified = 0;
    status = enclose_box(&s, lo, hi, &g, &dg, &flags);
    if (status == 0 && !(flags & (SMOOTHNESS_FLAGS | CODEGEN_IV_OUTSIDE))
        && !codegen_iv_has_zero(dg)) {
        b.lo = lo;
        b.hi = hi;
        b.sign_lo = b.sign_hi = UNKNOWN_SIGN;
        status = end_signs(&s, &b);
        *certified = status == 0 && b.sign_lo * b.sign_hi < 0;
    }
    return status;
}

/* Moore's interval Newton test. With 0 outside G'(X) on X = [m - w, m + w], every zero x of G
 * in X satisfies x = m - G(m) / G'(xi) for some xi in X, so it lies in N = m - G([m]) / G'(X);
 * and N inside X proves that X holds exactly one zero. The width comes from the Newton step's
 * own bound, |G([m])| / |G'(m)|, doubled for the spread of G' over X, plus a few ulps of m,
 * and is tried once more sixteen times wider: two enclosures a try (the one at m of G alone
 * when the caller knows the slope), where guessing widths for codegen_certify costs three
 * each. X's enclosure covers m: non-smoothness at m is seen there. */
int codegen_certify_newton(codegen_enclosure enclose, const void *context, unsigned mode,
                           codegen_real m, codegen_real slope, codegen_real *lo, codegen_real *hi,
                           int *certified)
{
    codegen_iv g_m, dg_m;
    unsigned flags = 0u;
    codegen_real w;
    int attempt, status;
    const int known = slope != 0 && isfinite(slope);
    *certified = 0;
    status = enclose(context, mode, codegen_iv_point(m), &g_m, known ? NULL : &dg_m, &flags);
    if (status != 0 || (flags & (SMOOTHNESS_FLAGS | CODEGEN_IV_OUTSIDE)) != 0u
        || (!known && codegen_iv_has_zero(dg_m))) {
        return status;
    }
    w = CODEGEN_R(2.0) * codegen_fmax(codegen_fabs(g_m.lo), codegen_fabs(g_m.hi))
          / (known ? codegen_fabs(slope) : codegen_fmin(codegen_fabs(dg_m.lo), codegen_fabs(dg_m.hi)))
        + CODEGEN_R(8.0) * CODEGEN_EPSILON * codegen_fmax(codegen_fabs(m), (codegen_real)1);
    for (attempt = 0; attempt < 2 && !*certified; ++attempt, w *= CODEGEN_R(16.0)) {
        const codegen_iv x = codegen_iv_make(m - w, m + w);
        codegen_iv g_x, dg_x, n;
        flags = 0u;
        status = enclose(context, mode, x, &g_x, &dg_x, &flags);
        if (status != 0) {
            return status;
        }
        if ((flags & (SMOOTHNESS_FLAGS | CODEGEN_IV_OUTSIDE)) != 0u || codegen_iv_has_zero(dg_x)) {
            continue;
        }
        n = codegen_iv_sub(codegen_iv_point(m), codegen_iv_div(g_m, dg_x, &flags));
        if (n.lo > x.lo && n.hi < x.hi) {
            *certified = 1;
            *lo = x.lo;
            *hi = x.hi;
        }
    }
    return 0;
}
