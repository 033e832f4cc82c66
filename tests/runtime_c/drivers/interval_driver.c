/* Drives the interval runtime (runtime/codegen_interval.h/.c) for
 * tests/runtime_c/test_interval_runtime.py: reads one command a line from stdin and writes
 * one line of results to stdout. Doubles are read with strtod (hex floats, inf, nan accepted) and written
 * with %a, so nothing is rounded on the way between Python and C.
 *
 * Interval operations (a, b intervals given as two doubles lo hi; flags start at 0):
 *   add|sub|mul|div|sumsq  alo ahi blo bhi  ->  lo hi flags      (sumsq: a^2 + b^2)
 *   pow                    alo ahi n        ->  lo hi flags
 *   sqrt|sin|cos|neg|abs   alo ahi          ->  lo hi flags
 *
 * Isolation and certification of the zeros of a test function G over [lo, hi]:
 *   isolate MODE LO HI CAPACITY FAIL_STATUS FAIL_AFTER FUNCTION
 *       -> status count calls bad {lo hi theta kind sign_change} * count
 *   certify MODE LO HI FAIL_STATUS FAIL_AFTER FUNCTION
 *       -> status certified calls bad
 *   newton MODE LO HI FAIL_STATUS FAIL_AFTER FUNCTION   (the interval Newton test around
 *       m = (LO + HI) / 2; [LO, HI] only bounds where enclosures may be asked)
 *       -> status certified calls bad lo hi   (lo, hi: the proven interval, NaN if none)
 * FUNCTION is one of
 *   poly C K R1 M1 .. RK MK   G = (t - R1)^M1 ... (t - RK)^MK + C, G' by the product rule
 *   pole C P                  G = C + 1 / (t - P)
 *   sqrt E C                  G = sqrt(t - E) - C
 *   sin S                     G = sin(t) - S, G' = cos(t)
 *   zero                      G = 0, G' = 0
 *   flagged BITS A B FUNCTION FUNCTION, with the flags BITS & (POLE | EDGE) raised where theta
 *                             meets [A, B], and BITS & OUTSIDE where theta lies within [A, B]
 * The enclosure callback returns FAIL_STATUS (when nonzero) from its (FAIL_AFTER + 1)-th call
 * on. calls counts its calls; bad counts calls whose mode differs from MODE or whose theta is
 * not a proper sub-interval of [LO, HI] (NaN, lo > hi, or outside). The results live in a heap
 * block of exactly CAPACITY entries (NULL for 0), so AddressSanitizer sees any write past it.
 * A malformed line is answered with "error"; the exit status is 0 unless input is malformed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen_interval.h"

#define MAX_FACTORS 32
#define LINE_SIZE 65536

typedef enum function_kind { F_POLY, F_POLE, F_SQRT, F_SIN, F_ZERO } function_kind;

typedef struct counters {
    long calls;
    long bad;
} counters;

typedef struct function {
    function_kind kind;
    int factors;
    double root[MAX_FACTORS];
    int multiplicity[MAX_FACTORS];
    double c, p, e, s;
    unsigned flag_bits;
    double flag_lo, flag_hi;
    int fail_status;
    long fail_after;
    unsigned mode;
    double lo, hi;
    counters *count; /* the context is const; the counters it points to are not */
} function;

static char *next_token(void)
{
    return strtok(NULL, " \t\r\n");
}

static int read_double(double *x)
{
    const char *token = next_token();
    char *end;
    if (token == NULL) {
        return 0;
    }
    *x = strtod(token, &end);
    return *end == '\0';
}

static int read_long(long *x)
{
    const char *token = next_token();
    char *end;
    if (token == NULL) {
        return 0;
    }
    *x = strtol(token, &end, 10);
    return *end == '\0';
}

static int read_int(int *x)
{
    long v;
    if (!read_long(&v) || v < -1000000000L || v > 1000000000L) {
        return 0;
    }
    *x = (int)v;
    return 1;
}

static int read_interval(codegen_iv *x)
{
    return read_double(&x->lo) && read_double(&x->hi);
}

/* ---- the test functions ---- */

static void enclose_poly(const function *f, codegen_iv t, codegen_iv *g, codegen_iv *dg)
{
    codegen_iv power[MAX_FACTORS], derivative[MAX_FACTORS], value = codegen_iv_point(1.0),
               slope = codegen_iv_point(0.0);
    int i, j;
    for (i = 0; i < f->factors; ++i) {
        const codegen_iv factor = codegen_iv_sub(t, codegen_iv_point(f->root[i]));
        const int m = f->multiplicity[i];
        power[i] = codegen_iv_pow(factor, m);
        derivative[i] = m == 1 ? codegen_iv_point(1.0)
                               : codegen_iv_mul(codegen_iv_point((double)m),
                                                codegen_iv_pow(factor, m - 1));
        value = codegen_iv_mul(value, power[i]);
    }
    for (i = 0; i < f->factors; ++i) {
        codegen_iv term = derivative[i];
        for (j = 0; j < f->factors; ++j) {
            if (j != i) {
                term = codegen_iv_mul(term, power[j]);
            }
        }
        slope = codegen_iv_add(slope, term);
    }
    *g = codegen_iv_add(value, codegen_iv_point(f->c));
    *dg = slope;
}

