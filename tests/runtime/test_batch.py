"""codegen.runtime.batch: the analysis of many sets as structured arrays, over threads, against
analyze() one set at a time."""
from __future__ import annotations

import math

import numpy as np
import pytest

from codegen.runtime.analysis import DAMPING, KINDS, STABILITY, analyze
from codegen.api import load
from codegen.runtime import batch
from codegen.runtime.batch import ROOT_DTYPE, analyze_table

#: (mechanism, route): both routes where G is algebraic, isolation where it is not.
CASES = [("doughty", "polynomial"), ("doughty", "isolate"), ("slider_crank", "polynomial"),
         ("torsion_pendulum", "isolate")]


def _sets(lib, n, seed):
    """n sets around the example (every parameter scaled by up to 2x either way), with
    every fifth one made invalid (a negative first parameter or NaN)."""
    rng = np.random.default_rng(seed)
    example = lib.example_params()
    sets = []
    for i in range(n):
        values = {name: getattr(example, name) * math.exp(rng.uniform(-0.7, 0.7))
                  for name in lib.PARAMETER_NAMES}
        if i % 5 == 4:
            values[lib.PARAMETER_NAMES[i % len(lib.PARAMETER_NAMES)]] = math.nan
        sets.append(lib.Params(**values))
    return sets


def _same(a, b):
    return a == b or (math.isnan(a) and math.isnan(b))


@pytest.mark.parametrize("name, method", CASES)
def test_rows_are_what_analyze_gives_set_by_set(name, method):
    lib = load(name)
    sets = _sets(lib, 30, 7)
    result = analyze_table(lib.params_array(sets), lib, method)
    assert result.roots.dtype == ROOT_DTYPE and result.method == method
    assert result.counts.sum() == len(result.roots)
    assert 0 < np.count_nonzero(result.statuses) < len(sets)   # failures are rows-free
    assert np.all(np.diff(result.roots["set"]) >= 0)
    for i, p in enumerate(sets):
        rows = result.roots[result.roots["set"] == i]
        try:
            single = analyze(p, method)
        except ValueError as error:
            assert result.statuses[i] == error.status and len(rows) == 0
            continue
        assert result.statuses[i] == 0 and len(rows) == len(single.roots)
        for row, r in zip(rows, single.roots):
            assert (row["theta"], row["theta_lo"], row["theta_hi"]) == (
                r.theta, r.theta_lo, r.theta_hi)
            assert bool(row["certified"]) == r.certified and KINDS[row["kind"]] == r.kind
            # an extraneous root is no equilibrium: no code in the rows, None in Python
            assert (STABILITY[row["stability"]] if row["stability"] >= 0 else None) == r.stability
            assert (DAMPING[row["damping"]] if row["damping"] >= 0 else None) == r.damping
            for field in ("M", "B", "K", "residual", "relative_residual"):
                assert _same(float(row[field]), getattr(r, field)), field
            for field in ("omega_n", "zeta"):
                z, w = complex(row[field]), getattr(r, field)
                assert _same(z.real, w.real) and _same(z.imag, w.imag), field
            assert tuple(row["eigenvalues"]) == r.eigenvalues
    assert len(result.equilibria) == sum(
        r.genuine for p, s in zip(sets, result.statuses) if s == 0
        for r in analyze(p, method).roots)


@pytest.mark.parametrize("workers", [2, 3, 7])
def test_any_number_of_threads_and_blocks_gives_the_same_arrays(workers, monkeypatch):
    lib = load("doughty")
    table = lib.params_array(_sets(lib, 41, 11))
    one = analyze_table(table, lib)
    monkeypatch.setattr(batch, "BLOCK", 4)   # threads' ranges cross many blocks
    many = lib.analyze_table(table, workers=workers)
    assert np.array_equal(one.statuses, many.statuses)
    assert one.roots.tobytes() == many.roots.tobytes()   # bit for bit, NaNs included


def test_empty_tables_and_bad_arguments():
    lib = load("doughty")
    empty = analyze_table(lib.params_array([]), lib, workers=4)
    assert len(empty.roots) == 0 and len(empty.statuses) == 0
    for workers in (0, -1, 1.5):
        with pytest.raises(ValueError, match="workers"):
            analyze_table(lib.params_array([lib.example_params()]), lib, workers=workers)
    with pytest.raises(ValueError, match="not algebraic"):
        analyze_table(load("torsion_pendulum").params_array([]), load("torsion_pendulum"),
                      "polynomial")
