"""The figure of a frequency response: a ``FrequencyResponse`` (``codegen.runtime.response``)
or a ``MultibodyFrequencyResponse`` (``codegen.runtime.multibody_response``).

``figure(response)`` draws the amplitude (logarithmic; a panel per unit, angles in degrees)
above the phase against the forcing frequency [Hz], the natural frequencies marked, and
gives the matplotlib Figure;
``plot(response, path)`` writes it to .png or .svg. Both read the results as data;
matplotlib comes through ``figures``.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from . import figures
from ..runtime.multibody_response import MultibodyFrequencyResponse
from ..runtime.response import FrequencyResponse


def figure(response: FrequencyResponse | MultibodyFrequencyResponse) -> Any:
    """|H| [deg/(N m)] (logarithmic) above the phase [deg] against the forcing frequency
    [Hz], the natural frequency marked; with several coordinates each coordinate's under a
    unit generalised force on the driven one, a panel of |H| per unit (deg or m, per N m on
    an angle or N on a length), every natural frequency marked. A matplotlib Figure; raises
    figures.PlotUnavailable without matplotlib."""
    if isinstance(response, MultibodyFrequencyResponse):
        return _several_coordinates(response)
    plt = figures.pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      constrained_layout=True)
    f = response.frequency
    e = response.equilibrium
    top.semilogy(f, np.degrees(response.amplitude), color="C0")   # angles in degrees
    bottom.plot(f, np.degrees(response.phase), color="C0")
    for axes in (top, bottom):
        axes.axvline(response.natural_frequency, color="C3", linestyle="--", linewidth=1,
                     label=rf"$f_n$ = {response.natural_frequency:.4g} Hz")
        axes.grid(True, which="both", alpha=0.3)
    top.set_ylabel("|H| [deg/(N m)]")
    bottom.set_ylabel("phase [deg]")
    bottom.set_xlabel("forcing frequency [Hz]")
    top.set_title(rf"{response.library.TITLE}: about $\theta_E$ = {math.degrees(e.theta):.4f} deg "
                  rf"($\zeta$ = {e.zeta.real:.3g})", fontsize=10)
    top.legend(loc="best", fontsize=8)
    return fig


def _several_coordinates(response: MultibodyFrequencyResponse) -> Any:
    """A panel per unit of the coordinates of each coordinate's amplitude (logarithmic;
    angles in deg, lengths in m, per unit of the driving force: N m on an angle, N on a
    length), above their phases, the natural frequencies marked."""
    plt = figures.pyplot()
    coordinates = response.library.SPEC["coordinates"]
    groups = figures.by_unit(coordinates)
    load = figures.load_unit(coordinates[response.drive]["unit"])
    fig, panels = plt.subplots(len(groups) + 1, 1, sharex=True, squeeze=False,
                               figsize=(7.5, 1.0 + 2.25 * (len(groups) + 1)),
                               constrained_layout=True)
    panels = panels[:, 0]
    bottom = panels[-1]
    for axes, (unit, members) in zip(panels, groups):
        for i in members:
            H = response.response[:, i]
            name, color = coordinates[i]["name"], f"C{i % 10}"
            axes.semilogy(response.frequency, figures.shown_values(np.abs(H), unit),
                          color=color, label=name)
            bottom.plot(response.frequency, np.degrees(np.angle(H)), color=color, label=name)
        axes.set_ylabel(f"|H| [{figures.per(figures.shown_unit(unit), load)}]")
    for j, f in enumerate(response.natural_frequencies):
        for axes in panels:
            axes.axvline(f, color="0.4", linestyle="--", linewidth=1,
                         label=rf"$f_{j + 1}$ = {f:.4g} Hz" if axes is panels[0] else None)
    for axes in panels:
        axes.grid(True, which="both", alpha=0.3)
        axes.legend(loc="best", fontsize=8)
    bottom.set_ylabel("phase [deg]")
    bottom.set_xlabel("forcing frequency [Hz]")
    panels[0].set_title(f"{response.library.TITLE}: a harmonic "
                        f"{'torque' if load == 'N m' else 'force'} [{load}] on "
                        f"{response.coordinates[response.drive]}", fontsize=10)
    return fig


def plot(response: FrequencyResponse | MultibodyFrequencyResponse, path: str | Path) -> Path:
    """``figure`` written to ``path`` (.png or .svg); the path. Raises ValueError for another
    extension, figures.PlotUnavailable without matplotlib."""
    path = figures.check_path(path)
    return figures.save(figure(response), path)
