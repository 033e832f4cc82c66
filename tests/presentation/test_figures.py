"""codegen.presentation: the runtime's results drawn, as docs/python.md shows it.

The runtime returns data (a Trajectory, a FrequencyResponse, a drawing's Geometry, of one
coordinate or several) and draws nothing; these functions take those results and draw them,
headless, to PNG or SVG, or give the matplotlib Figure. What each figure holds is read back
from its axes. Branches' figure is tested in test_branches.py, the command line's --plot in
test_simulate_command.py, test_frequency_response.py and test_discoverability.py.
"""
from __future__ import annotations

import dataclasses
import math
import os
import re
import sys

import numpy as np
import pytest

from codegen.api import load
from codegen.presentation import (PlotUnavailable, draw_mechanism, figures, mechanism_figure,
                                  plot_response, plot_trajectory, response_figure,
                                  trajectory_figure)
from codegen.runtime import multibody_motion, simulation
from codegen.runtime.drawing import geometry


@pytest.fixture(autouse=True)
def matplotlib_there():
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        if os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no"):
            pytest.fail("matplotlib is needed (CI is set)")
        pytest.skip("matplotlib is not installed")


def _axes(figure):
    axes = figure.axes
    figures.pyplot().close(figure)
    return axes


@pytest.fixture(scope="module")
def doughty_motion():
    lib = load("doughty")
    trajectory = lib.simulate(None, np.radians(160), 0.0, np.linspace(0, 2, 201))
    return trajectory, simulation.linearised(trajectory)


@pytest.fixture(scope="module")
def pendulum_motion():
    lib = load("double_pendulum")
    trajectory = lib.simulate(None, [1.2, 0.3], [0.0, 0.0], np.linspace(0, 2, 81))
    return trajectory, multibody_motion.linearised(trajectory)


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG"), (".svg", b"<?xml")])
def test_a_trajectory_and_its_linearisation_are_written_headless(doughty_motion, tmp_path,
                                                                   suffix, magic):
    trajectory, linear = doughty_motion
    path = plot_trajectory(trajectory, tmp_path / f"theta{suffix}", linear)
    assert path == tmp_path / f"theta{suffix}"
    assert path.read_bytes().startswith(magic) and path.stat().st_size > 10_000


def test_the_trajectory_figure_holds_the_motion_in_degrees(doughty_motion):
    trajectory, linear = doughty_motion
    top, bottom = _axes(trajectory_figure(trajectory, linear))
    assert top.get_ylabel() == r"$\theta$ [deg]" and bottom.get_xlabel() == "t [s]"
    nonlinear, linearised = top.get_lines()[:2]
    np.testing.assert_array_equal(nonlinear.get_ydata(), np.degrees(trajectory.theta))
    np.testing.assert_array_equal(linearised.get_ydata(), np.degrees(linear.theta))
    assert linearised.get_linestyle() == "--"
    equilibrium = [t.get_text() for t in top.get_legend().get_texts()]
    assert equilibrium[1].startswith(r"linearised about $\theta_E$ = 176.72 deg")
    without = _axes(trajectory_figure(trajectory))[0]
    assert len(without.get_lines()) == 1


def test_several_coordinates_are_drawn_each_with_its_linearisation(pendulum_motion, tmp_path):
    trajectory, linear = pendulum_motion
    top, bottom = _axes(trajectory_figure(trajectory, linear))
    names = trajectory.coordinates
    labels = [line.get_label() for line in top.get_lines()]
    assert labels == [item for name in names for item in (name, f"{name}, linearised")]
    np.testing.assert_array_equal(top.get_lines()[0].get_ydata(), trajectory.theta_shown[:, 0])
    assert [line.get_label() for line in bottom.get_lines()][::2] == [f"{n}dot" for n in names]
    assert plot_trajectory(trajectory, tmp_path / "swing.svg").read_text().startswith("<?xml")


class _WithALength:
    """flexible_doughty's library with its second coordinate read as a length s [m]: no
    shipped mechanism has an angle and a length as its independent coordinates, and the
    figures take each coordinate's unit from the library's SPEC, its values from the data."""

    def __init__(self, library):
        self._library = library
        coordinates = [dict(c) for c in library.SPEC["coordinates"]]
        coordinates[1].update(name="s", unit="m", description="a length")
        self.SPEC = {**library.SPEC, "coordinates": coordinates}

    def __getattr__(self, name):
        return getattr(self._library, name)


