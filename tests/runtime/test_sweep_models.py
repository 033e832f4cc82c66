"""Every feature for every n (issue 50): a sweep and ``analyze_table`` of a user's model file,
with one coordinate and with several, set by set against the library's own single analysis
(``library.analyze``), through the Python API and through ``mechvib sweep --model FILE``; and
the matrix functions of a mechanism with several coordinates: ``None`` for the example, n x n
matrices and n-vectors (a leading batch dimension in a batch), their values those of the
model's own SymPy expressions evaluated with mpmath at 40 digits."""
from __future__ import annotations

import csv
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest

from codegen.api import LibraryError, load
from codegen.cli.common import number
from codegen.runtime import sweep as sw
from codegen.runtime.analysis import KINDS, STABILITY

REPO = Path(__file__).resolve().parents[2]
MODELS = Path(__file__).resolve().parents[1] / "models"

#: A user's model with one coordinate (the polynomial route), and one with two (a dyad).
ONE, TWO = "two_spring_pendulum", "four_bar_pendulum"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """model name -> (its file, the folder it is built in, its Library): each built once
    (~15 s), on first use, and reused by the command line (--build DIR)."""
    from codegen.user_model import library

    done = {}

    def build(name):
        if name not in done:
            path, folder = MODELS / f"{name}.py", tmp_path_factory.mktemp(name)
            done[name] = path, folder, library(path, folder)
        return done[name]
    return build


def _sets(lib, name):
    """Parameter sets around the example, a few made to fail (NaN), and for the four-bar a
    crank too long to turn fully (its dead points: boxes left undecided)."""
    if name == ONE:
        table = sw.sample(lib, 40, {"k_1": (20, 90), "l_1": (0.5, 1.1), "c": (0, 1)}, seed=5)
        table["l_1"][7::13] = math.nan
    else:
        table = sw.sample(lib, 30, {"k_c": (0.3, 12), "alpha": (-2.5, 2.5),
                                    "m_p": (0.1, 2)}, seed=5)
        table["a_2"][4::9] = 0.3     # the crank cannot turn fully
        table["k_c"][6::11] = math.nan
    return table


def _single(lib, values):
    """library.analyze of one set of a table, or the LibraryError it raises."""
    try:
        return lib.analyze({n: float(values[n]) for n in lib.PARAMETER_NAMES})
    except LibraryError as error:
        return error


def _same(a, b):
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


def _stability_code(e) -> int:
    """An equilibrium's stability as a table's code (one vocabulary for any number of
    coordinates)."""
    return STABILITY.index(e.stability)


def _assert_one_coordinate_rows(rows, analysis):
    kept = [r for r in analysis.roots if r.kind == "equilibrium"]
    if not kept:
        assert len(rows) == 1 and math.isnan(rows["theta"][0]) and rows["kind"][0] == sw.NO_ROOT
        return
    assert len(rows) == len(kept)
    for row, r in zip(rows, kept):
        assert (row["theta"], row["K"], row["M"], row["B"]) == (r.theta, r.K, r.M, r.B)
        assert KINDS[row["kind"]] == r.kind and bool(row["certified"]) == r.certified
        assert row["stability"] == STABILITY.index(r.stability)
        real = r.omega_n.imag == 0 and r.omega_n.real > 0
        assert _same(row["omega_n"], r.omega_n.real if real else math.nan)
        assert _same(row["zeta"], r.zeta.real if real else math.nan)


def _assert_several_coordinates_rows(lib, rows, analysis):
    names = [c["name"] for c in lib.SPEC["coordinates"]]
    assert np.all(rows["uncertain"] == len(analysis.uncertain))
    if not analysis.equilibria:
        assert len(rows) == 1 and all(math.isnan(rows[n][0]) for n in names)
        assert rows["stability"][0] == sw.NO_ROOT
        return
    assert len(rows) == len(analysis.equilibria)
    for row, e in zip(rows, analysis.equilibria):
        assert [row[n] for n in names] == list(e.theta)
        assert row["stability"] == _stability_code(e)
        for j in range(lib.dof):
            assert _same(row[f"omega_n_{j + 1}"], e.frequencies[j])
            assert _same(row[f"zeta_{j + 1}"], e.modal_damping[j])


