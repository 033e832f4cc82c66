"""codegen.runtime.sweep and `mechvib sweep`: grids and samples of parameter sets, analysed into one
row per root, against batch.analyze_table set by set; written to CSV and Parquet and read
back; the same bit for bit on any threads, chunks, and on a Dask cluster."""
from __future__ import annotations

import io
import math
import os
import re
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from codegen.runtime import sweep as sw
from codegen.runtime.analysis import KINDS
from codegen.api import load
from codegen.runtime.batch import analyze_table
from codegen.cli.common import ProgressBar

pa = pytest.importorskip("pyarrow")
import pyarrow.csv as pacsv  # noqa: E402
import pyarrow.parquet as pq  # noqa: E402

#: (mechanism, route, the parameter whose large value leaves a set without any equilibrium)
MECHANISMS = [("doughty", "polynomial", None), ("slider_crank", "polynomial", "T"),
              ("torsion_pendulum", "isolate", None)]


def _sets(lib, n, seed, empty=None):
    """n sets around the example (three parameters drawn within +-40%), every seventh made
    to fail (NaN), and with ``empty`` (a torque) one set left without an equilibrium."""
    names = lib.PARAMETER_NAMES[:3]
    ranges = {name: sorted((0.6 * lib.EXAMPLE[name], 1.4 * lib.EXAMPLE[name])) for name in names}
    table = sw.sample(lib, n, ranges, seed=seed)
    table[names[1]][3::7] = math.nan
    if empty:
        table[empty][5] = 10.0
    return table


def _same(a, b):
    """Equal arrays, NaN equal to NaN."""
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


# ------------------------------------------------------------------------ parameter sets

def test_grid_is_every_combination_over_the_example():
    lib = load("doughty")
    table = sw.grid(lib, {"F": np.linspace(0, 200, 5), "k": [1000.0, 3000.0]})
    assert table.dtype == lib.PARAMS_DTYPE and table.shape == (10,)
    assert list(table["F"]) == [0, 0, 50, 50, 100, 100, 150, 150, 200, 200]   # first: slowest
    assert list(table["k"]) == [1000.0, 3000.0] * 5
    assert all(np.all(table[n] == lib.EXAMPLE[n]) for n in lib.PARAMETER_NAMES if n not in "Fk")
    over = sw.grid(lib, {"F": [1.0]}, base={"b": 0.0})
    assert over["b"][0] == 0.0 and over["H"][0] == lib.EXAMPLE["H"]
    assert sw.grid(lib, {"F": [1.0]}, base=lib.example_params(b=2.0))["b"][0] == 2.0
    assert sw.grid(lib, {}).shape == (1,) and sw.grid(lib, {"F": []}).shape == (0,)


def test_sample_is_uniform_in_its_ranges_and_reproducible():
    lib = load("slider_crank")
    table = sw.sample(lib, 5000, {"F": (-60, 0), "k": (1000, 3000)}, base={"b": 0}, seed=3)
    assert table.dtype == lib.PARAMS_DTYPE and table.shape == (5000,)
    assert table["F"].min() >= -60 and table["F"].max() < 0 and abs(table["F"].mean() + 30) < 1
    assert 1000 <= table["k"].min() and table["k"].max() < 3000
    assert np.all(table["b"] == 0) and np.all(table["R"] == lib.EXAMPLE["R"])
    again = sw.sample(lib, 5000, {"F": (-60, 0), "k": (1000, 3000)}, base={"b": 0}, seed=3)
    assert again.tobytes() == table.tobytes()
    assert not np.array_equal(sw.sample(lib, 5000, {"F": (-60, 0)}, seed=4)["F"], table["F"])


