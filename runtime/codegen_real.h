/*
 * codegen_real.h -- the real type of the whole library, chosen when it is compiled.
 * Hand-written (not generated). Plain C99.
 *
 * By default the library computes in double. Compiled with -DCODEGEN_FLOAT (every file of the
 * library and the program using it: the header's types change), it computes in float, for
 * cores with a single-precision FPU only (Cortex-M4F): codegen_real is float, literals are
 * float literals, the library calls the float functions of libm (sinf, ...: through the
 * codegen_sin, ... names below), and every rounding tolerance derives from CODEGEN_EPSILON.
 *
 * Flags that break the arithmetic are refused here, at compile time:
 *   -ffast-math (and -ffinite-math-only, which it implies): the rounding bounds of the
 *     interval arithmetic and the checks for NaN parameters assume IEEE arithmetic;
 *   -fsingle-precision-constant: double literals silently become float ones.
 * Documented, not refusable: contraction into fma (-ffp-contract=fast, the default of gnu99)
 * changes results in the last bits; use -ffp-contract=off (or -std=c99) where bit
 * reproducibility across compilers and targets matters.
 */
#ifndef CODEGEN_REAL_H
#define CODEGEN_REAL_H

#include <float.h>
#include <math.h>

#ifdef __FAST_MATH__
#error "codegen: -ffast-math (or -ffinite-math-only) breaks the library's IEEE rounding bounds and NaN checks; compile without it"
#endif

/* With -fsingle-precision-constant, 1.0 has the size of a float: the array size is -1. */
typedef char codegen_error_compiled_with_fsingle_precision_constant[
    sizeof(1.0) == sizeof(double) ? 1 : -1];

#ifdef CODEGEN_FLOAT
typedef float codegen_real;
#define CODEGEN_R(literal) literal##F          /* a literal of the library's type */
#define CODEGEN_BOUND(as_double, as_float) as_float##F /* a constant rounded for each type */
#define CODEGEN_EPSILON FLT_EPSILON            /* 2^-23 */
#define CODEGEN_SQRT_EPSILON 3.45266983e-4F   /* 2^-11.5: tolerances on what rounding squares */
#define CODEGEN_REAL_MIN FLT_MIN               /* smallest normal */
#define CODEGEN_REAL_TRUE_MIN 0x1p-149F        /* smallest subnormal */
#define CODEGEN_REAL_MAX FLT_MAX
#define CODEGEN_HUGE HUGE_VALF
#define CODEGEN_NAN NAN
#define CODEGEN_REAL_NAME "float"
#define CODEGEN_SPLITTER 4097.0F              /* Veltkamp's 2^12 + 1: halves of a float */
#define CODEGEN_SPLIT_MAX 0x1p114F             /* CODEGEN_SPLITTER * a stays finite below */
#ifdef FP_FAST_FMAF
#define CODEGEN_FAST_FMA 1                     /* fmaf is as fast as a product */
#endif
#else
typedef double codegen_real;
#define CODEGEN_R(literal) literal
#define CODEGEN_BOUND(as_double, as_float) as_double
#define CODEGEN_EPSILON DBL_EPSILON            /* 2^-52 */
#define CODEGEN_SQRT_EPSILON 0x1p-26
#define CODEGEN_REAL_MIN DBL_MIN
#define CODEGEN_REAL_TRUE_MIN 0x1p-1074
#define CODEGEN_REAL_MAX DBL_MAX
#define CODEGEN_HUGE HUGE_VAL
#define CODEGEN_NAN ((double)NAN)                /* NAN is a float */
#define CODEGEN_REAL_NAME "double"
#define CODEGEN_SPLITTER 134217729.0           /* Veltkamp's 2^27 + 1: halves of a double */
#define CODEGEN_SPLIT_MAX 0x1p995
#ifdef FP_FAST_FMA
#define CODEGEN_FAST_FMA 1
#endif
#endif

/* libm for codegen_real: codegen_sin is sinf in the float build and sin in the double one.
 * (Not <tgmath.h>: newlib's, for one, does not compile without complex long double.) */
#ifdef CODEGEN_FLOAT
#define CODEGEN_LIBM(name) name##f
#else
#define CODEGEN_LIBM(name) name
#endif
#define codegen_atan CODEGEN_LIBM(atan)
#define codegen_atan2 CODEGEN_LIBM(atan2)
#define codegen_ceil CODEGEN_LIBM(ceil)
#define codegen_copysign CODEGEN_LIBM(copysign)
#define codegen_cos CODEGEN_LIBM(cos)
#define codegen_fabs CODEGEN_LIBM(fabs)
#define codegen_fma CODEGEN_LIBM(fma)
#define codegen_fmax CODEGEN_LIBM(fmax)
#define codegen_fmin CODEGEN_LIBM(fmin)
#define codegen_frexp CODEGEN_LIBM(frexp)
#define codegen_ldexp CODEGEN_LIBM(ldexp)
#define codegen_pow CODEGEN_LIBM(pow)
#define codegen_sin CODEGEN_LIBM(sin)
#define codegen_sqrt CODEGEN_LIBM(sqrt)
#define codegen_tan CODEGEN_LIBM(tan)

/* Exact products without fma, where it is not hardware (a software fma costs a call, and
 * newlib 3.3's rounds twice). codegen_split: hi + lo = a exactly, each with half the
 * significand (Veltkamp; |a| < CODEGEN_SPLIT_MAX). codegen_product_error: a b - p exactly
 * for p = fl(a b), from the halves of a and b (Dekker's TwoProduct; no underflow). */
static inline void codegen_split(codegen_real a, codegen_real *hi, codegen_real *lo)
{
    const codegen_real t = CODEGEN_SPLITTER * a;
    *hi = t - (t - a);
    *lo = a - *hi;
}

static inline codegen_real codegen_product_error(codegen_real p, codegen_real ah, codegen_real al,
                                                 codegen_real bh, codegen_real bl)
{
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

#endif /* CODEGEN_REAL_H */