@pytest.mark.parametrize("name", [ONE, TWO])
def test_a_sweep_of_a_users_model_is_its_single_analyses(built, name):
    _, _, lib = built(name)
    table = _sets(lib, name)
    rows = lib.sweep(table, chunk=7, workers=2)
    assert rows.dtype == sw.dtype(lib) and set(rows["set"]) == set(range(len(table)))
    assert rows.tobytes() == sw.sweep(lib, table, chunk=1000, workers=1).tobytes()
    failed = undecided = 0
    for i, values in enumerate(table):
        mine, single = rows[rows["set"] == i], _single(lib, values)
        assert all(_same(mine[c], np.full(len(mine), values[n])) for n, c in
                   zip(lib.PARAMETER_NAMES, sw.parameter_columns(lib)))
        if isinstance(single, LibraryError):
            failed += 1
            assert len(mine) == 1 and np.all(mine["status"] == single.status)
            continue
        assert np.all(mine["status"] == 0)
        if lib.dof == 1:
            _assert_one_coordinate_rows(mine, single)
        else:
            _assert_several_coordinates_rows(lib, mine, single)
            undecided += bool(single.uncertain)
    assert failed > 0 and (lib.dof == 1 or undecided > 0)   # both kinds of set were there


@pytest.mark.parametrize("name", [ONE, TWO])
def test_analyze_table_of_a_users_model_is_its_single_analyses(built, name):
    _, _, lib = built(name)
    table = _sets(lib, name)
    result = lib.analyze_table(table, workers=2)
    assert result.method == (lib.analyze(None).method if lib.dof == 1 else "isolate")
    for i, values in enumerate(table):
        mine, single = result.roots[result.roots["set"] == i], _single(lib, values)
        assert result.counts[i] == len(mine)
        if isinstance(single, LibraryError):
            assert result.statuses[i] == single.status and len(mine) == 0
            continue
        assert result.statuses[i] == 0
        if lib.dof == 1:
            assert result.uncertain is None and len(mine) == len(single.roots)
            for row, r in zip(mine, single.roots):
                assert (row["theta"], row["theta_lo"], row["theta_hi"], row["K"]) == (
                    r.theta, r.theta_lo, r.theta_hi, r.K)
                assert KINDS[row["kind"]] == r.kind
                assert _same(row["omega_n"], r.omega_n) and _same(row["zeta"], r.zeta)
            continue
        assert result.uncertain[i] == len(single.uncertain)
        assert len(mine) == len(single.equilibria)
        assert np.all(mine["certified"]) and np.all(mine["kind"] == KINDS.index("equilibrium"))
        for row, e in zip(mine, single.equilibria):
            for field, value in (("theta", e.theta), ("theta_lo", e.lo), ("theta_hi", e.hi),
                                 ("omega_squared", e.omega_squared), ("shapes", e.shapes),
                                 ("eigenvalues", e.eigenvalues),
                                 ("damping_ratios", e.damping_ratios),
                                 ("zeta", e.modal_damping), ("omega_n", e.frequencies)):
                assert _same(row[field], value), field
            assert row["stability"] == _stability_code(e)
    assert len(result.equilibria) == np.count_nonzero(result.roots["kind"] == 0)
    empty = lib.analyze_table(table[:0])
    assert len(empty.roots) == 0 and empty.roots.dtype == result.roots.dtype


def test_several_coordinates_have_no_polynomial_route():
    lib = load("double_pendulum")
    for call in (lambda: lib.analyze_table(lib.params_array([lib.EXAMPLE]), "polynomial"),
                 lambda: lib.sweep(lib.params_array([lib.EXAMPLE]), method="polynomial")):
        with pytest.raises(ValueError, match="several coordinates there is no polynomial"):
            call()
    assert lib.analyze_table(lib.params_array([lib.EXAMPLE]), "isolate").method == "isolate"


def test_a_sweep_of_a_users_model_over_dask_is_the_same(built):
    """A dask array of sets, and the chunks on a local cluster's worker process, which loads
    the user's library again from its folder (its origin)."""
    da = pytest.importorskip("dask.array")
    distributed = pytest.importorskip("distributed")
    _, _, lib = built(TWO)
    table = _sets(lib, TWO)[:12]
    local = sw.sweep(lib, table)
    assert sw.sweep(lib, da.from_array(table, chunks=5)).tobytes() == local.tobytes()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            assert sw.sweep(lib, table, client=client, chunk=5).tobytes() == local.tobytes()


# --------------------------------------------------------------------- the command line

