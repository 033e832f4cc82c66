/*
 * codegen_dd.h -- double-double arithmetic for the generated polynomial coefficients.
 * Hand-written (not generated). Plain C99 (+ libm's fma where the hardware has it); no state.
 *
 * Generated code does not call the arithmetic directly: a long coefficient program written
 * as calls takes compilers minutes. It is a table of three-address instructions instead,
 * run by codegen_dd_run, in which the arithmetic is inlined.
 *
 * A value is hi + lo with |lo| <= ulp(hi)/2: about 106 significant bits. Squaring the
 * square roots out of G cancels many digits in the low coefficients of sigma (13 in a
 * non-Grashof four-bar); evaluated in double-double they keep ~16 digits after that.
 * Sums use Knuth's two-sum and products the exact error of the leading product (fma where it
 * is hardware, Dekker's TwoProduct elsewhere: both exact, so every platform gets the same
 * bits, even one whose software fma rounds twice), so the results do not depend on the
 * compiler contracting expressions; like all of this library, it needs IEEE round-to-
 * nearest and no -ffast-math.
 */
#ifndef CODEGEN_DD_H
#define CODEGEN_DD_H

#include <stddef.h>

#include "codegen_real.h"

typedef struct codegen_dd {
    codegen_real hi, lo;
} codegen_dd;

codegen_dd codegen_dd_from(codegen_real x);
codegen_dd codegen_dd_add(codegen_dd a, codegen_dd b);
codegen_dd codegen_dd_sub(codegen_dd a, codegen_dd b);
codegen_dd codegen_dd_neg(codegen_dd a);
codegen_dd codegen_dd_mul(codegen_dd a, codegen_dd b);
/* a / b by two long-division steps (b.hi == 0 gives a non-finite result, as in double). */
codegen_dd codegen_dd_div(codegen_dd a, codegen_dd b);
/* The nearest double. */
codegen_real codegen_dd_to_double(codegen_dd a);

typedef enum codegen_dd_operation {
    CODEGEN_DD_CONST, /* v[destination] = constants[left] */
    CODEGEN_DD_ADD,   /* v[destination] = v[left] + v[right] */
    CODEGEN_DD_SUB,
    CODEGEN_DD_MUL,
    CODEGEN_DD_DIV,
    CODEGEN_DD_NEG    /* v[destination] = -v[left] */
} codegen_dd_operation;

typedef struct codegen_dd_instruction {
    unsigned short operation, destination, left, right;
} codegen_dd_instruction;

/* Runs count instructions in order over the values v (operands are read before the
 * destination is written, so they may coincide). */
void codegen_dd_run(const codegen_dd_instruction *program, size_t count,
                    const codegen_real *constants, codegen_dd *v);

/* codegen_dd_run (the same values, bit for bit) with a running error bound: e[slot] receives
 * an upper bound on |v[slot] - the exact value of what the program computes in slot|, given
 * e[] on entry for the caller's inputs (0: exact). The constants are exact (the generator
 * emits only dyadic ones of 24 bits or fewer). Each operation's own error is bounded
 * relative to its operands' size (Joldes, Muller & Popescu, 2017: at most 3 u^2 for the sum,
 * below 8 u^2 for the product, u = CODEGEN_EPSILON / 2; a factor 2 more is allowed, and 4 for
 * the quotient), and the operands' errors are carried through to first order and beyond. A
 * quotient whose divisor's bound reaches its size gets an infinite bound. */
void codegen_dd_run_bounded(const codegen_dd_instruction *program, size_t count,
                            const codegen_real *constants, codegen_dd *v, codegen_real *e);

/* An upper bound on the error of out = codegen_dd_to_double(value) as an approximation of
 * the exact value within error of value. */
codegen_real codegen_dd_output_bound(codegen_real out, codegen_real error);

#endif /* CODEGEN_DD_H */