#: The mechanisms whose figures are read back: two angles, and an angle with a length.
SEVERAL = ("double_pendulum", "flexible_doughty", "angle_and_length")


def _library(name):
    return _WithALength(load("flexible_doughty")) if name == "angle_and_length" else load(name)


def _unit(axes) -> str:
    """The unit of an axis' ylabel: the one text in [...]."""
    units = re.findall(r"\[([^\]]*)\]", axes.get_ylabel())
    assert len(units) == 1, axes.get_ylabel()
    return units[0]


def _shown(values, unit):
    return np.degrees(values) if unit == "rad" else values


@pytest.mark.parametrize("name", SEVERAL)
def test_a_motion_has_a_panel_per_unit_of_its_coordinates_and_of_their_rates(name):
    """Coordinates of one unit share a panel, whose ylabel carries that unit (angles in deg,
    lengths in m), then their rates likewise; each line holds its coordinate's values so
    converted, the linearised response's too."""
    lib = _library(name)
    theta0 = {"double_pendulum": [1.2, 0.3]}.get(name, [-0.1, 0.05])
    real = load("flexible_doughty") if name == "angle_and_length" else lib
    trajectory = real.simulate(None, theta0, [0.0, 0.0], np.linspace(0, 0.5, 41))
    linear = multibody_motion.linearised(trajectory)
    if name == "angle_and_length":
        trajectory = dataclasses.replace(trajectory, library=lib)
        linear = dataclasses.replace(linear, library=lib)
    coordinates = lib.SPEC["coordinates"]
    units = list(dict.fromkeys(c["unit"] for c in coordinates))
    shown = ["deg" if u == "rad" else u for u in units]
    panels = _axes(trajectory_figure(trajectory, linear))
    assert [_unit(axes) for axes in panels] == shown + [f"{u}/s" for u in shown]
    assert panels[-1].get_xlabel() == "t [s]"
    for axes, unit, rates in zip(panels, units * 2, [False] * len(units) + [True] * len(units)):
        members = [i for i, c in enumerate(coordinates) if c["unit"] == unit]
        suffix = "dot" if rates else ""
        expected = [item for i in members for item in
                    (coordinates[i]["name"] + suffix,
                     f"{coordinates[i]['name']}{suffix}, linearised")]
        lines = axes.get_lines()
        assert [line.get_label() for line in lines] == expected
        for k, i in enumerate(members):
            data, lin = ((trajectory.theta_d, linear.theta_d) if rates
                         else (trajectory.theta, linear.theta))
            np.testing.assert_allclose(lines[2 * k].get_ydata(), _shown(data[:, i], unit),
                                       rtol=1e-15)
            np.testing.assert_allclose(lines[2 * k + 1].get_ydata(), _shown(lin[:, i], unit),
                                       rtol=1e-15)


def test_the_frequency_response_marks_the_natural_frequency(tmp_path):
    r = load("doughty").frequency_response(equilibrium=5, points=201)
    top, bottom = _axes(response_figure(r))
    assert top.get_yscale() == "log" and bottom.get_xlabel() == "forcing frequency [Hz]"
    assert top.get_ylabel() == "|H| [deg/(N m)]" and bottom.get_ylabel() == "phase [deg]"
    np.testing.assert_allclose(top.get_lines()[0].get_ydata(), np.degrees(r.amplitude),
                               rtol=1e-15)
    np.testing.assert_allclose(bottom.get_lines()[0].get_ydata(), np.degrees(r.phase))
    marked = [line.get_xdata()[0] for line in top.get_lines()[1:]]
    assert marked == [r.natural_frequency]
    path = plot_response(r, tmp_path / "frf.png")
    assert path.read_bytes()[:4] == b"\x89PNG"


def test_a_response_of_several_coordinates_marks_every_natural_frequency(tmp_path):
    lib = load("double_pendulum")
    from codegen.runtime.multibody_response import frequency_response

    r = frequency_response(lib, lib.example_params(), drive=1, points=101)
    top, _ = _axes(response_figure(r))
    curves = [line for line in top.get_lines() if line.get_label() in r.coordinates]
    assert [c.get_label() for c in curves] == r.coordinates
    np.testing.assert_allclose(curves[1].get_ydata(), np.degrees(np.abs(r.response[:, 1])))
    marked = sorted(line.get_xdata()[0] for line in top.get_lines() if line not in curves)
    np.testing.assert_allclose(marked, sorted(r.natural_frequencies))
    assert top.get_title().endswith(f"a harmonic torque [N m] on {r.coordinates[1]}")
    assert plot_response(r, tmp_path / "frf.svg").read_text().startswith("<?xml")


