"""Inputs a hostile user gives are refused in one line, never silently used (issue 27).

Batch parameter tables are matched by field name: every entry that takes a table (a
function's batch, ``analyze_batch``, ``analyze_table``) goes through ``Library.table``, and a
table with its fields in another order gives the same results bit for bit as the library's
own layout. Numerical options beyond what the arithmetic supports are refused.
"""
from __future__ import annotations

import numpy as np
import pytest

from codegen.api import load

lib = load("doughty")
NAMES = lib.PARAMETER_NAMES


def _sets(count: int = 3) -> np.ndarray:
    return lib.params_array([lib.example_params(F=100.0 + 10 * i, k=1500.0 + 200 * i)
                             for i in range(count)])


def _reordered(table: np.ndarray, dtype=np.float64) -> np.ndarray:
    other = np.zeros(len(table), dtype=[(n, dtype) for n in reversed(NAMES)])
    for name in NAMES:
        other[name] = table[name]
    return other


def test_fields_in_another_order_give_the_same_results():
    table = _sets()
    other = _reordered(table)
    theta = np.array([0.1, 1.2, -2.0])
    assert np.array_equal(lib.equilibrium_residual.batch(table, theta).residual,
                          lib.equilibrium_residual.batch(other, theta).residual)
    mine, theirs = lib.analyze_table(table), lib.analyze_table(other)
    assert mine.roots.tobytes() == theirs.roots.tobytes() and mine.roots.size
    analyses, _ = lib.analyze_batch(other)
    assert [a.params for a in analyses] == [lib.Params(**{n: float(t[n]) for n in NAMES})
                                            for t in table]


def test_float32_fields_are_widened():
    table = _sets()
    narrow = _reordered(table, np.float32)
    assert lib.table(narrow)["F"].tolist() == table["F"].astype(np.float32).tolist()


@pytest.mark.parametrize("bad, words", [
    (np.zeros((2, len(NAMES))), "not a plain float64 array of shape (2, 11)"),
    (np.zeros(2, dtype=[(n, np.int64) for n in NAMES]), "floating-point scalars: H (int64)"),
    (None, "not NoneType"),
    (np.zeros(2, dtype=[(n, np.float64) for n in NAMES if n != "F"]), "missing F"),
    (np.zeros(2, dtype=[(n, np.float64) for n in NAMES + ("G",)]), "unknown G"),
    (np.stack([np.zeros(2, dtype=lib.PARAMS_DTYPE)] * 2), "one-dimensional"),
])
def test_anything_else_is_refused_in_one_line(bad, words):
    for call in (lambda: lib.analyze_table(bad), lambda: lib.analyze_batch(bad),
                 lambda: lib.linearisation.batch(bad, np.zeros(2))):
        with pytest.raises(ValueError) as error:
            call()
        message = str(error.value)
        assert words in message and "\n" not in message, message


@pytest.mark.parametrize("tolerance", [1e300, float("inf"), float("nan"), 0.0, -1.0, True])
def test_a_branch_tolerance_that_would_drop_the_folds_is_refused(tolerance):
    with pytest.raises(ValueError, match="tolerance: must be positive and below the samples' "
                                         r"spacing \(4.08163\)"):
        lib.branches("F", 0.0, 200.0, points=50, tolerance=tolerance)


def test_a_tolerance_below_the_spacing_still_locates_the_folds():
    found = lib.branches("F", -200.0, 300.0, points=200, tolerance=1e-6)
    assert sum(e.kind == "fold" for e in found.events) == 2


@pytest.mark.parametrize("theta0, theta_d0, words", [
    (1e20, 0.0, "theta0: 1e+20 rad is beyond what double precision resolves"),
    (-2.0**23, 0.0, "|theta0| <= 4.1943e+06 rad"),
    (0.1, 1e308, "theta_d0: 1e+308 rad/s is beyond"),
])
def test_an_initial_state_beyond_double_precision_is_refused(theta0, theta_d0, words):
    with pytest.raises(ValueError) as error:
        lib.simulate(None, theta0, theta_d0, np.linspace(0.0, 1.0, 5))
    assert words in str(error.value)


def test_a_large_but_resolvable_initial_state_runs():
    trajectory = lib.simulate(None, 2.0**21, 10.0, np.linspace(0.0, 0.01, 3))
    assert np.isfinite(trajectory.theta).all()


def _analyze_set(params):
    from codegen.runtime.analysis import analyze
    return analyze(params)


