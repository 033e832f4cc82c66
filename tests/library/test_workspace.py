"""The analysis in the caller's working memory (PREFIX_analyze_work, PREFIX_isolate_work), the
entries a firmware calls to keep its stack small: the same bytes as the plain entries, with
one workspace reused dirty from set to set, and a NULL workspace refused."""
from __future__ import annotations

import numpy as np
import pytest

from codegen.api import load, shipped
from sampling import near_example

SEED = 20_240_611


ROUTES = ("analyze", "isolate")


def _call(lib, entry, params, *workspace):
    ffi, P = lib.ffi, lib.PREFIX
    result = ffi.new(f"{P}_analysis *")
    status = getattr(lib.lib, f"{P}_{entry}")(lib._c_params(params), result, *workspace)
    return status, bytes(ffi.buffer(result))


@pytest.mark.parametrize("name", [n for n in shipped() if load(n).dof == 1])
def test_work_entries_give_the_plain_entries_bytes(name):
    lib = load(name)
    rng = np.random.default_rng([SEED, 31])
    workspace = lib.ffi.new(f"{lib.PREFIX}_workspace *")
    lib.ffi.buffer(workspace)[:] = b"\xa5" * lib.ffi.sizeof(workspace[0])  # dirty from the start
    sets = [lib.example_params()] + [lib.example_params(**near_example(lib, rng, 0.3))
                                     for _ in range(6 if name == "four_bar" else 20)]
    for entry in ROUTES:
        for p in sets:
            plain = _call(lib, entry, p)
            assert _call(lib, f"{entry}_work", p, workspace) == plain, (name, entry, p)


@pytest.mark.parametrize("name", [n for n in shipped() if load(n).dof == 1])
def test_work_entries_refuse_null_and_leave_the_result_on_failure(name):
    lib = load(name)
    ffi, P = lib.ffi, lib.PREFIX
    workspace = ffi.new(f"{P}_workspace *")
    bad = lib.example_params(**{lib.PARAMETER_NAMES[0]: float("nan")})
    for entry in ROUTES:
        status, _ = _call(lib, f"{entry}_work", lib.example_params(), ffi.NULL)
        assert status == lib.STATUS["ERR_NULL_POINTER"]
        result = ffi.new(f"{P}_analysis *")
        ffi.buffer(result)[:] = b"\x5a" * ffi.sizeof(result[0])
        status = getattr(lib.lib, f"{P}_{entry}_work")(lib._c_params(bad), result, workspace)
        assert status != lib.STATUS["OK"]
        assert bytes(ffi.buffer(result)) == b"\x5a" * ffi.sizeof(result[0])