@pytest.mark.parametrize("drive", [0, 1])
@pytest.mark.parametrize("name", SEVERAL)
def test_a_response_has_an_amplitude_panel_per_unit_of_its_coordinates(name, drive):
    """H_ij's unit is coordinate i's per the load on j (N m on an angle, N on a length): a
    panel of |H| per unit of the coordinates, its ylabel that unit per the load, its lines
    those coordinates' |H| (angles in deg); the phase [deg] of every coordinate below; every
    natural frequency marked on each."""
    from codegen.runtime.multibody_response import frequency_response

    lib = _library(name)
    real = load("flexible_doughty") if name == "angle_and_length" else lib
    r = frequency_response(real, real.example_params(), drive=drive, points=101)
    if name == "angle_and_length":
        r = dataclasses.replace(r, library=lib)
    coordinates = lib.SPEC["coordinates"]
    units = list(dict.fromkeys(c["unit"] for c in coordinates))
    load_unit = {"rad": "(N m)", "m": "N"}[coordinates[drive]["unit"]]
    panels = _axes(response_figure(r))
    *amplitudes, phase = panels
    assert [_unit(axes) for axes in amplitudes] == [
        f"{'deg' if u == 'rad' else u}/{load_unit}" for u in units]
    assert _unit(phase) == "deg" and phase.get_xlabel() == "forcing frequency [Hz]"
    names = [c["name"] for c in coordinates]
    for axes, unit in zip(amplitudes, units):
        assert axes.get_yscale() == "log"
        members = [i for i, c in enumerate(coordinates) if c["unit"] == unit]
        curves = [line for line in axes.get_lines() if line.get_label() in names]
        assert [line.get_label() for line in curves] == [names[i] for i in members]
        for line, i in zip(curves, members):
            np.testing.assert_allclose(line.get_ydata(),
                                       _shown(np.abs(r.H[:, i, drive]), unit), rtol=1e-15)
    curves = [line for line in phase.get_lines() if line.get_label() in names]
    assert [line.get_label() for line in curves] == names
    for line, i in zip(curves, range(len(names))):
        np.testing.assert_allclose(line.get_ydata(), np.degrees(np.angle(r.H[:, i, drive])),
                                   rtol=1e-15)
    for axes in panels:
        marked = sorted(line.get_xdata()[0] for line in axes.get_lines()
                        if line.get_label() not in names)
        np.testing.assert_allclose(marked, sorted(r.natural_frequencies))
    torque = coordinates[drive]["unit"] == "rad"
    assert amplitudes[0].get_title().endswith(
        f"a harmonic {'torque [N m]' if torque else 'force [N]'} on {names[drive]}")


def test_a_mechanism_is_drawn_from_its_geometry(tmp_path):
    pytest.importorskip("sympy")
    from codegen.compiler.model import load as load_model

    lib = load("doughty")
    g = geometry(load_model("doughty"), lib, lib.example_params(), math.radians(30))
    ax, = _axes(mechanism_figure(g))
    names = {text.get_text() for text in ax.texts}
    assert set(g.points) <= names and "θ" in names
    assert ax.get_title().endswith("θ = 30°") and ax.get_aspect() == 1
    path = draw_mechanism(g, tmp_path / "doughty.svg")
    assert path.read_text().lstrip().startswith("<?xml")


def test_a_path_of_another_type_fails_before_drawing(doughty_motion, tmp_path):
    trajectory, _ = doughty_motion
    with pytest.raises(ValueError, match="a figure is written as .png or .svg"):
        plot_trajectory(trajectory, tmp_path / "theta.pdf")
    assert not any(tmp_path.iterdir())


def test_without_matplotlib_a_figure_says_how_to_install_it(doughty_motion, monkeypatch,
                                                             tmp_path):
    trajectory, _ = doughty_motion
    monkeypatch.setitem(sys.modules, "matplotlib", None)   # `import matplotlib` now fails
    with pytest.raises(PlotUnavailable, match=r"pip install 'mechvib\[plot\]'"):
        plot_trajectory(trajectory, tmp_path / "theta.png")
    assert not any(tmp_path.iterdir())
