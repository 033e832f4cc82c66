/*
 * codegen_interval.h -- interval arithmetic with outward rounding, and certified isolation of
 * the zeros of a function from enclosures of it and its derivative.
 * Hand-written (not generated). Plain C99 + libm; no allocation, no mutable static state, no I/O.
 *
 * Rounding: every operation is computed in the default rounding mode (to nearest) and its
 * bounds moved outward past the rounding error: by one unit in the last place (ulp) for
 * +, -, *, / and sqrt (correctly rounded by IEEE 754), by two for sin and cos (libm's are
 * within one ulp on glibc, musl and newlib). An enclosure therefore holds every value the
 * expression takes for any real arguments inside the argument intervals. This needs IEEE
 * double evaluated in double (FLT_EVAL_METHOD 0: SSE2, AArch64, soft-float ARM; not x87),
 * round-to-nearest, and no -ffast-math (-ffinite-math-only would drop the infinities that
 * stand for unbounded enclosures). Contraction into fma is harmless: it can only tighten.
 */
#ifndef CODEGEN_INTERVAL_H
#define CODEGEN_INTERVAL_H

#include <stddef.h>

#include "codegen_real.h"

#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0
#error "codegen_interval.h: needs each type evaluated in its own precision (FLT_EVAL_METHOD 0; use -msse2 -mfpmath=sse on x86)"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The closed interval [lo, hi]; lo may be -HUGE_VAL and hi HUGE_VAL (unbounded). */
typedef struct codegen_iv {
    codegen_real lo, hi;
} codegen_iv;

/* What an enclosure met on the way, or-ed together by the operations that notice it. */
#define CODEGEN_IV_POLE 1u    /* a divisor's enclosure holds 0: the value may be undefined */
#define CODEGEN_IV_EDGE 2u    /* a radicand's enclosure reaches below 0: a square root may be
                                 0 inside (a limit position, a length through zero), or the
                                 mechanism may not exist on part of the interval */
#define CODEGEN_IV_OUTSIDE 4u /* a radicand is below 0 on the whole interval: no state there */

/* The next double below / above x: a bound on any real that rounds to x. */
static inline codegen_real codegen_iv_down(codegen_real x)
{
    return x == CODEGEN_HUGE ? CODEGEN_REAL_MAX : x - (codegen_fabs(x) * CODEGEN_EPSILON + CODEGEN_REAL_TRUE_MIN);
}

static inline codegen_real codegen_iv_up(codegen_real x)
{
    return x == -CODEGEN_HUGE ? -CODEGEN_REAL_MAX : x + (codegen_fabs(x) * CODEGEN_EPSILON + CODEGEN_REAL_TRUE_MIN);
}

static inline codegen_iv codegen_iv_make(codegen_real lo, codegen_real hi)
{
    codegen_iv r;
    r.lo = lo;
    r.hi = hi;
    return r;
}

static inline codegen_iv codegen_iv_point(codegen_real x)
{
    return codegen_iv_make(x, x);
}

static inline int codegen_iv_has_zero(codegen_iv x)
{
    return !(x.lo > 0 || x.hi < 0); /* a NaN bound counts as holding everything */
}

/* A sum with one operand exactly 0 is exact: no widening (so 0 + 0 stays 0, and a sum of
 * squares cannot dip below zero). */
static inline codegen_real codegen_iv_sum_down(codegen_real a, codegen_real b)
{
    return a == 0 ? b : b == 0 ? a : codegen_iv_down(a + b);
}

static inline codegen_real codegen_iv_sum_up(codegen_real a, codegen_real b)
{
    return a == 0 ? b : b == 0 ? a : codegen_iv_up(a + b);
}

static inline codegen_iv codegen_iv_add(codegen_iv a, codegen_iv b)
{
    return codegen_iv_make(codegen_iv_sum_down(a.lo, b.lo), codegen_iv_sum_up(a.hi, b.hi));
}

static inline codegen_iv codegen_iv_neg(codegen_iv a)
{
    return codegen_iv_make(-a.hi, -a.lo);
}