def mechvib(*args, cwd):
    """`mechvib sweep ARGS` of this checkout."""
    return subprocess.run([sys.executable, "-m", "codegen", "sweep", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(REPO),
                               "XDG_CACHE_HOME": str(cwd / "cache")})


def _read(path: Path) -> dict[str, list]:
    """A written table as {column: values}: numbers as floats, text (and true/false) as
    read, None where empty (null)."""
    if path.suffix == ".parquet":
        pq = pytest.importorskip("pyarrow.parquet")
        return pq.read_table(path).to_pydict()
    with open(path, newline="") as f:
        header, *lines = list(csv.reader(f))

    def value(name, text):
        if text == "" or name in sw.LABELS:
            return text or None
        return {"true": True, "false": False}[text] if name == "certified" else float(text)
    return {name: [value(name, line[k]) for line in lines] for k, name in enumerate(header)}


def _assert_file_holds(lib, path: Path, rows) -> None:
    """The file holds the sweep's rows: angle columns in degrees as NAME_deg, coded columns as
    text, null where a row has no root."""
    rows = sw.in_degrees(rows, sw.angle_columns(lib))
    data = _read(path)
    assert list(data) == list(rows.dtype.names)
    for name in rows.dtype.names:
        if name in sw.LABELS:
            assert data[name] == [None if c == sw.NO_ROOT else sw.LABELS[name][c]
                                  for c in rows[name]], name
        elif name == "certified":
            rootless = rows["kind"] == sw.NO_ROOT
            assert data[name] == [None if r else bool(c) for c, r in zip(rows[name], rootless)]
        else:
            assert _same(np.array(data[name], dtype=float), rows[name]), name


