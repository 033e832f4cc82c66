"""codegen.presentation: the runtime's results drawn, as docs/python.md shows it.

The runtime returns data (a Trajectory, a FrequencyResponse, a drawing's Geometry, of one
coordinate or several) and draws nothing; these functions take those results and draw them,
headless, to PNG or SVG, or give the matplotlib Figure. What each figure holds is read back
from its axes. Branches' figure is tested in test_branches.py, the command line's --plot in
test_simulate_cli.py, test_frequency_response.py and test_newcomer.py.
"""
from __future__ import annotations

import math
import os
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
    names, rates = trajectory.labels()
    labels = [line.get_label() for line in top.get_lines()]
    assert labels == [item for name in names for item in (name, f"{name}, linearised")]
    np.testing.assert_array_equal(top.get_lines()[0].get_ydata(), trajectory.theta_shown[:, 0])
    assert [line.get_label() for line in bottom.get_lines()][::2] == rates
    assert plot_trajectory(trajectory, tmp_path / "swing.svg").read_text().startswith("<?xml")


def test_the_frequency_response_marks_the_natural_frequency(tmp_path):
    r = load("doughty").frequency_response(equilibrium=5, points=201)
    top, bottom = _axes(response_figure(r))
    assert top.get_yscale() == "log" and bottom.get_xlabel() == "forcing frequency [Hz]"
    np.testing.assert_array_equal(top.get_lines()[0].get_ydata(), r.amplitude)
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
    np.testing.assert_allclose(curves[1].get_ydata(), np.abs(r.response[:, 1]))
    marked = sorted(line.get_xdata()[0] for line in top.get_lines() if line not in curves)
    np.testing.assert_allclose(marked, sorted(r.natural_frequencies))
    assert top.get_title().endswith(f"a harmonic force on {r.coordinates[1]}")
    assert plot_response(r, tmp_path / "frf.svg").read_text().startswith("<?xml")


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