/* |a|, exact (no rounding): a, -a, or [0, max(-lo, hi)] across zero. It arises where a
 * length's radicand holds a square factor of a sign (sqrt(n cos^2 theta) = sqrt(n) |cos|). */
static inline codegen_iv codegen_iv_abs(codegen_iv a)
{
    if (a.lo >= 0) {
        return a;
    }
    if (a.hi <= 0) {
        return codegen_iv_neg(a);
    }
    return codegen_iv_make(0, -a.lo > a.hi ? -a.lo : a.hi);
}

static inline codegen_iv codegen_iv_sub(codegen_iv a, codegen_iv b)
{
    return codegen_iv_add(a, codegen_iv_neg(b));
}

/* Bounds on x * y and x / y: exactly 0 when x (or y, for the product) is 0 -- so 0 * infinity
 * counts as 0, the bounds standing for finite values -- and moved outward otherwise (an
 * underflow to 0 included). */
static inline codegen_real codegen_iv_mul_down(codegen_real x, codegen_real y)
{
    return x == 0 || y == 0 ? 0 : codegen_iv_down(x * y);
}

static inline codegen_real codegen_iv_mul_up(codegen_real x, codegen_real y)
{
    return x == 0 || y == 0 ? 0 : codegen_iv_up(x * y);
}

/* (infinity / infinity is NaN: unbounded in the bound's direction) */
static inline codegen_real codegen_iv_div_down(codegen_real x, codegen_real y)
{
    const codegen_real q = x / y;
    return x == 0 ? 0 : q != q ? -CODEGEN_HUGE : codegen_iv_down(q);
}

static inline codegen_real codegen_iv_div_up(codegen_real x, codegen_real y)
{
    const codegen_real q = x / y;
    return x == 0 ? 0 : q != q ? CODEGEN_HUGE : codegen_iv_up(q);
}

static inline codegen_real codegen_iv_min4(codegen_real a, codegen_real b, codegen_real c, codegen_real d)
{
    const codegen_real ab = a < b ? a : b, cd = c < d ? c : d;
    return ab < cd ? ab : cd;
}

static inline codegen_real codegen_iv_max4(codegen_real a, codegen_real b, codegen_real c, codegen_real d)
{
    const codegen_real ab = a > b ? a : b, cd = c > d ? c : d;
    return ab > cd ? ab : cd;
}

/* Bounds that cannot cross 0 (an underflow widened outward would). */
static inline codegen_real codegen_iv_at_least_0(codegen_real x)
{
    return x < 0 ? 0 : x;
}

/* By the signs of the factors: two products where neither interval holds 0 inside. */
static inline codegen_iv codegen_iv_mul(codegen_iv a, codegen_iv b)
{
    if (a.lo >= 0) {
        return b.lo >= 0 ? codegen_iv_make(codegen_iv_at_least_0(codegen_iv_mul_down(a.lo, b.lo)), codegen_iv_mul_up(a.hi, b.hi))
             : b.hi <= 0 ? codegen_iv_make(codegen_iv_mul_down(a.hi, b.lo), codegen_iv_mul_up(a.lo, b.hi))
             : codegen_iv_make(codegen_iv_mul_down(a.hi, b.lo), codegen_iv_mul_up(a.hi, b.hi));
    }
    if (a.hi <= 0) {
        return b.lo >= 0 ? codegen_iv_make(codegen_iv_mul_down(a.lo, b.hi), codegen_iv_mul_up(a.hi, b.lo))
             : b.hi <= 0 ? codegen_iv_make(codegen_iv_at_least_0(codegen_iv_mul_down(a.hi, b.hi)), codegen_iv_mul_up(a.lo, b.lo))
             : codegen_iv_make(codegen_iv_mul_down(a.lo, b.hi), codegen_iv_mul_up(a.lo, b.lo));
    }
    if (b.lo >= 0) {
        return codegen_iv_make(codegen_iv_mul_down(a.lo, b.hi), codegen_iv_mul_up(a.hi, b.hi));
    }
    if (b.hi <= 0) {
        return codegen_iv_make(codegen_iv_mul_down(a.hi, b.lo), codegen_iv_mul_up(a.lo, b.lo));
    }
    return codegen_iv_make( /* both hold 0 inside */
        codegen_iv_min4(codegen_iv_mul_down(a.lo, b.lo), codegen_iv_mul_down(a.lo, b.hi),
                        codegen_iv_mul_down(a.hi, b.lo), codegen_iv_mul_down(a.hi, b.hi)),
        codegen_iv_max4(codegen_iv_mul_up(a.lo, b.lo), codegen_iv_mul_up(a.lo, b.hi),
                        codegen_iv_mul_up(a.hi, b.lo), codegen_iv_mul_up(a.hi, b.hi)));
}