@pytest.mark.parametrize("make, message", [
    (lambda lib: sw.grid(lib, {"Q": [1.0]}), r"unknown parameter\(s\): Q; doughty has H, L"),
    (lambda lib: sw.grid(lib, {"F": [1.0]}, base={"Z": 1}), "unknown parameter.*Z"),
    (lambda lib: sw.grid(lib, {"F": [[1.0, 2.0]]}), "F: a grid axis is a 1-D array"),
    (lambda lib: sw.sample(lib, 10, {"nope": (0, 1)}), "unknown parameter.*nope.*F, g"),
    (lambda lib: sw.sample(lib, 10, {"F": (2, 1)}), "F: a range needs finite lo <= hi"),
    (lambda lib: sw.sample(lib, 10, {"F": (0, math.inf)}), "F: a range needs finite"),
    (lambda lib: sw.sample(lib, 10, {"F": 3}), r"F: a range is a pair \(lo, hi\)"),
    (lambda lib: sw.sample(lib, -1, {"F": (0, 1)}), "count must be a non-negative integer"),
    (lambda lib: sw.sweep(lib, np.zeros(3)), "one field per parameter of doughty"),
    (lambda lib: sw.sweep(lib, sw.grid(lib, {}), roots="some"), "roots must be one of"),
    (lambda lib: sw.sweep(lib, sw.grid(lib, {}), chunk=0), "chunk must be a positive"),
    (lambda lib: sw.sweep(lib, sw.grid(lib, {}), workers=1.5), "workers must be a positive"),
    (lambda lib: sw.sweep(lib, sw.grid(lib, {}), method="magic"), "method must be one of"),
])
def test_bad_arguments_are_value_errors_naming_them(make, message):
    with pytest.raises(ValueError, match=message):
        make(load("doughty"))


# --------------------------------------------------------------------- the analysis

@pytest.mark.parametrize("roots", sw.ROOTS)
@pytest.mark.parametrize("name, method, empty", MECHANISMS)
def test_rows_are_analyze_table_set_by_set(name, method, empty, roots):
    lib = load(name)
    table = _sets(lib, 60, 5, empty)
    rows = sw.sweep(lib, table, method=method, roots=roots, chunk=16, workers=2)
    reference = analyze_table(table, lib, method)
    assert rows.dtype == sw.dtype(lib) and np.all(np.diff(rows["set"]) >= 0)
    assert set(rows["set"]) == set(range(len(table)))          # every set has a row
    genuine = KINDS.index("equilibrium")
    for i, params in enumerate(table):
        mine = rows[rows["set"] == i]
        assert all(_same(mine[n], np.full(len(mine), params[n])) for n in lib.PARAMETER_NAMES)
        assert np.all(mine["status"] == reference.statuses[i])
        found = reference.roots[reference.roots["set"] == i]
        if roots == "equilibria":
            found = found[found["kind"] == genuine]
        if len(found) == 0:   # failed, or no root kept: one rootless row
            assert len(mine) == 1 and math.isnan(mine["theta"][0])
            assert mine["kind"][0] == mine["stability"][0] == mine["damping"][0] == sw.NO_ROOT
            assert not mine["certified"][0]
            assert all(math.isnan(mine[n][0]) for n in ("omega_n", "zeta", "K", "M", "B"))
            continue
        assert len(mine) == len(found)
        for field in ("theta", "kind", "certified", "K", "M", "B"):
            assert _same(mine[field], found[field]), field
        extraneous = found["kind"] == KINDS.index("extraneous")   # not an equilibrium: null
        for field in ("stability", "damping"):
            assert _same(mine[field], np.where(extraneous, sw.NO_ROOT, found[field])), field
        real = (found["omega_n"].imag == 0) & (found["omega_n"].real > 0)
        assert _same(mine["omega_n"], np.where(real, found["omega_n"].real, np.nan))
        assert _same(mine["zeta"], np.where(real, found["zeta"].real, np.nan))
    assert np.count_nonzero(reference.statuses) > 0   # the failures are there, as rows
    if empty and roots == "equilibria":
        assert reference.statuses[5] == 0 and math.isnan(rows[rows["set"] == 5]["theta"][0])


