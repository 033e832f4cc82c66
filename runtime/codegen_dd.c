/*
 * codegen_dd.c -- double-double arithmetic (see codegen_dd.h). Hand-written (not generated).
 */
#include "codegen_dd.h"

#include <math.h>

codegen_dd codegen_dd_from(codegen_real x)
{
    codegen_dd r;
    r.hi = x;
    r.lo = 0;
    return r;
}

/* hi + lo = a + b exactly, given |a| >= |b| or a == 0. */
static codegen_dd quick_two_sum(codegen_real a, codegen_real b)
{
    codegen_dd r;
    r.hi = a + b;
    r.lo = b - (r.hi - a);
    return r;
}

/* hi + lo = a + b exactly (Knuth). */
static codegen_dd two_sum(codegen_real a, codegen_real b)
{
    codegen_dd r;
    codegen_real v;
    r.hi = a + b;
    v = r.hi - a;
    r.lo = (a - (r.hi - v)) + (b - v);
    return r;
}

/* The operations, inline in both runners; the public functions call them. */
static inline codegen_dd dd_add(codegen_dd a, codegen_dd b)
{
    codegen_dd s = two_sum(a.hi, b.hi);
    const codegen_dd t = two_sum(a.lo, b.lo);
    s = quick_two_sum(s.hi, s.lo + t.hi);
    return quick_two_sum(s.hi, s.lo + t.lo);
}

static inline codegen_dd dd_neg(codegen_dd a)
{
    a.hi = -a.hi;
    a.lo = -a.lo;
    return a;
}

static inline codegen_dd dd_sub(codegen_dd a, codegen_dd b)
{
    return dd_add(a, dd_neg(b));
}

/* a * b - p exactly, for p = fl(a * b) (no underflow). Hardware fma, or Dekker's
 * TwoProduct (codegen_real.h): the same value, without a software fma, which costs a call and
 * on some C libraries (newlib 3.3) rounds twice. Beyond CODEGEN_SPLIT_MAX, where the halves
 * would overflow, libm's fma. */
static codegen_real product_error(codegen_real a, codegen_real b, codegen_real p)
{
#ifndef CODEGEN_FAST_FMA
    if (codegen_fabs(a) < CODEGEN_SPLIT_MAX && codegen_fabs(b) < CODEGEN_SPLIT_MAX) {
        codegen_real ah, al, bh, bl;
        codegen_split(a, &ah, &al);
        codegen_split(b, &bh, &bl);
        return codegen_product_error(p, ah, al, bh, bl);
    }
#endif
    return codegen_fma(a, b, -p);
}

static inline codegen_dd dd_mul(codegen_dd a, codegen_dd b)
{
    const codegen_real p = a.hi * b.hi;
    const codegen_real e = product_error(a.hi, b.hi, p) + (a.hi * b.lo + a.lo * b.hi);
    return quick_two_sum(p, e);
}

static inline codegen_dd dd_div(codegen_dd a, codegen_dd b)
{
    const codegen_real q1 = a.hi / b.hi;
    const codegen_dd r = dd_sub(a, dd_mul(b, codegen_dd_from(q1)));
    const codegen_real q2 = r.hi / b.hi;
    return quick_two_sum(q1, q2);
}

codegen_dd codegen_dd_add(codegen_dd a, codegen_dd b)
{
    return dd_add(a, b);
}

codegen_dd codegen_dd_sub(codegen_dd a, codegen_dd b)
{
    return dd_sub(a, b);
}

codegen_dd codegen_dd_neg(codegen_dd a)
{
    return dd_neg(a);
}

codegen_dd codegen_dd_mul(codegen_dd a, codegen_dd b)
{
    return dd_mul(a, b);
}

codegen_dd codegen_dd_div(codegen_dd a, codegen_dd b)
{
    return dd_div(a, b);
}

codegen_real codegen_dd_to_double(codegen_dd a)
{
    return a.hi + a.lo;
}