static inline codegen_iv codegen_iv_whole(void)
{
    return codegen_iv_make(-CODEGEN_HUGE, CODEGEN_HUGE);
}

static inline codegen_iv codegen_iv_div(codegen_iv a, codegen_iv b, unsigned *flags)
{
    codegen_iv r;
    if (codegen_iv_has_zero(b)) {
        *flags |= CODEGEN_IV_POLE;
        return codegen_iv_whole();
    }
    r = codegen_iv_make(
        codegen_iv_min4(codegen_iv_div_down(a.lo, b.lo), codegen_iv_div_down(a.lo, b.hi),
                        codegen_iv_div_down(a.hi, b.lo), codegen_iv_div_down(a.hi, b.hi)),
        codegen_iv_max4(codegen_iv_div_up(a.lo, b.lo), codegen_iv_div_up(a.lo, b.hi),
                        codegen_iv_div_up(a.hi, b.lo), codegen_iv_div_up(a.hi, b.hi)));
    return r.lo == r.lo && r.hi == r.hi ? r : codegen_iv_whole(); /* infinity / infinity */
}

/* x^n of one double, enclosed (n >= 1): square-and-multiply, ~log2(n) roundings, the first
 * factor taken as it is (no product with 1). */
static inline codegen_iv codegen_iv_point_pow(codegen_real x, int n)
{
    codegen_iv base = codegen_iv_point(x), result = base;
    int started = 0;
    while (n > 0) {
        if (n & 1) {
            result = started ? codegen_iv_mul(result, base) : base;
            started = 1;
        }
        n >>= 1;
        if (n > 0) {
            base = codegen_iv_mul(base, base);
        }
    }
    return result;
}

/* a^n for an integer n >= 1: monotone for odd n, |.|-monotone for even n (so x^2 of an
 * interval around 0 starts at 0, as x * x would not). */
static inline codegen_iv codegen_iv_pow(codegen_iv a, int n)
{
    const codegen_iv lo = codegen_iv_point_pow(a.lo, n);
    const codegen_iv hi = a.hi == a.lo ? lo : codegen_iv_point_pow(a.hi, n);
    if (n % 2 == 1) {
        return codegen_iv_make(lo.lo, hi.hi);
    }
    if (a.lo >= 0) {
        return codegen_iv_make(codegen_iv_at_least_0(lo.lo), hi.hi);
    }
    if (a.hi <= 0) {
        return codegen_iv_make(codegen_iv_at_least_0(hi.lo), lo.hi);
    }
    return codegen_iv_make(0, lo.hi > hi.hi ? lo.hi : hi.hi);
}

static inline codegen_iv codegen_iv_sqrt(codegen_iv a, unsigned *flags)
{
    if (a.hi < 0) {
        *flags |= CODEGEN_IV_OUTSIDE;
        return codegen_iv_make(0, 0);
    }
    if (!(a.lo > 0)) { /* 0 or below (or NaN): the root may be 0 inside */
        *flags |= CODEGEN_IV_EDGE;
        return codegen_iv_make(0, codegen_iv_up(codegen_sqrt(a.hi)));
    }
    {
        const codegen_real lo = codegen_iv_down(codegen_sqrt(a.lo));
        return codegen_iv_make(lo > 0 ? lo : 0, codegen_iv_up(codegen_sqrt(a.hi)));
    }
}