def test_any_threads_and_chunks_give_the_same_bytes():
    lib = load("doughty")
    table = _sets(lib, 97, 11)
    one = sw.sweep(lib, table, workers=1, chunk=1000)
    for workers, chunk in ((2, 1), (3, 10), (7, 33), (2, 97), (None, sw.CHUNK)):
        assert sw.sweep(lib, table, workers=workers, chunk=chunk).tobytes() == one.tobytes()
    assert lib.sweep(table, chunk=50).tobytes() == one.tobytes()     # Library.sweep
    shuffled = table[list(reversed(lib.PARAMETER_NAMES))]            # fields by name
    assert sw.sweep(lib, np.array(shuffled, dtype=shuffled.dtype)).tobytes() == one.tobytes()


def test_stream_pieces_and_progress():
    lib = load("doughty")
    table = _sets(lib, 50, 2)
    calls = []
    pieces = list(sw.stream(lib, table, chunk=20, progress=lambda d, n: calls.append((d, n))))
    assert [p["set"][0] for p in pieces] == [0, 20, 40] and pieces[-1]["set"][-1] == 49
    assert np.concatenate(pieces).tobytes() == sw.sweep(lib, table).tobytes()
    assert calls == [(0, 50), (20, 50), (40, 50), (50, 50)]
    empty = sw.sweep(lib, sw.grid(lib, {"F": []}))
    assert empty.dtype == sw.dtype(lib) and len(empty) == 0


# --------------------------------------------------------------------------- files

def _in_degrees(rows, angles):
    """rows with each column of ``angles`` it has in degrees, renamed NAME_deg: what a file
    holds (written here apart from the writer's own conversion)."""
    present = [name for name in angles if name in (rows.dtype.names or ())]
    if not present:
        return rows
    names = [f"{n}_deg" if n in present else n for n in rows.dtype.names]
    out = np.empty(len(rows), np.dtype([(new, rows.dtype[old])
                                        for new, old in zip(names, rows.dtype.names)]))
    for new, old in zip(names, rows.dtype.names):
        out[new] = np.degrees(rows[old]) if old in present else rows[old]
    return out


def _read(path):
    """A written table as {column: numpy array}, text columns as lists (None for null)."""
    if path.suffix == ".parquet":
        table = pq.read_table(path)
    else:   # floats declared, as a column of nulls (nan) would not say what it holds
        floats = {f: pa.float64() for f in path.read_text().splitlines()[0].replace('"', "")
                  .split(",") if f not in ("set", "status", "certified", *sw.LABELS)}
        table = pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(
            column_types=floats, strings_can_be_null=True))
    return {name: (table[name].to_pylist() if name in (*sw.LABELS, "certified")
                   else table[name].to_numpy()) for name in table.column_names}


def _assert_file_holds(path, rows):
    """The file holds the rows, theta in degrees as theta_deg (every angle column of a file)."""
    rows = _in_degrees(rows, sw.ANGLES)
    data = _read(path)
    assert list(data) == list(rows.dtype.names)
    rootless = rows["kind"] == sw.NO_ROOT
    for name in rows.dtype.names:
        if name in sw.LABELS:
            assert data[name] == [None if c == sw.NO_ROOT else sw.LABELS[name][c]
                                  for c in rows[name]], name
        elif name == "certified":
            assert data[name] == [None if r else bool(c) for c, r in zip(rows[name], rootless)]
        else:
            assert _same(data[name], rows[name]), name


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_files_read_back_as_the_table(tmp_path, suffix):
    lib = load("slider_crank")
    rows = sw.sweep(lib, _sets(lib, 40, 9, "T"), roots="all")
    path = tmp_path / f"roots{suffix}"
    assert sw.write(rows, path) == len(rows)
    _assert_file_holds(path, rows)
    streamed = tmp_path / f"streamed{suffix}"
    sw.write(sw.stream(lib, _sets(lib, 40, 9, "T"), roots="all", chunk=7), streamed)
    _assert_file_holds(streamed, rows)
    if suffix == ".parquet":   # bit for bit (theta as the degrees np.degrees gives)
        degrees = _in_degrees(rows, sw.ANGLES)
        assert all(pq.read_table(path)[n].to_numpy().tobytes() == degrees[n].tobytes()
                   for n in ("theta_deg", "omega_n", "zeta", "K", "M", "B", "set"))


