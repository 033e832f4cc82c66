"""Which names a model's parameters and coordinates may take, as far as C is concerned.

A parameter's name is the field of the C struct PREFIX_params and of the Python Params, so
it must be an identifier no header turns into something else: a C keyword, or an object-like
macro of the headers the library (or a program using it) includes, can never be a field.
Those names are refused. Every other identifier works: where a name is also one the C
standard library or the generated code uses for itself (``sin``, ``M_PI``, ``v``, ``out``,
``params``), the generated code computes with a local of another name (see
``codegen.compiler.derivation.names``) and only the struct field and the documentation keep the
user's.
"""
from __future__ import annotations

import keyword
import re

#: C99 and C11 keywords (C23's too: a header may be compiled as C23).
C_KEYWORDS = frozenset("""
    auto break case char const continue default do double else enum extern float for goto if
    inline int long register restrict return short signed sizeof static struct switch typedef
    union unsigned void volatile while _Alignas _Alignof _Atomic _Bool _Complex _Generic
    _Imaginary _Noreturn _Static_assert _Thread_local alignas alignof bool constexpr false
    nullptr static_assert thread_local true typeof typeof_unqual
""".split())

#: Object-like macros of <float.h>, <math.h>, <stddef.h> and <string.h> (what the library
#: includes), and of <stdio.h>, <errno.h>, <stdbool.h>, <limits.h> and <stdint.h> (what a
#: program that uses it includes): a struct field of such a name is replaced by the macro.
HEADER_MACROS = frozenset("""
    NULL NAN INFINITY HUGE_VAL HUGE_VALF HUGE_VALL FP_INFINITE FP_NAN FP_NORMAL FP_SUBNORMAL
    FP_ZERO FP_FAST_FMA FP_FAST_FMAF FP_FAST_FMAL FP_ILOGB0 FP_ILOGBNAN MATH_ERRNO
    MATH_ERREXCEPT math_errhandling DECIMAL_DIG FLT_RADIX FLT_ROUNDS FLT_EVAL_METHOD
    EOF BUFSIZ FILENAME_MAX FOPEN_MAX L_tmpnam SEEK_CUR SEEK_END SEEK_SET TMP_MAX _IOFBF
    _IOLBF _IONBF stdin stdout stderr errno EDOM ERANGE EILSEQ CHAR_BIT CHAR_MAX CHAR_MIN
    INT_MAX INT_MIN LONG_MAX LONG_MIN LLONG_MAX LLONG_MIN SCHAR_MAX SCHAR_MIN SHRT_MAX SHRT_MIN
    UCHAR_MAX UINT_MAX ULONG_MAX ULLONG_MAX USHRT_MAX MB_LEN_MAX SIZE_MAX PTRDIFF_MAX
    PTRDIFF_MIN __bool_true_false_are_defined
""".split())

#: Prefixes of the headers' macro families (FLT_MAX, DBL_EPSILON, INT32_MAX, ...) and of the
#: runtime's own (CODEGEN_R, CODEGEN_EPSILON, ...).
MACRO_PREFIXES = ("FLT_", "DBL_", "LDBL_", "FP_", "INT8_", "INT16_", "INT32_", "INT64_",
                  "UINT8_", "UINT16_", "UINT32_", "UINT64_", "INTMAX_", "UINTMAX_", "INTPTR_",
                  "UINTPTR_", "CODEGEN_")

#: Names the C standard library (the functions and macros of <math.h>, <tgmath.h>,
#: <float.h>, <stddef.h>, <string.h>, including POSIX's M_ constants) and the generated code
#: itself use in a function's scope. A parameter or coordinate may have one of these names,
#: but the generated code then calls its local something else.
C_TAKEN = frozenset("""
    acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp exp2 expm1
    fabs fdim floor fma fmax fmin fmod fpclassify frexp hypot ilogb isfinite isgreater
    isgreaterequal isinf isless islessequal islessgreater isnan isnormal isunordered ldexp
    lgamma llrint llround log log10 log1p log2 logb lrint lround modf nan nearbyint nextafter
    nexttoward pow remainder remquo rint round scalbln scalbn signbit sin sinh sqrt tan tanh
    tgamma trunc float_t double_t size_t ptrdiff_t wchar_t offsetof max_align_t memcpy memmove
    memset memcmp strlen M_E M_LOG2E M_LOG10E M_LN2 M_LN10 M_PI M_PI_2 M_PI_4 M_1_PI M_2_PI
    M_2_SQRTPI M_SQRT2 M_SQRT1_2 main
    params out v iv_flags iv_g iv_dg flags work slots mode status values copy_out all_finite
""".split())

#: The argument and output names of the generated functions: a coordinate of such a name is
#: an argument itself, so it is called something else in C (a parameter is read into a
#: local of another name only in the functions that have such an argument).
C_ARGUMENTS = frozenset("""
    coords rates accels multipliers f A f_d f_dd positions velocities T V_G V_E lagrangian
    dt_dL_dqdot dL_dq constraint_forces dissipative_forces applied_forces residual e theta_dd
    scale values scales residuals sigma M B K omega_n_squared zeta_omega_n branch_residuals
    radicands radicand_scales
""".split())

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def refusal(name: str, prefix: str) -> str | None:
    """Why ``name`` cannot name a parameter or coordinate of the library ``prefix``; None if
    it can."""
    if not _IDENTIFIER.match(name):
        return "is not an identifier (letters, digits and _, not starting with a digit)"
    if keyword.iskeyword(name):
        return "is a Python keyword (it names a field of the Python Params)"
    if name in C_KEYWORDS:
        return "is a C keyword (it names a field of the C struct of parameters)"
    if name in HEADER_MACROS or name.startswith(MACRO_PREFIXES):
        return "is a macro of the C headers (it names a field of the C struct of parameters)"
    if name.upper().startswith(f"{prefix.upper()}_"):
        return f"begins with the library's own prefix {prefix}_"
    if name.startswith("__") or re.match(r"_[A-Z]", name):
        return "is reserved to the C implementation (a leading __ or _ and a capital)"
    return None


def c_taken(name: str, argument: bool = False) -> bool:
    """Whether the generated code must call a parameter's local (or, ``argument``, a
    coordinate's) something else than ``name``: a name of the C library or of the generated
    code, or the runtime's prefix codegen_."""
    return name in C_TAKEN or name.startswith("codegen_") or (argument and name in C_ARGUMENTS)


def c_identifier(name: str) -> bool:
    """Whether name is a C identifier (ASCII letters, digits and _, no leading digit)."""
    return bool(_IDENTIFIER.match(name)) and name not in C_KEYWORDS