/* cos over [lo, hi] and sin (as cos(x - pi/2)) are defined in codegen_interval.c. */
codegen_iv codegen_iv_cos(codegen_iv a);
codegen_iv codegen_iv_sin(codegen_iv a);

/* ---- Interval programs ---- */

/* A long enclosure written as inline calls, one local per operation, is fastest where the
 * compiler keeps them in registers, but on a 32-bit target with single-precision registers
 * it gives temporaries their own stack slots (gcc on a Cortex-M4: 19 KB in one frame for the
 * four-bar). As a table of three-address instructions over caller-provided slots, run by
 * codegen_iv_run, it needs only the slots, reused as soon as a value is consumed, and far less
 * code. Each instruction calls the operation above that the inline form calls, so both give
 * the same bounds bit for bit. The generated libraries take the inline form where
 * CODEGEN_INLINE_INTERVALS is defined, as it is by default on 64-bit x86 and ARM (frames of
 * a few hundred bytes there, and analyses ~10 % faster), and the programs otherwise: define
 * CODEGEN_INTERVAL_PROGRAMS for them on any target (a thread with a small stack, less code). */
#if defined(CODEGEN_INLINE_INTERVALS) && defined(CODEGEN_INTERVAL_PROGRAMS)
#error "codegen_interval.h: CODEGEN_INLINE_INTERVALS and CODEGEN_INTERVAL_PROGRAMS both defined"
#endif
#if !defined(CODEGEN_INLINE_INTERVALS) && !defined(CODEGEN_INTERVAL_PROGRAMS) \
    && (defined(__x86_64__) || defined(_M_X64) || defined(__aarch64__) || defined(_M_ARM64))
#define CODEGEN_INLINE_INTERVALS 1
#endif
typedef enum codegen_iv_operation {
    CODEGEN_IV_CONST, /* v[destination] = constants[left] */
    CODEGEN_IV_ADD,   /* v[destination] = v[left] + v[right] */
    CODEGEN_IV_SUB,
    CODEGEN_IV_MUL,
    CODEGEN_IV_DIV,   /* raises CODEGEN_IV_POLE */
    CODEGEN_IV_NEG,   /* v[destination] = -v[left] */
    CODEGEN_IV_POW,   /* v[destination] = v[left]^right */
    CODEGEN_IV_SQRT,  /* raises CODEGEN_IV_EDGE, CODEGEN_IV_OUTSIDE */
    CODEGEN_IV_SIN,
    CODEGEN_IV_COS,
    CODEGEN_IV_ABS    /* v[destination] = |v[left]| */
} codegen_iv_operation;

typedef struct codegen_iv_instruction {
    unsigned short operation, destination, left, right;
} codegen_iv_instruction;

/* Runs count instructions in order over the slots v (operands are read before the
 * destination is written, so they may coincide); flags collects what the operations raise. */
void codegen_iv_run(const codegen_iv_instruction *program, size_t count,
                    const codegen_iv *constants, codegen_iv *v, unsigned *flags);

/* ---- Certified isolation of the zeros of G on an interval ---- */

/* Enclosures of G and G' over theta for one assembly mode (or branch) of a mechanism,
 * and the flags its square roots and divisions raised. With dg NULL, G alone (cheaper; the
 * flags are then those of G's own operations); with g NULL too, the flags alone, from G's
 * divisions and square roots (cheaper still: whether G is smooth over theta; the analysis'
 * sign tests ask it of the generated enclosures, codegen_isolate never does). Returns 0, or a
 * nonzero status that codegen_isolate passes on unchanged (bad parameters, say). */
typedef int (*codegen_enclosure)(const void *context, unsigned mode, codegen_iv theta,
                                 codegen_iv *g, codegen_iv *dg, unsigned *flags);

typedef enum codegen_isolated_kind {
    CODEGEN_ISOLATED_ROOT = 0,     /* exactly one zero of G, simple: G changes sign at the
                                      ends and G' keeps its sign over the interval */
    CODEGEN_ISOLATED_CLUSTER = 1,  /* G and G' both within rounding of 0 over the interval: a
                                      double root, a pair closer than double can separate,
                                      or a near-double pair of complex roots (no zero) */
    CODEGEN_ISOLATED_SINGULAR = 2  /* G is undefined, or not smooth, somewhere inside (a pole,
                                      a limit position): no zero is claimed or excluded */
} codegen_isolated_kind;