static int enclosure(const void *context, unsigned mode, codegen_iv t, codegen_iv *g,
                     codegen_iv *dg, unsigned *flags)
{
    const function *f = (const function *)context;
    codegen_iv d, r, slope_unwanted;
    if (dg == NULL) {             /* G alone asked for: G' is computed and dropped */
        dg = &slope_unwanted;
    }
    f->count->calls += 1;
    if (mode != f->mode || !(t.lo <= t.hi) || t.lo < f->lo || t.hi > f->hi) {
        f->count->bad += 1;
    }
    if (f->fail_status != 0 && f->count->calls > f->fail_after) {
        return f->fail_status;
    }
    switch (f->kind) {
    case F_POLY:
        enclose_poly(f, t, g, dg);
        break;
    case F_POLE:
        d = codegen_iv_sub(t, codegen_iv_point(f->p));
        *g = codegen_iv_add(codegen_iv_point(f->c),
                            codegen_iv_div(codegen_iv_point(1.0), d, flags));
        *dg = codegen_iv_neg(codegen_iv_div(codegen_iv_point(1.0), codegen_iv_pow(d, 2), flags));
        break;
    case F_SQRT:
        r = codegen_iv_sqrt(codegen_iv_sub(t, codegen_iv_point(f->e)), flags);
        *g = codegen_iv_sub(r, codegen_iv_point(f->c));
        *dg = codegen_iv_div(codegen_iv_point(0.5), r, flags);
        break;
    case F_SIN:
        *g = codegen_iv_sub(codegen_iv_sin(t), codegen_iv_point(f->s));
        *dg = codegen_iv_cos(t);
        break;
    case F_ZERO:
        *g = codegen_iv_point(0.0);
        *dg = codegen_iv_point(0.0);
        break;
    }
    if (t.lo <= f->flag_hi && t.hi >= f->flag_lo) {
        *flags |= f->flag_bits & (CODEGEN_IV_POLE | CODEGEN_IV_EDGE);
    }
    if (t.lo >= f->flag_lo && t.hi <= f->flag_hi) {
        *flags |= f->flag_bits & CODEGEN_IV_OUTSIDE;
    }
    return 0;
}

static int read_function(function *f)
{
    const char *name = next_token();
    int i;
    f->factors = 0;
    f->c = f->p = f->e = f->s = 0.0;
    if (name == NULL) {
        return 0;
    }
    if (strcmp(name, "flagged") == 0) {
        long bits;
        if (f->flag_bits != 0u || !read_long(&bits) || bits <= 0 || bits > 7
            || !read_double(&f->flag_lo) || !read_double(&f->flag_hi)) {
            return 0;
        }
        f->flag_bits = (unsigned)bits;
        return read_function(f);
    }
    if (strcmp(name, "poly") == 0) {
        f->kind = F_POLY;
        if (!read_double(&f->c) || !read_int(&f->factors) || f->factors < 0
            || f->factors > MAX_FACTORS) {
            return 0;
        }
        for (i = 0; i < f->factors; ++i) {
            if (!read_double(&f->root[i]) || !read_int(&f->multiplicity[i])
                || f->multiplicity[i] < 1) {
                return 0;
            }
        }
        return 1;
    }
    if (strcmp(name, "pole") == 0) {
        f->kind = F_POLE;
        return read_double(&f->c) && read_double(&f->p);
    }
    if (strcmp(name, "sqrt") == 0) {
        f->kind = F_SQRT;
        return read_double(&f->e) && read_double(&f->c);
    }
    if (strcmp(name, "sin") == 0) {
        f->kind = F_SIN;
        return read_double(&f->s);
    }
    if (strcmp(name, "zero") == 0) {
        f->kind = F_ZERO;
        return 1;
    }
    return 0;
}

