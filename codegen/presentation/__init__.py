"""Figures of the runtime's results: the layer above ``codegen.runtime`` that draws.

The runtime computes and returns data (``Branches``, ``Trajectory``, ``FrequencyResponse``,
a drawing's ``Geometry``, ...); the functions here take those results and draw them with
matplotlib (the ``plot`` extra: ``pip install 'mechvib[plot]'``), headless, to PNG or SVG.
matplotlib is imported only in ``figures``, and only when a figure is drawn; without it a
figure raises ``PlotUnavailable`` with the install command. Nothing below this layer imports
it (tests/system/test_import_graph.py).

Each ``plot_*`` writes a file (.png at 150 dpi, or .svg) and returns its path; each
``*_figure`` returns the matplotlib Figure instead, to change or show before saving:

- ``plot_branches(result, path)``: theta_E, omega_n and zeta against the parameter of a
  ``codegen.runtime.branches.Branches`` (``branches``);
- ``plot_trajectory(trajectory, path, linear=None)``: a ``simulate``'s motion, and its
  linearised response beside it, of one coordinate or several (``motion``);
- ``plot_response(response, path)``: a frequency response's amplitude and phase, the
  natural frequencies marked (``response``);
- ``draw_mechanism(geometry, path)``: the mechanism at one angle, from
  ``codegen.runtime.drawing.geometry`` (``drawing``).
"""
from __future__ import annotations

from .branches import figure as branches_figure
from .branches import plot as plot_branches
from .drawing import draw as draw_mechanism
from .drawing import figure as mechanism_figure
from .figures import PlotUnavailable
from .motion import figure as trajectory_figure
from .motion import plot as plot_trajectory
from .response import figure as response_figure
from .response import plot as plot_response

__all__ = ["PlotUnavailable", "branches_figure", "draw_mechanism", "mechanism_figure",
           "plot_branches", "plot_response", "plot_trajectory", "response_figure",
           "trajectory_figure"]