def test_a_pool_child_that_cannot_load_the_library_reports_it(tmp_path):
    """A spawn pool's worker unpickles each task's parameters, loading their library; where
    that folder is gone it gets the error when the task runs (raised while unpickling, it
    ended the worker, and the pool waited for the task forever)."""
    import multiprocessing
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    from codegen.api import load_from

    repo = Path(__file__).resolve().parents[2]
    model = (repo / "tests" / "system" / "test_user_model.py").read_text()
    (tmp_path / "mine.py").write_text(model.split("MODEL = '''\\\n", 1)[1].split("'''", 1)[0])
    out = tmp_path / "lib"
    done = subprocess.run([sys.executable, "-m", "codegen", "generate", "--model",
                           str(tmp_path / "mine.py"), "--out", str(out)], cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lib = load_from(out, "spring_pendulum")
    sets = [lib.example_params(k=k) for k in (5.0, 20.0)]
    shutil.rmtree(out)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        result = pool.map_async(_analyze_set, sets, chunksize=1)
        with pytest.raises(ValueError, match="'spring_pendulum' could not be loaded in this "
                                             "process"):
            result.get(timeout=120)


@pytest.mark.parametrize("call, words", [
    (lambda: lib.example_params(F="a"), "F: 'a' is not a number"),
    (lambda: lib.example_params(k=None), "k: None is not a number"),
    (lambda: lib.Params(**{**lib.EXAMPLE, "H": True}), "H: True is not a number"),
    (lambda: lib.linearisation(lib.example_params(), "x"), "theta: 'x' is not a number"),
    (lambda: lib.branches("F", "a", 3.0), "from: 'a' is not a number"),
])
def test_a_value_that_is_not_a_number_is_named(call, words):
    with pytest.raises(ValueError) as error:
        call()
    assert str(error.value) == words


def test_numbers_of_other_types_become_floats():
    params = lib.example_params(F=np.float32(2.5), k=2000)
    assert (params.F, params.k) == (2.5, 2000.0) and type(params.k) is float


@pytest.mark.parametrize("b", [1e154, 1e200, 1e300, 1.7e308])
def test_a_huge_damping_gives_finite_eigenvalues_where_they_are_representable(b):
    """B/(2M) squared overflows but the eigenvalues of M s^2 + B s + K do not: the analysis
    gives them finite, with the sum -B/M and the product K/M they must have."""
    from codegen.runtime.analysis import analyze

    equilibria = [r for r in analyze(lib.example_params(b=b)).roots if r.genuine]
    assert equilibria
    for r in equilibria:
        values = [r.omega_n, r.zeta, *r.eigenvalues]
        assert all(np.isfinite(z.real) and np.isfinite(z.imag) for z in values), values
        first, second = r.eigenvalues
        assert (first + second).real == pytest.approx(-r.B / r.M, rel=1e-12)
        assert (first * second).real == pytest.approx(r.K / r.M, rel=1e-12)


def test_eigenvalues_too_large_to_represent_are_an_overflow_not_success():
    """B/M beyond the range of double: a status saying so, never OK with an infinity."""
    from codegen.runtime.analysis import analyze

    tiny = dict(m_A=1e-30, m_B=1e-30, m_C=1e-30)
    with pytest.raises(lib.LibraryError, match="too large to represent"):
        analyze(lib.example_params(b=1e300, **tiny))


def test_the_cli_prints_huge_damping_finite_and_short():
    """--json has no null eigenvalue and the table no value hundreds of digits long."""
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    repo = Path(__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": str(repo)}

    def analyze(*extra: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "codegen", "analyze", "--set", "b=1e300",
                               *extra], capture_output=True, text=True, env=env, timeout=120)

    data = json.loads(analyze("--json").stdout)
    genuine = [r for r in data["roots"] if r["genuine"]]
    assert genuine and all(None not in z for r in genuine for z in r["eigenvalues"])
    table = analyze("--wide")
    assert table.returncode == 0, table.stderr
    numbers = [word for word in table.stdout.split() if any(c.isdigit() for c in word)]
    assert max(len(word) for word in numbers) < 20, table.stdout
    tiny = analyze("--set", "m_A=1e-30", "--set", "m_B=1e-30", "--set", "m_C=1e-30")
    assert tiny.returncode == 2 and "too large to represent" in tiny.stderr
    assert "Traceback" not in tiny.stderr and tiny.stdout == ""
