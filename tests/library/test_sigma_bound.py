"""The bound on sigma's coefficients that the default route's proof rests on
(NAME_sigma_bounds_kernel_work: the double-double program with a running error bound,
codegen_dd_run_bounded): against the symbolic coefficients at 60 digits, every coefficient is
within its bound of the exact value, on parameter sets near the examples and far from them,
and the bound is tight enough to be of use (far below double rounding of the largest
coefficient); the values are those of the plain kernel, bit for bit.
"""
from __future__ import annotations

import functools
import importlib.util

import cffi
import mpmath
import numpy as np
import pytest
import sympy as sp

from codegen.api import load
from codegen.resources import cflags
from conftest import ROOT, mp_lambdify

#: doughty only: the slider-crank's coefficients written out explicitly take sympy minutes to lambdify
MECHANISMS = ("doughty",)


@functools.lru_cache(maxsize=None)
def _plan(name):
    from codegen.compiler.derivation import derive
    from codegen.compiler.emission.plan import build_plan
    from codegen.compiler.model import doughty, slider_crank

    return build_plan(derive({"doughty": doughty, "slider_crank": slider_crank}[name].build()))


@pytest.fixture(scope="module", params=MECHANISMS)
def bounded(request, tmp_path_factory):
    """(name, ffi, lib) of a module with the mechanism's sigma kernels."""
    name = request.param
    library = load(name)
    n = len(library.EXAMPLE)
    fields = " ".join(f"double {p};" for p in library.EXAMPLE)
    values = f"{name.upper()}_SIGMA_VALUES"
    degree = f"{name.upper()}_N_SIGMA"
    ffi = cffi.FFI()
    ffi.cdef(f"""
        typedef struct {{ {fields} }} {name}_params;
        typedef struct {{ double hi, lo; }} codegen_dd;
        #define {values} ...
        #define {degree} ...
        void {name}_sigma_kernel_work(const {name}_params *params, double *out, codegen_dd *v);
        void {name}_sigma_bounds_kernel_work(const {name}_params *params, double *out,
                                             double *bound, codegen_dd *v, double *e);
    """)
    generated = ROOT / "generated"
    module = f"_sigma_bound_{name}"
    ffi.set_source(module, f'#include "{name}.h"\n#include "{name}_kernels.h"',
                   sources=[str(generated / name / f"{name}.c"),
                            str(generated / "runtime" / "codegen_dd.c"),
                            str(generated / "runtime" / "codegen_interval.c"),
                            str(generated / "runtime" / "codegen_roots.c")],
                   include_dirs=[str(generated / name), str(generated / "runtime")],
                   extra_compile_args=[*cflags("base"), "-O1"], libraries=["m"])
    path = ffi.compile(tmpdir=str(tmp_path_factory.mktemp(module)))
    spec = importlib.util.spec_from_file_location(module, path)
    compiled = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(compiled)
    assert n == len(library.EXAMPLE)
    return name, compiled.ffi, compiled.lib


def _exact(name):
    function = _plan(name).function("sigma")
    exprs = function.explicit([e for out in function.outputs for e in out.exprs])
    symbols = [sp.Symbol(p, real=True) for p in load(name).EXAMPLE]
    return mp_lambdify(symbols, exprs, dps=60)


def _parameter_sets(name, count, spread, seed):
    example = load(name).EXAMPLE
    rng = np.random.default_rng(seed)
    return [{p: v * float(np.exp(rng.uniform(-spread, spread))) for p, v in example.items()}
            for _ in range(count)]


@pytest.mark.parametrize("spread", [0.05, 1.5], ids=["near", "far"])
def test_every_coefficient_is_within_its_bound_of_the_exact_value(bounded, spread):
    name, ffi, lib = bounded
    exact = _exact(name)
    n_sigma = getattr(lib, f"{name.upper()}_N_SIGMA")
    n_values = getattr(lib, f"{name.upper()}_SIGMA_VALUES")
    ratios = []
    for values in _parameter_sets(name, 40, spread, 29 + int(10 * spread)):
        params = ffi.new(f"{name}_params *", values)
        out, bound = ffi.new("double[]", n_sigma), ffi.new("double[]", n_sigma)
        plain = ffi.new("double[]", n_sigma)
        getattr(lib, f"{name}_sigma_bounds_kernel_work")(
            params, out, bound, ffi.new("codegen_dd[]", n_values), ffi.new("double[]", n_values))
        getattr(lib, f"{name}_sigma_kernel_work")(params, plain, ffi.new("codegen_dd[]", n_values))
        assert list(out) == list(plain)  # the same values, bit for bit
        with mpmath.workdps(60):
            reference = exact(*values.values())
            size = max(abs(x) for x in reference)
            for i, x in enumerate(reference):
                error = abs(mpmath.mpf(out[i]) - x)
                assert error <= bound[i], (values, i, out[i], float(x), float(error), bound[i])
                ratios.append(float(bound[i] / size))
    # a bound of use: a few units of the coefficients' own rounding at most
    assert np.median(ratios) < 2.0**-50, np.median(ratios)