typedef struct codegen_isolated {
    codegen_real lo, hi;   /* the interval */
    codegen_real theta;    /* ROOT: the zero to working precision; otherwise the midpoint */
    codegen_isolated_kind kind;
    int sign_change; /* G's sign is decided at both ends, and differs: an odd number of
                        zeros inside if G is continuous there */
} codegen_isolated;

/* Returned by codegen_isolate besides 0 and the enclosure's own statuses. */
#define CODEGEN_ISOLATE_FULL (-1)    /* more results than capacity */
#define CODEGEN_ISOLATE_BUDGET (-2)  /* more than CODEGEN_ISOLATE_MAX_BOXES boxes examined */

#ifndef CODEGEN_ISOLATE_MAX_BOXES
#define CODEGEN_ISOLATE_MAX_BOXES 200000L
#endif

/* Every zero of G on [lo, hi] (an interval spanning few binades, like a 2 pi range of angles:
 * boxes are halved, so [0, 1e30] would exhaust the subdivision and come back as one
 * CLUSTER), in ascending order, each once: subdivide, discard what the
 * enclosures of G (natural and mean-value) keep away from 0, certify what is monotone with a
 * sign change, and report what double precision cannot decide as a CLUSTER or SINGULAR
 * interval. Nothing is dropped: every zero of G in [lo, hi] lies in some reported interval.
 * out receives *count entries (at most capacity). Reentrant; its boxes waiting to be
 * examined (CODEGEN_ISOLATE_DEPTH of them, 2.3 KiB in double) are on the stack:
 * codegen_isolate_work takes them from the caller. */
int codegen_isolate(codegen_enclosure enclose, const void *context, unsigned mode, codegen_real lo,
                    codegen_real hi, codegen_isolated *out, int capacity, int *count);

/* A box of codegen_isolate's subdivision waiting to be examined. */
typedef struct codegen_isolation_box {
    codegen_real lo, hi;
    int sign_lo, sign_hi;   /* G's decided sign at each end, 0 undecided, or unknown (2) */
} codegen_isolation_box;

/* Boxes waiting at once: deeper than the ~60 halvings from any interval of doubles down to
 * the resolution; a box beyond it is reported undecided, never dropped. */
#define CODEGEN_ISOLATE_DEPTH 96

/* codegen_isolate with its boxes in the caller's memory: stack has room for
 * CODEGEN_ISOLATE_DEPTH (contents on return unspecified). The same results, bit for bit. */
int codegen_isolate_work(codegen_enclosure enclose, const void *context, unsigned mode,
                         codegen_real lo, codegen_real hi, codegen_isolated *out, int capacity,
                         int *count, codegen_isolation_box *stack);

/* *certified = 1 if [lo, hi] provably holds exactly one zero of G, a simple one (G changes
 * sign at the ends, G' keeps its sign between), else 0. Returns 0 or the enclosure's status. */
int codegen_certify(codegen_enclosure enclose, const void *context, unsigned mode, codegen_real lo,
                    codegen_real hi, int *certified);

/* *certified = 1 if an interval [*lo, *hi] around m, a few times the distance a Newton step
 * from m can move, provably holds exactly one zero of G, a simple one (as codegen_certify
 * says it), proven by the interval Newton test; else 0 and *lo, *hi untouched. For m within
 * rounding of a simple zero, as polishing leaves it. slope: G'(m) as the caller knows it
 * (it sizes the interval only; the proof does not rely on it), or 0 if unknown, which costs
 * an enclosure of G' at m. Returns 0 or the enclosure's status. */
int codegen_certify_newton(codegen_enclosure enclose, const void *context, unsigned mode,
                           codegen_real m, codegen_real slope, codegen_real *lo, codegen_real *hi,
                           int *certified);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_INTERVAL_H */
