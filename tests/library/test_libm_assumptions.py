"""What the proofs assume of the C library's maths, tested on this machine's libm.

The certified routes (docs/method.md) assume libm's sin and cos within two ulps (the interval
sin and cos of codegen_interval.c widen libm's values by two ulps), atan and atan2 within a
few (a span's ends are widened by 16 eps relative in codegen_roots.c) and sqrt correctly
rounded (IEEE 754 requires it; the interval square root widens by one ulp). The library
calls these through codegen_real.h: sin, cos, ... in double and sinf, cosf, ... in float.
Here the same functions of the process's libm (ctypes) are held against mpmath at 60 digits
on a fixed sample of angles, the hard neighbourhoods of multiples of pi/2 included, and on
hypothesis-drawn ones. Another libm (newlib on the Cortex-M4F) is compared with this one in
`make embedded` (embedded/report.md: its values differ by a few ulps of the angles at most).
"""
from __future__ import annotations

import ctypes
import ctypes.util
import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

#: The most each function may be off, in ulps of the true value, as the proofs assume.
ASSUMED_ULPS = {"sin": 2.0, "cos": 2.0, "atan": 4.0, "atan2": 4.0, "sqrt": 0.5}
#: The angles where the interval sin and cos still place crests (codegen_interval.c).
LARGEST_ANGLE = 2.0 ** 50

_LIBM = ctypes.CDLL(ctypes.util.find_library("m"))
mpmath.mp.dps = 60


def _function(name: str, real: str):
    """libm's name (sin or sinf) with ctypes types for the precision."""
    c_type = ctypes.c_double if real == "double" else ctypes.c_float
    f = getattr(_LIBM, name if real == "double" else name + "f")
    f.restype = c_type
    f.argtypes = [c_type] * (2 if name == "atan2" else 1)
    return f


REFERENCES = {"sin": mpmath.sin, "cos": mpmath.cos, "atan": mpmath.atan,
              "atan2": mpmath.atan2, "sqrt": mpmath.sqrt}


def _as_real(x: float, real: str) -> float:
    return float(np.float32(x)) if real == "float" else float(x)


def _ulp(value: mpmath.mpf, real: str) -> float:
    """The spacing of the format's numbers at value (its subnormal spacing near 0)."""
    nearest = float(value)
    if real == "float":
        return float(np.spacing(np.float32(abs(nearest))))
    return math.ulp(nearest)


def _error_in_ulps(name: str, real: str, *args: float) -> float:
    args = tuple(_as_real(a, real) for a in args)
    got = _function(name, real)(*args)
    exact = REFERENCES[name](*(mpmath.mpf(a) for a in args))
    return float(abs(mpmath.mpf(got) - exact)) / _ulp(exact, real)


def _angles(real: str) -> list[float]:
    """A fixed sample: uniform on +-4 pi, log-uniform up to the largest angle the interval
    functions take (float: 1e4, where float spacing is still below the width of a crest),
    and the neighbours of multiples of pi/2, where sin and cos are hardest."""
    rng = np.random.default_rng(20_261_126)
    top = LARGEST_ANGLE if real == "double" else 1e4
    uniform = rng.uniform(-4 * math.pi, 4 * math.pi, 3000)
    wide = rng.choice([-1, 1], 2000) * np.exp(rng.uniform(math.log(1e-8), math.log(top), 2000))
    near = [k * math.pi / 2 for k in range(-40, 41)]
    neighbours = [x for c in near for x in (c, math.nextafter(c, math.inf),
                                            math.nextafter(c, -math.inf))]
    return [float(x) for x in np.concatenate([uniform, wide, neighbours])]


@pytest.mark.parametrize("real", ["double", "float"])
@pytest.mark.parametrize("name", ["sin", "cos"])
def test_sin_and_cos_within_the_ulps_the_intervals_assume(name, real):
    worst = max(_error_in_ulps(name, real, x) for x in _angles(real))
    assert worst <= ASSUMED_ULPS[name], f"{name} ({real}) is off by {worst:.2f} ulps"


@pytest.mark.parametrize("real", ["double", "float"])
def test_atan_atan2_and_sqrt_within_the_ulps_assumed(real):
    rng = np.random.default_rng(7)
    xs = np.concatenate([rng.standard_normal(2000) * 10.0 ** rng.uniform(-8, 8, 2000),
                         [0.0, 1.0, -1.0, 1e-300 if real == "double" else 1e-30]])
    worst = {"atan": max(_error_in_ulps("atan", real, x) for x in xs),
             "atan2": max(_error_in_ulps("atan2", real, 1.0, x) for x in xs),
             "sqrt": max(_error_in_ulps("sqrt", real, abs(x)) for x in xs)}
    for name, error in worst.items():
        assert error <= ASSUMED_ULPS[name], f"{name} ({real}) is off by {error:.2f} ulps"


@settings(max_examples=300, deadline=None)
@given(st.floats(-LARGEST_ANGLE, LARGEST_ANGLE, allow_nan=False),
       st.sampled_from(["sin", "cos"]))
def test_sin_and_cos_on_drawn_angles(x, name):
    assert _error_in_ulps(name, "double", x) <= ASSUMED_ULPS[name]


def test_the_check_would_catch_a_libm_two_ulps_worse():
    """The measure itself: a value moved four ulps from libm's is reported as such."""
    x = 0.7
    exact = mpmath.sin(mpmath.mpf(x))
    moved = math.sin(x) + 4 * math.ulp(math.sin(x))
    assert float(abs(mpmath.mpf(moved) - exact)) / _ulp(exact, "double") > ASSUMED_ULPS["sin"]