def test_csv_without_pyarrow_reads_the_same(tmp_path, monkeypatch):
    lib = load("doughty")
    rows = sw.sweep(lib, _sets(lib, 30, 4))
    monkeypatch.setattr(sw, "_pyarrow", lambda: None)
    sw.write(rows, tmp_path / "plain.csv")
    _assert_file_holds(tmp_path / "plain.csv", rows)
    with pytest.raises(ValueError, match=r"Parquet needs pyarrow: pip install 'mechvib\[sweep\]'"):
        sw.write(rows, tmp_path / "t.parquet")
    assert not (tmp_path / "t.parquet").exists()


def test_bad_outputs_and_failures_leave_no_file(tmp_path):
    lib = load("doughty")
    rows = sw.sweep(lib, sw.grid(lib, {"F": [1.0]}))
    with pytest.raises(ValueError, match=r"must end in \.csv or \.parquet"):
        sw.write(rows, tmp_path / "t.xlsx")
    with pytest.raises(ValueError, match="no folder"):
        sw.write(rows, tmp_path / "missing" / "t.csv")

    def broken():
        yield rows
        raise RuntimeError("interrupted")
    with pytest.raises(RuntimeError):
        sw.write(broken(), tmp_path / "t.parquet")
    assert list(tmp_path.iterdir()) == []   # neither the file nor its partial


# --------------------------------------------------------------------------- progress

class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_draws_on_a_terminal_only():
    """The CLI's bar (tqdm) from the progress(done, total) calls of a sweep: drawn on a
    terminal, cleared at the end, nothing in a pipe."""
    screen = _Terminal()
    with ProgressBar(screen, mininterval=0) as bar:
        bar(0, 1000)
        bar(500, 1000)
        assert re.search(r"50%\|[^|]*\| 500/1000 \[.*sets/s\]$", screen.getvalue())
        bar(1000, 1000)
    drawn = screen.getvalue()
    assert "1000/1000" in drawn and drawn.endswith("\r")   # the line cleared at the end
    assert "\n" not in drawn
    pipe = io.StringIO()
    with ProgressBar(pipe) as bar:
        bar(1, 2)
    assert pipe.getvalue() == ""
    assert ProgressBar(None).stream is sys.stderr


# --------------------------------------------------------------------------- the command

REPO = Path(__file__).resolve().parents[2]


def mechvib(*args, cwd, env_extra=None):
    """`mechvib sweep ARGS` of this checkout."""
    return subprocess.run([sys.executable, "-m", "codegen", "sweep", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(REPO), **(env_extra or {})})


def test_cli_grid_to_csv_is_the_python_sweep(tmp_path):
    out = mechvib("--vary", "F=0:200:11", "--vary", "k=1000:3000:3", "--set", "b=0",
                  "--out", "grid.csv", "--workers", "2", "--chunk", "7", cwd=tmp_path)
    assert out.returncode == 0 and out.stderr == "", out.stderr   # no bar in a pipe
    lib = load("doughty")
    rows = sw.sweep(lib, sw.grid(lib, {"F": np.linspace(0, 200, 11),
                                       "k": np.linspace(1000, 3000, 3)}, base={"b": 0}))
    _assert_file_holds(tmp_path / "grid.csv", rows)
    summary = " ".join(out.stdout.split())
    equilibria = np.count_nonzero(rows["kind"] == 0)
    assert re.fullmatch(rf"Swept 33 parameter sets of .+ in [\d.]+ s on 2 threads \([\d,]+ "
                        rf"sets/s\)\. 0 sets failed; {equilibria} equilibria found, \d+ of "
                        rf"them stable\. Wrote {len(rows)} rows to grid\.csv\.", summary), summary


