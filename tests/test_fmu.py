"""`mechvib fmu`: each shipped mechanism with one coordinate as an FMI 2.0 FMU, checked with
fmpy (validation, Model Exchange and Co-Simulation against `mechvib simulate`'s integration,
inputs, parameters, its own sources rebuilt, errors in the log)."""
from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from codegen.api import load
from codegen.fmu import FmuError, write_fmu

fmpy = pytest.importorskip("fmpy")
from fmpy import simulate_fmu  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

ONE_COORDINATE = ("doughty", "four_bar", "slider_crank", "torsion_pendulum")
TIMES = np.linspace(0.0, 0.5, 11)


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fmus")
    return {name: write_fmu(load(name), folder / f"{name}.fmu") for name in ONE_COORDINATE}


def _run(path, kind, start_values, **options):
    result = simulate_fmu(str(path), fmi_type=kind, stop_time=TIMES[-1],
                          output_interval=TIMES[1], start_values=start_values,
                          output=["theta", "theta_d"], **options)
    assert np.allclose(result["time"], TIMES)
    return result


@pytest.mark.parametrize("name", ONE_COORDINATE)
def test_each_fmu_passes_fmpys_validation(fmus, name):
    assert validate_fmu(str(fmus[name])) == []
    with zipfile.ZipFile(fmus[name]) as archive:
        names = archive.namelist()
    assert f"binaries/linux64/{name}.so" in names and f"sources/{name}_fmi2.c" in names
    assert "sources/codegen_fmi2.c" in names and "modelDescription.xml" in names


@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
@pytest.mark.parametrize("name", ONE_COORDINATE)
def test_the_fmu_moves_as_mechvib_simulate(fmus, name, kind):
    lib = load(name)
    e = next(e for e in lib.analyze().equilibria if e.K > 0)
    theta0 = e.theta + 0.3
    result = _run(fmus[name], kind, {"theta": theta0}, relative_tolerance=1e-12)
    expected = lib.simulate(None, theta0, 0.0, TIMES, rtol=1e-12, atol=1e-15)
    assert np.allclose(result["theta"], expected.theta, rtol=1e-8, atol=1e-9)
    assert np.allclose(result["theta_d"], expected.theta_d, rtol=1e-8, atol=1e-8)


def test_parameters_and_the_input_load_act_as_set_would(fmus):
    """A parameter set through FMI, and the load's input added to its parameter: the
    response of `--set`."""
    lib = load("doughty")
    changed = {"k": 2500.0, "F": 0.0, "F_input": 40.0}
    result = _run(fmus["doughty"], "CoSimulation", {"theta": 0.3, **changed},
                  relative_tolerance=1e-12)
    expected = lib.simulate({**lib.EXAMPLE, "k": 2500.0, "F": 40.0}, 0.3, 0.0, TIMES,
                            rtol=1e-12, atol=1e-15)
    assert np.allclose(result["theta"], expected.theta, rtol=1e-8, atol=1e-9)
    unloaded = _run(fmus["doughty"], "CoSimulation", {"theta": 0.3, "k": 2500.0, "F": 0.0},
                    relative_tolerance=1e-12)
    assert np.abs(unloaded["theta"] - result["theta"]).max() > 1e-3


def test_the_outputs_are_the_librarys_points_and_energies(fmus):
    lib = load("four_bar")
    result = simulate_fmu(str(fmus["four_bar"]), fmi_type="ModelExchange", stop_time=0.2,
                          output_interval=0.1, start_values={"theta": 0.4},
                          output=["theta", "theta_d", "A.x", "B.y", "kinetic_energy",
                                  "potential_energy"])
    for row in result:
        coords, rates = lib.dependent_state(lib.EXAMPLE, row["theta"], row["theta_d"])
        positions, _ = lib.point_kinematics(lib.EXAMPLE, coords, rates)
        T, V_G, V_E, _ = lib.energies(lib.EXAMPLE, coords, rates)
        assert row["A.x"] == pytest.approx(positions[0], rel=1e-12)
        assert row["B.y"] == pytest.approx(positions[3], rel=1e-12)
        assert row["kinetic_energy"] == pytest.approx(T, rel=1e-12, abs=1e-15)
        assert row["potential_energy"] == pytest.approx(V_G + V_E, rel=1e-12)


def test_a_bad_parameter_is_an_fmi_error_with_the_reason_in_the_log(fmus):
    messages = []

    def logger(environment, instance, status, category, message):
        messages.append(message.decode())

    with pytest.raises(Exception, match="fmi2ExitInitializationMode"):
        simulate_fmu(str(fmus["doughty"]), fmi_type="CoSimulation", stop_time=0.1,
                     start_values={"L": -1.0}, logger=logger)
    assert any("the parameters:" in m and "L" in m for m in messages), messages


def test_the_fmu_rebuilt_from_its_sources_gives_the_same_motion(fmus, tmp_path):
    """fmpy's CMake build of the FMU's sources (its binary removed first) moves as the
    binary inside it."""
    from fmpy.build import build_platform_binary

    folder = tmp_path / "doughty"
    with zipfile.ZipFile(fmus["doughty"]) as archive:
        archive.extractall(folder)
    shutil.rmtree(folder / "binaries")
    build_platform_binary(folder)
    assert (folder / "binaries" / "linux64" / "doughty.so").is_file()
    start = {"theta": 2.8}
    rebuilt = _run(folder, "CoSimulation", start)
    original = _run(fmus["doughty"], "CoSimulation", start)
    assert np.allclose(rebuilt["theta"], original["theta"], rtol=1e-12, atol=1e-12)


def test_the_same_model_gives_the_same_fmu_byte_for_byte(fmus, tmp_path):
    again = write_fmu(load("doughty"), tmp_path / "doughty.fmu")
    assert again.read_bytes() == fmus["doughty"].read_bytes()


def test_the_command_line_writes_an_fmu_and_refuses_what_it_cannot(tmp_path):
    run = [sys.executable, "-m", "codegen", "fmu"]
    out = subprocess.run(run + ["--mechanism", "slider_crank", "--equilibrium", "0", "--out",
                                str(tmp_path / "s.fmu")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "Wrote" in out.stdout and validate_fmu(str(tmp_path / "s.fmu")) == []
    for extra, message in ((["--out", str(tmp_path / "s.zip")], "name ends in .fmu"),
                           (["--mechanism", "double_pendulum", "--out", str(tmp_path / "d.fmu")],
                            "2 coordinates"),
                           (["--equilibrium", "99", "--out", str(tmp_path / "e.fmu")],
                            "--equilibrium 99")):
        out = subprocess.run(run + extra, capture_output=True, text=True)
        assert out.returncode != 0 and message in out.stderr and "Traceback" not in out.stderr


def test_a_mechanism_with_several_coordinates_is_refused_in_python(tmp_path):
    with pytest.raises(FmuError, match="2 coordinates"):
        write_fmu(load("double_pendulum"), Path(tmp_path) / "d.fmu")