/* MODE LO HI [CAPACITY] FAIL_STATUS FAIL_AFTER FUNCTION */
static int read_problem(function *f, counters *count, int *capacity)
{
    long mode;
    if (!read_long(&mode) || mode < 0 || !read_double(&f->lo) || !read_double(&f->hi)) {
        return 0;
    }
    f->mode = (unsigned)mode;
    if (capacity != NULL && (!read_int(capacity) || *capacity < 0)) {
        return 0;
    }
    if (!read_int(&f->fail_status) || !read_long(&f->fail_after)) {
        return 0;
    }
    count->calls = 0;
    count->bad = 0;
    f->count = count;
    f->flag_bits = 0u;
    f->flag_lo = HUGE_VAL;
    f->flag_hi = -HUGE_VAL;
    return read_function(f);
}

static int run_isolate(void)
{
    function f;
    counters count;
    codegen_isolated *out = NULL;
    int capacity = 0, found = -1, status, i;
    if (!read_problem(&f, &count, &capacity)) {
        return 0;
    }
    if (capacity > 0) {
        out = (codegen_isolated *)malloc((size_t)capacity * sizeof *out);
        if (out == NULL) {
            return 0;
        }
    }
    status = codegen_isolate(enclosure, &f, f.mode, f.lo, f.hi, out, capacity, &found);
    printf("%d %d %ld %ld", status, found, count.calls, count.bad);
    for (i = 0; i < found && i < capacity; ++i) {
        printf(" %a %a %a %d %d", out[i].lo, out[i].hi, out[i].theta, (int)out[i].kind,
               out[i].sign_change);
    }
    printf("\n");
    free(out);
    return 1;
}

static int run_certify(void)
{
    function f;
    counters count;
    int certified = -1, status;
    if (!read_problem(&f, &count, NULL)) {
        return 0;
    }
    status = codegen_certify(enclosure, &f, f.mode, f.lo, f.hi, &certified);
    printf("%d %d %ld %ld\n", status, certified, count.calls, count.bad);
    return 1;
}

/* newton PROBLEM (the slope unknown), or newton_slope SLOPE PROBLEM */
static int run_newton(int with_slope)
{
    function f;
    counters count;
    int certified = -1, status;
    double lo = NAN, hi = NAN, slope = 0.0;
    if ((with_slope && !read_double(&slope)) || !read_problem(&f, &count, NULL)) {
        return 0;
    }
    status = codegen_certify_newton(enclosure, &f, f.mode, 0.5 * f.lo + 0.5 * f.hi, slope, &lo,
                                    &hi, &certified);
    printf("%d %d %ld %ld %a %a\n", status, certified, count.calls, count.bad, lo, hi);
    return 1;
}

static int run_operation(const char *op)
{
    codegen_iv a, b, r;
    unsigned flags = 0u;
    int n;
    if (!read_interval(&a)) {
        return 0;
    }
    if (strcmp(op, "sqrt") == 0) {
        r = codegen_iv_sqrt(a, &flags);
    } else if (strcmp(op, "sin") == 0) {
        r = codegen_iv_sin(a);
    } else if (strcmp(op, "cos") == 0) {
        r = codegen_iv_cos(a);
    } else if (strcmp(op, "neg") == 0) {
        r = codegen_iv_neg(a);
    } else if (strcmp(op, "abs") == 0) {
        r = codegen_iv_abs(a);
    } else if (strcmp(op, "pow") == 0) {
        if (!read_int(&n) || n < 1) {
            return 0;
        }
        r = codegen_iv_pow(a, n);
    } else {
        if (!read_interval(&b)) {
            return 0;
        }
        if (strcmp(op, "add") == 0) {
            r = codegen_iv_add(a, b);
        } else if (strcmp(op, "sub") == 0) {
            r = codegen_iv_sub(a, b);
        } else if (strcmp(op, "mul") == 0) {
            r = codegen_iv_mul(a, b);
        } else if (strcmp(op, "div") == 0) {
            r = codegen_iv_div(a, b, &flags);
        } else if (strcmp(op, "sumsq") == 0) {
            r = codegen_iv_add(codegen_iv_pow(a, 2), codegen_iv_pow(b, 2));
        } else {
            return 0;
        }
    }
    printf("%a %a %u\n", r.lo, r.hi, flags);
    return 1;
}

int main(void)
{
    static char line[LINE_SIZE];
    int malformed = 0;
    while (fgets(line, (int)sizeof line, stdin) != NULL) {
        const char *op = strtok(line, " \t\r\n");
        int ok;
        if (op == NULL) {
            continue;
        }
        if (strcmp(op, "isolate") == 0) {
            ok = run_isolate();
        } else if (strcmp(op, "certify") == 0) {
            ok = run_certify();
        } else if (strcmp(op, "newton") == 0) {
            ok = run_newton(0);
        } else if (strcmp(op, "newton_slope") == 0) {
            ok = run_newton(1);
        } else {
            ok = run_operation(op);
        }
        if (!ok) {
            printf("error\n");
            malformed = 1;
        }
    }
    return malformed;
}