def test_cli_sample_to_parquet_with_every_root(tmp_path):
    out = mechvib("--mechanism", "slider_crank", "--sample", "300", "--vary", "T=0:12",
                  "--vary", "k=-100:3000", "--seed", "7", "--all-roots", "--out", "s.parquet",
                  cwd=tmp_path)
    assert out.returncode == 0 and out.stderr == "", out.stderr
    lib = load("slider_crank")
    rows = sw.sweep(lib, sw.sample(lib, 300, {"T": (0, 12), "k": (-100, 3000)}, seed=7),
                    roots="all")
    _assert_file_holds(tmp_path / "s.parquet", rows)
    failed = len(set(rows["set"][rows["status"] != 0]))
    assert failed > 0 and f"{failed} sets failed (" in " ".join(out.stdout.split())


@pytest.mark.parametrize("args, message", [
    (("--vary", "F=0:200", "--out", "x.csv"), "F=0:200: a grid axis is NAME=START:STOP:COUNT"),
    (("--vary", "F=0:200:1.5", "--out", "x.csv"), "COUNT must be a positive integer"),
    (("--vary", "F=0:x:3", "--out", "x.csv"), "F: 'x' is not a number"),
    (("--sample", "5", "--vary", "F=0:200:3", "--out", "x.csv"), "with --sample, a range is"),
    (("--vary", "F", "--out", "x.csv"), "expected NAME=VALUE"),
    (("--vary", "Q=0:1:2", "--out", "x.csv"), "unknown parameter"),
    (("--vary", "F=0:1:2", "--set", "F=3", "--out", "x.csv"), "F: given more than once"),
    (("--vary", "F=0:1:2", "--seed", "3", "--out", "x.csv"), "--seed is for --sample"),
    (("--vary", "F=0:1:2", "--out", "x.txt"), r"must end in \.csv or \.parquet"),
    (("--vary", "F=0:1:2", "--workers", "0", "--out", "x.csv"), "expected a positive integer"),
    (("--vary", "F=0:1:2",), "required: --out"),
])
def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, args, message):
    out = mechvib(*args, cwd=tmp_path)
    assert out.returncode == 2 and out.stdout == "", out.stdout
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and re.search(message, lines[0]), out.stderr
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- Dask

def test_dask_array_without_a_cluster_runs_locally():
    da = pytest.importorskip("dask.array")
    distributed = pytest.importorskip("distributed")

    with pytest.raises(ValueError):
        distributed.default_client()   # no client of this process: the local path
    lib = load("doughty")
    table = _sets(lib, 90, 1)
    assert (sw.sweep(lib, da.from_array(table, chunks=40)).tobytes()
            == sw.sweep(lib, table).tobytes())


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            yield client


def test_dask_cluster_gives_the_local_bytes(client):
    """Worker processes load the library again from its origin; the rows are the same."""
    da = pytest.importorskip("dask.array")

    lib = load("slider_crank")
    table = _sets(lib, 400, 13, "T")
    local = sw.sweep(lib, table, roots="all")
    calls = []
    remote = sw.sweep(lib, table, roots="all", client=client, chunk=64,
                      progress=lambda d, n: calls.append(d))
    assert remote.tobytes() == local.tobytes()
    assert calls[0] == 0 and calls[-1] == 400 and calls == sorted(calls) and len(calls) == 8
    records = da.from_array(table, chunks=150)   # a dask array: its blocks, on the client
    assert sw.sweep(lib, records, roots="all").tobytes() == local.tobytes()


