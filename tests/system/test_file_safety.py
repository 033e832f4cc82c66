"""Nothing of the user's is lost (issue 27): generate removes only files it wrote, model names
cannot reach outside --out, cache entries are checked before they are trusted, every file is
written whole or not at all, and a check of one mechanism checks that one only.

The destructive cases run in a temporary folder with sentinel files that must survive.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from codegen import files
from codegen.compiler import generate
from codegen.api import load

REPO = Path(__file__).resolve().parents[2]


def codegen(cwd: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": str(REPO)})


def test_generate_keeps_files_it_did_not_write(tmp_path):
    out = tmp_path / "gen"
    for folder in ("runtime", "doughty"):
        (out / folder).mkdir(parents=True)
        (out / folder / "notes.txt").write_text("mine")
    (out / "doughty" / "old_mine.c").write_text("int x;")
    done = codegen(tmp_path, "generate", "--mechanism", "doughty", "--out", str(out))
    assert done.returncode == 0, done.stderr
    assert (out / "doughty" / "doughty.h").is_file()
    for sentinel in ("runtime/notes.txt", "doughty/notes.txt", "doughty/old_mine.c"):
        assert (out / sentinel).read_text() in ("mine", "int x;"), sentinel


def test_a_file_generate_wrote_and_no_longer_emits_is_removed(tmp_path):
    out = tmp_path / "lib"
    generate.write_folder(out, {"a.c": "1", "b.c": "2"})
    (out / "user.c").write_text("mine")
    assert generate.write_folder(out, {"a.c": "1"}) == []
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "a.c", "user.c"]


@pytest.mark.parametrize("name", ["", ".", "..", "../escape", "/tmp/absolute", "math-lib",
                                  "math", "stdint"])
def test_a_model_name_that_is_no_identifier_writes_nothing(tmp_path, name):
    model = (REPO / "tests" / "system" / "test_user_model.py").read_text()
    text = model.split("MODEL = '''\\\n", 1)[1].split("'''", 1)[0]
    (tmp_path / "mine.py").write_text(text.replace('name="spring_pendulum"', f"name={name!r}"))
    work = tmp_path / "work"
    (work / "out").mkdir(parents=True)
    (work / "sentinel").write_text("keep")
    (work / "out" / "sentinel").write_text("keep")
    done = codegen(work, "generate", "--model", str(tmp_path / "mine.py"), "--out", "out")
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert sorted(p.name for p in work.rglob("*")) == ["out", "sentinel", "sentinel"]


def test_a_damaged_cache_entry_is_rebuilt(tmp_path):
    cache = tmp_path / "cache"
    good = generate.emit_all(["torsion_pendulum"], cache=cache)["torsion_pendulum"]
    (entry,) = cache.glob("torsion_pendulum-*.json")
    entry.write_text(entry.read_text()[:100])                  # truncated
    assert generate.emit_all(["torsion_pendulum"], cache=cache)["torsion_pendulum"] == good
    stored = json.loads(entry.read_text())                      # valid JSON, wrong files
    stored["files"] = json.dumps({"torsion_pendulum.h": "wrong"})
    entry.write_text(json.dumps(stored))
    assert generate.emit_all(["torsion_pendulum"], cache=cache)["torsion_pendulum"] == good


def test_check_of_one_mechanism_ignores_the_others(tmp_path):
    out = tmp_path / "gen"
    assert codegen(tmp_path, "generate", "--out", str(out)).returncode == 0
    (out / "four_bar" / "four_bar.h").write_text("stale")
    one = codegen(tmp_path, "generate", "--check", "--mechanism", "doughty", "--out", str(out))
    assert one.returncode == 0, one.stdout[-2000:] + one.stderr
    every = codegen(tmp_path, "generate", "--check", "--out", str(out))
    assert every.returncode == 1 and "four_bar.h" in every.stdout


def test_an_error_while_writing_leaves_the_old_file(tmp_path):
    target = tmp_path / "t.json"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with files.replacing(target) as scratch:
            scratch.write_text("half")
            raise RuntimeError("disk full")
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["t.json"]


def test_a_full_disk_leaves_the_old_trajectory(tmp_path, monkeypatch):
    """A write that fails part way (ENOSPC from the stream) keeps the previous file whole."""
    lib = load("doughty")
    trajectory = lib.simulate(None, 2.8, 0.0, np.linspace(0.0, 0.05, 2001))
    target = tmp_path / "m.csv"
    target.write_text("t_s,theta_deg,thetadot_deg_s\n0,1,2\n")
    from codegen.runtime import simulation

    def full(stream, *args):
        stream.write("t_s,theta")
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(simulation, "write_csv", full)
    with pytest.raises(OSError):
        simulation.write(trajectory, target)
    assert target.read_text() == "t_s,theta_deg,thetadot_deg_s\n0,1,2\n"
    assert [p.name for p in tmp_path.iterdir()] == ["m.csv"]


@pytest.mark.parametrize("delay", [2.0, pytest.param(0.5, marks=pytest.mark.slow),
                                   pytest.param(3.5, marks=pytest.mark.slow)])
def test_a_sweep_killed_with_sigterm_leaves_the_old_file_or_the_new(tmp_path, delay):
    """Killed at some point of a ~5 s sweep: the old file as it was (and no partial file
    left), or, had it finished, the whole new one."""
    target = tmp_path / "s.csv"
    target.write_text("old\n")
    command = [sys.executable, "-m", "codegen", "sweep", "--vary", "F=0:200:40001",
               "--vary", "k=1000:3000:5", "--out", str(target), "--workers", "1"]
    process = subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               env={**os.environ, "PYTHONPATH": str(REPO)})
    time.sleep(delay)
    process.send_signal(signal.SIGTERM)
    out, err = process.communicate(timeout=120)
    if process.returncode == 0:
        rows = int(out.split("Wrote ")[1].split(" rows")[0].replace(",", ""))
        assert len(target.read_text().splitlines()) == rows + 1
    else:
        assert process.returncode == 128 + signal.SIGTERM, err
        assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["s.csv"]   # no partial file left


def _dead_pid() -> str:
    return subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()


def test_the_partial_file_of_a_killed_process_is_removed_by_the_next_write(tmp_path):
    target, ours = tmp_path / "s.csv", files.machine_id()
    orphan = tmp_path / f".s.csv.{_dead_pid()}.{ours}.abcd1234.partial"
    orphan.write_text("600 MB")
    live = tmp_path / f".s.csv.{os.getpid()}.{ours}.abcd1234.partial"  # a run still going
    live.write_text("busy")
    files.write_text(target, "new")
    assert not orphan.exists() and live.exists() and target.read_text() == "new"


def test_a_sweep_removes_neither_users_files_nor_another_machines_partial(tmp_path):
    """Issue 48: beside the target, only our own temporary files of a dead process of this
    machine go; a pid written by another container or host means nothing here."""
    from codegen.runtime import sweep

    lib = load("doughty")
    rows = sweep.sweep(lib, sweep.grid(lib, {"F": [1.0, 2.0]}))
    dead, ours = _dead_pid(), files.machine_id()
    other = "0123abcd" if ours != "0123abcd" else "fedc3210"
    kept = [f".s.csv.{dead}.notes", f".s.csv.2024.notes", f".s.csv.{dead}.x.partial",
            f".s.csv.{dead}.{other}.abcd1234.partial", f".s.csv.{dead}.{ours}.abcd1234.notes"]
    stale = f".s.csv.{dead}.{ours}.abcd1234.partial"
    for name in (*kept, stale):
        (tmp_path / name).write_text("mine")
    sweep.write(rows, tmp_path / "s.csv")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([*kept, "s.csv"])


def test_the_machine_id_names_this_boot_of_this_host():
    machine = files.machine_id()
    assert len(machine) == 8 and int(machine, 16) >= 0
    assert files.temporary(Path("/x/s.csv")).name.split(".")[4] == machine


def _pendulum(k: str) -> str:
    """The spring pendulum of docs/models.md with another example stiffness (the same name)."""
    model = (REPO / "tests" / "system" / "test_user_model.py").read_text()
    text = model.split("MODEL = '''\\\n", 1)[1].split("'''", 1)[0]
    return text.replace('parameter("k", "N/m", "spring stiffness", "20")',
                        f'parameter("k", "N/m", "spring stiffness", "{k}")')


def test_concurrent_analyses_of_two_models_of_one_name_into_one_folder(tmp_path):
    """Each run prints its own model's equilibria: the builds take turns in the folder."""
    for k in ("20", "5"):
        (tmp_path / f"k{k}.py").write_text(_pendulum(k))
    command = [sys.executable, "-m", "codegen", "analyze", "--json", "--out", "shared"]
    runs = [subprocess.Popen(command + ["--model", f"k{k}.py"], cwd=tmp_path,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONPATH": str(REPO)})
            for k in ("20", "5")]
    outputs = [run.communicate(timeout=600) for run in runs]
    assert all(run.returncode == 0 for run in runs), [err for _, err in outputs]
    ks = [json.loads(out)["params"]["k"] for out, _ in outputs]
    assert ks == [20.0, 5.0]
    counts = [sum(r["kind"] == "equilibrium" for r in json.loads(out)["roots"])
              for out, _ in outputs]
    assert counts == [4, 2]   # docs/models.md: k = 20 has four equilibria, k = 5 two


def test_concurrent_sweeps_to_one_file_each_write_a_whole_file(tmp_path):
    command = [sys.executable, "-m", "codegen", "sweep", "--vary", "k=1000:3000:5",
               "--out", "s.csv", "--workers", "1", "--vary"]
    runs = [subprocess.Popen(command + [axis], cwd=tmp_path, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONPATH": str(REPO)})
            for axis in ("F=0:200:20001", "F=0:100:10001")]
    outputs = [run.communicate(timeout=600) for run in runs]
    assert all(run.returncode == 0 for run in runs), [err for _, err in outputs]
    rows = [int(out.split("Wrote ")[1].split(" rows")[0].replace(",", "")) for out, _ in outputs]
    assert len((tmp_path / "s.csv").read_text().splitlines()) - 1 in rows
    assert [p.name for p in tmp_path.iterdir()] == ["s.csv"]


def _damage_truncated(library: Path) -> None:
    library.write_bytes(library.read_bytes()[:4096])


def _damage_garbled(library: Path) -> None:
    """The same size, its middle overwritten: only the hash tells."""
    data = bytearray(library.read_bytes())
    middle = len(data) // 2
    data[middle:middle + 4096] = b"\xff" * 4096
    library.write_bytes(bytes(data))


def test_a_damaged_cached_library_is_built_again(tmp_path):
    """A cache entry's compiled library truncated or overwritten after its build is built
    again on the next run, which prints the model's analysis, not a traceback."""
    (tmp_path / "mine.py").write_text(_pendulum("20"))
    env = {**os.environ, "PYTHONPATH": str(REPO), "XDG_CACHE_HOME": str(tmp_path / "cache")}

    def analyze() -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "codegen", "analyze", "--json", "--model",
                               "mine.py"], cwd=tmp_path, capture_output=True, text=True,
                              timeout=600, env=env)

    first = analyze()
    assert first.returncode == 0, first.stderr
    for damage in (_damage_truncated, _damage_garbled):
        (library,) = (tmp_path / "cache").glob("mechvib/*/_native_spring_pendulum.*")
        damage(library)
        again = analyze()
        assert again.returncode == 0 and "Traceback" not in again.stderr, again.stderr
        assert "building" in again.stderr, damage.__name__
        assert json.loads(again.stdout) == json.loads(first.stdout), damage.__name__


def test_a_model_build_compiles_only_the_files_generate_wrote(tmp_path):
    """C files of the user's in --out (one valid, defining a symbol, one not C at all) are
    left alone: neither compiled nor linked into the library."""
    (tmp_path / "mine.py").write_text(_pendulum("20"))
    users = {"runtime/extra.c": "int users_own_symbol_48 = 42;\n",
             "runtime/broken.c": "this is not C\n",
             "spring_pendulum/mine_too.c": "int users_other_symbol_48 = 7;\n"}
    for name, text in users.items():
        (tmp_path / "lib" / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / "lib" / name).write_text(text)
    done = codegen(tmp_path, "generate", "--model", "mine.py", "--out", "lib")
    assert done.returncode == 0, done.stderr
    (library,) = (tmp_path / "lib").glob("_native_spring_pendulum.*")
    assert b"users_own_symbol_48" not in library.read_bytes()
    assert b"users_other_symbol_48" not in library.read_bytes()
    assert all((tmp_path / "lib" / name).read_text() == text for name, text in users.items())