#: Per model: the command line's --vary and --set, and the same as SI grid axes and a base.
CASES = {ONE: (["--vary", "k_1=20:90:4", "--vary", "l_1=0.6:1:3", "--set", "c=0.1"],
               {"k_1": np.linspace(20, 90, 4), "l_1": np.linspace(0.6, 1, 3)}, {"c": 0.1}),
         TWO: (["--vary", "k_c=0.5:8:4", "--vary", "alpha=-60:60:3", "--set", "a_2=0.3"],
               {"k_c": np.linspace(0.5, 8, 4),
                "alpha": np.linspace(number("alpha", "-60", "rad"),
                                     number("alpha", "60", "rad"), 3)}, {"a_2": 0.3})}


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
@pytest.mark.parametrize("name", [ONE, TWO])
def test_the_command_line_sweeps_a_users_model(built, tmp_path, name, suffix):
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    path, folder, lib = built(name)
    options, axes, base = CASES[name]
    out = mechvib("--model", str(path), "--build", str(folder), *options, "--workers", "2",
                  "--chunk", "5", "--out", f"table{suffix}", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""           # the build in DIR is reused: no stage is printed
    rows = lib.sweep(sw.grid(lib, axes, base))
    _assert_file_holds(lib, tmp_path / f"table{suffix}", rows)
    summary = " ".join(out.stdout.split())
    assert re.fullmatch(rf"Swept 12 parameter sets of {re.escape(lib.TITLE)} in [\d.]+ s on 2 "
                        rf"threads \([\d,]+ sets/s\)\. 0 sets failed; \d+ equilibria found, \d+ "
                        rf"of them stable\. Wrote {len(rows)} rows to table\{suffix}\.",
                        summary), summary


def test_the_command_line_refuses_a_build_folder_without_a_model_and_a_bad_table_first(
        tmp_path):
    out = mechvib("--build", "here", "--vary", "F=0:1:2", "--out", "t.csv", cwd=tmp_path)
    assert out.returncode == 2 and "--build DIR is where --model FILE is built" in out.stderr
    # the table's name is checked before the model is built (minutes)
    out = mechvib("--model", str(MODELS / f"{TWO}.py"), "--vary", "k_c=1:2:2", "--out",
                  "t.txt", cwd=tmp_path)
    assert out.returncode == 2 and "t.txt: the output must end in .csv or .parquet" in out.stderr
    assert not (tmp_path / "cache").exists()


# ------------------------------------------------------------ the functions of n coordinates

def _expressions(model):
    """The model's own expressions of M, B, h, G, K (SymPy, from its derivation) as one
    function of the parameters, theta and its rates, evaluated with mpmath (each dyad's
    program step by step): {name: its values as a list}."""
    from codegen.compiler.derivation.multibody import derive_multibody
    from codegen.compiler.model import load as load_model
    from codegen.compiler.verification_multibody import in_program

    d = derive_multibody(load_model(str(model)))
    args = list(d.mechanism.symbols) + list(d.theta) + list(d.theta_d)
    parts = {"mass_matrix": d.mass, "damping_matrix": d.damping,
             "velocity_terms": d.velocity_terms, "generalised_force": d.generalised_force,
             "stiffness_matrix": d.stiffness}
    f = in_program(args, d.program, [e for m in parts.values() for e in m], "mpmath")

    def evaluate(params, theta, rates):
        with mpmath.workdps(40):
            values = f(*(mpmath.mpf(float(v)) for v in [*params, *theta, *rates]))
        out, at = {}, 0
        for key, matrix in parts.items():
            out[key], at = values[at:at + len(matrix)], at + len(matrix)
        return out
    return evaluate


MATRICES = ("mass_matrix", "damping_matrix", "stiffness_matrix")
VECTORS = ("generalised_force",)


@pytest.mark.parametrize("name", ["double_pendulum", TWO])
def test_the_matrix_functions_take_none_and_give_matrices_of_the_models_values(built, name):
    """A shipped mechanism, and a user's with a dyad (its expressions a program of steps)."""
    model, lib = (name, load(name)) if name != TWO else built(name)[::2]
    n, theta, rates = lib.dof, np.array([1.2, 0.3]), np.array([0.7, -0.4])
    example = lib.example_params()
    reference = _expressions(model)(lib._fields(example), theta, rates)
    calls = {f: (theta,) for f in MATRICES + VECTORS}
    calls["velocity_terms"] = (theta, rates)
    for f, args in calls.items():
        value = lib.FUNCTIONS[f](None, *args)
        assert value.shape == ((n, n) if f in MATRICES else (n,)), f
        assert np.array_equal(value, lib.FUNCTIONS[f](example, *args)), f
        assert np.array_equal(value, lib.FUNCTIONS[f](lib.EXAMPLE, *args)), f
        exact = np.array([float(x) for x in reference[f]]).reshape(value.shape)
        scale = 1 + np.abs(exact).max()
        assert np.abs(value - exact).max() <= 1e-12 * scale, (f, value, exact)
        # a batch keeps its leading dimension: by params, by the coordinates, or both
        table = lib.params_array([example, example, {**lib.EXAMPLE, "g": 0.0}])
        many = lib.FUNCTIONS[f](table, *args)
        assert many.shape == (3, *value.shape) and np.array_equal(many[0], value), f
        stacked = lib.FUNCTIONS[f](None, *(np.stack([a, a]) for a in args))
        assert stacked.shape == (2, *value.shape) and np.array_equal(stacked[1], value), f
        assert np.array_equal(lib.FUNCTIONS[f].batch(example, *args)[0], value), f
    for f in MATRICES:   # symmetric, as M, B and K (a potential's Hessian) are
        value = lib.FUNCTIONS[f](None, theta)
        assert np.allclose(value, value.T, rtol=1e-12, atol=0), f


def test_every_function_the_multibody_guide_shows_runs_as_shown():
    """docs/multibody.md's Python runs: each call on None for the example, with the shapes
    its comments and its text give."""
    text = (REPO / "docs" / "multibody.md").read_text().split("## From Python", 1)[1]
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    scope: dict = {"print": lambda *a: None}
    exec(compile(code, "docs/multibody.md", "exec"), scope)
    lib, n = scope["lib"], scope["lib"].dof
    assert scope["H"].shape == (3, n, n) and scope["motion"].theta.shape == (3, n)
    for matrix in ("M", "B", "K"):
        assert scope[matrix].shape == (n, n)
    assert scope["G"].shape == scope["h"].shape == (n,) and scope["Ms"].shape == (4, n, n)
    rates = np.array([0.5, -1.0])
    assert scope["T"] == pytest.approx(rates @ scope["M"] @ rates / 2, rel=1e-13)
    table, rows, sets = scope["table"], scope["rows"], scope["sets"]
    assert table.roots["theta"].shape == (len(table.roots), n)
    assert table.uncertain.shape == table.counts.shape == (len(sets),)
    names = [c["name"] for c in lib.SPEC["coordinates"]]
    assert np.array_equal(np.column_stack([rows[c] for c in names]), table.roots["theta"])