def test_cli_scheduler_runs_on_the_cluster(client, tmp_path):
    address = client.scheduler_info()["address"]
    out = mechvib("--vary", "F=0:200:21", "--out", "d.parquet", "--scheduler", address,
                  "--chunk", "5", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert f"on the Dask cluster at {address}" in " ".join(out.stdout.split())
    lib = load("doughty")
    _assert_file_holds(tmp_path / "d.parquet",
                       sw.sweep(lib, sw.grid(lib, {"F": np.linspace(0, 200, 21)})))


def test_a_worker_lost_mid_sweep_is_replaced_and_every_row_arrives(client):
    """Issue 27: chunks travel inside their tasks, so the scheduler runs a lost worker's
    again elsewhere (scattered chunks died with their worker: FutureCancelledError)."""
    lib = load("doughty")
    table = _sets(lib, 6000, 29)
    local = sw.sweep(lib, table)
    pieces = sw.stream(lib, table, client=client, chunk=100)
    first = next(pieces)
    busy = [w for w, tasks in client.processing().items() if tasks]
    victim = busy[0] if busy else next(iter(client.scheduler_info()["workers"]))
    try:
        client.run(lambda: os._exit(1), workers=[victim])
    except Exception:  # the worker died answering: expected
        pass
    rest = list(pieces)
    assert np.concatenate([first, *rest]).tobytes() == local.tobytes()


def test_cli_scheduler_without_workers_is_one_line(tmp_path):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=0, dashboard_address=":0") as empty:
        out = mechvib("--vary", "F=0:200:21", "--out", "d.csv", "--scheduler",
                      empty.scheduler_address, cwd=tmp_path,
                      env_extra={"MECHVIB_WORKER_WAIT": "2"})
    assert out.returncode == 2 and "no worker joined the scheduler" in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and list(tmp_path.iterdir()) == []


def _deserted_cluster(distributed):
    """A cluster, and its client, whose only worker has been closed."""
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                       dashboard_address=None)
    client = distributed.Client(cluster)
    client.wait_for_workers(1, timeout=30)
    cluster.scale(0)
    deadline = time.monotonic() + 30
    while client.nthreads() and time.monotonic() < deadline:
        time.sleep(0.05)
    return cluster, client


def test_a_sweep_on_a_cluster_without_workers_fails_in_one_line(monkeypatch):
    """Issue 48: its tasks would wait forever; after MECHVIB_WORKER_WAIT seconds without any
    worker, the sweep stops with an error that says so."""
    distributed = pytest.importorskip("distributed")
    monkeypatch.setenv("MECHVIB_WORKER_WAIT", "1")
    lib = load("doughty")
    cluster, client = _deserted_cluster(distributed)
    errors = []

    def run():
        try:
            list(sw.stream(lib, _sets(lib, 600, 3), client=client, chunk=100))
        except Exception as error:
            errors.append(error)
    thread = threading.Thread(target=run, daemon=True)
    with cluster, client:
        thread.start()
        thread.join(60)
        assert not thread.is_alive(), "the sweep still waits for a worker after 60 s"
    (error,) = errors
    assert isinstance(error, TimeoutError) and "no worker is left" in str(error)
    assert "\n" not in str(error)


def test_cli_sweep_whose_workers_all_leave_is_one_line(tmp_path):
    """The workers closed mid-sweep: one line naming that no worker is left, no file."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  protocol="tcp", dashboard_address=None) as cluster:
        run = subprocess.Popen(
            [sys.executable, "-m", "codegen", "sweep", "--vary", "F=0:200:200001",
             "--out", "d.csv", "--chunk", "100", "--scheduler", cluster.scheduler_address],
            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            env={**os.environ, "PYTHONPATH": str(REPO), "MECHVIB_WORKER_WAIT": "2"})
        deadline = time.monotonic() + 60
        while not cluster.scheduler.tasks and time.monotonic() < deadline:
            time.sleep(0.05)
        cluster.scale(0)
        try:
            out, err = run.communicate(timeout=60)
        finally:
            run.kill()
    assert run.returncode == 2 and out == "", (out, err)
    assert len(err.strip().splitlines()) == 1 and "no worker is left" in err, err
    assert list(tmp_path.iterdir()) == []