void codegen_dd_run(const codegen_dd_instruction *program, size_t count,
                    const codegen_real *constants, codegen_dd *v)
{
    size_t i;
    for (i = 0; i < count; ++i) {
        const codegen_dd_instruction op = program[i];
        switch ((codegen_dd_operation)op.operation) {
        case CODEGEN_DD_CONST:
            v[op.destination] = codegen_dd_from(constants[op.left]);
            break;
        case CODEGEN_DD_ADD:
            v[op.destination] = dd_add(v[op.left], v[op.right]);
            break;
        case CODEGEN_DD_SUB:
            v[op.destination] = dd_sub(v[op.left], v[op.right]);
            break;
        case CODEGEN_DD_MUL:
            v[op.destination] = dd_mul(v[op.left], v[op.right]);
            break;
        case CODEGEN_DD_DIV:
            v[op.destination] = dd_div(v[op.left], v[op.right]);
            break;
        case CODEGEN_DD_NEG:
            v[op.destination] = dd_neg(v[op.left]);
            break;
        }
    }
}

/* u^2, the unit of a double-double operation's error, and how much a bound computed in
 * working precision is raised to stay an upper bound (a few roundings of u each). */
#define DD_UNIT2 (CODEGEN_R(0.25) * CODEGEN_EPSILON * CODEGEN_EPSILON)
#define DD_UP (1 + CODEGEN_R(4.0) * CODEGEN_EPSILON)

static codegen_real dd_size(codegen_dd a)
{
    return codegen_fabs(a.hi) + codegen_fabs(a.lo);
}

void codegen_dd_run_bounded(const codegen_dd_instruction *program, size_t count,
                            const codegen_real *constants, codegen_dd *v, codegen_real *e)
{
    size_t i;
    for (i = 0; i < count; ++i) {
        const codegen_dd_instruction op = program[i];
        codegen_dd a, b;
        codegen_real ea, eb, sa, sb, error = 0;
        if (op.operation == CODEGEN_DD_CONST) {
            v[op.destination] = codegen_dd_from(constants[op.left]);
            e[op.destination] = 0;
            continue;
        }
        a = v[op.left];
        b = v[op.right];
        ea = e[op.left];
        eb = e[op.right];
        sa = dd_size(a);
        sb = dd_size(b);
        switch ((codegen_dd_operation)op.operation) {
        case CODEGEN_DD_CONST:
            break;
        case CODEGEN_DD_ADD:
        case CODEGEN_DD_SUB:
            v[op.destination] = op.operation == CODEGEN_DD_ADD ? dd_add(a, b) : dd_sub(a, b);
            error = ea + eb + CODEGEN_R(6.0) * DD_UNIT2 * (sa + sb);
            break;
        case CODEGEN_DD_MUL:
            v[op.destination] = dd_mul(a, b);
            error = sa * eb + sb * ea + ea * eb + CODEGEN_R(16.0) * DD_UNIT2 * sa * sb;
            break;
        case CODEGEN_DD_DIV:
            v[op.destination] = dd_div(a, b);
            /* |a~/b~ - a/b| <= (e_a + |a~/b~| e_b) / (|b~| - e_b) */
            error = sb > eb ? (ea + dd_size(v[op.destination]) * eb) / ((sb - eb) / DD_UP)
                                  + CODEGEN_R(32.0) * DD_UNIT2 * dd_size(v[op.destination])
                            : CODEGEN_HUGE;
            break;
        case CODEGEN_DD_NEG:
            v[op.destination] = dd_neg(a);
            error = ea;
            break;
        }
        /* + the smallest normal: the last bits a result near underflow loses */
        e[op.destination] = error == 0 ? 0 : error * DD_UP + CODEGEN_REAL_MIN;
    }
}

codegen_real codegen_dd_output_bound(codegen_real out, codegen_real error)
{
    return (error + CODEGEN_R(0.5) * CODEGEN_EPSILON * codegen_fabs(out)) * DD_UP + CODEGEN_REAL_MIN;
}
