"""The figure of a frequency response: a ``FrequencyResponse`` (``codegen.runtime.response``)
or a ``MultibodyFrequencyResponse`` (``codegen.runtime.multibody_response``).

``figure(response)`` draws the amplitude (logarithmic) above the phase against the forcing
frequency [Hz], the natural frequencies marked, and gives the matplotlib Figure;
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
    """|H| (logarithmic) above the phase [deg] against the forcing frequency [Hz], the
    natural frequency marked; with several coordinates each coordinate's, under a unit force
    on the driven one, every natural frequency marked. A matplotlib Figure; raises
    figures.PlotUnavailable without matplotlib."""
    if isinstance(response, MultibodyFrequencyResponse):
        return _several_coordinates(response)
    plt = figures.pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      constrained_layout=True)
    f = response.frequency
    e = response.equilibrium
    top.semilogy(f, response.amplitude, color="C0")
    bottom.plot(f, np.degrees(response.phase), color="C0")
    for axes in (top, bottom):
        axes.axvline(response.natural_frequency, color="C3", linestyle="--", linewidth=1,
                     label=rf"$f_n$ = {response.natural_frequency:.4g} Hz")
        axes.grid(True, which="both", alpha=0.3)
    top.set_ylabel("|H| [rad/(N m)]")
    bottom.set_ylabel("phase [deg]")
    bottom.set_xlabel("forcing frequency [Hz]")
    top.set_title(rf"{response.library.TITLE}: about $\theta_E$ = {math.degrees(e.theta):.4f} deg "
                  rf"($\zeta$ = {e.zeta.real:.3g})", fontsize=10)
    top.legend(loc="best", fontsize=8)
    return fig


def _several_coordinates(response: MultibodyFrequencyResponse) -> Any:
    """Each coordinate's amplitude (logarithmic) above its phase, the natural frequencies
    marked."""
    plt = figures.pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      constrained_layout=True)
    for i, name in enumerate(response.coordinates):
        top.semilogy(response.frequency, np.abs(response.response[:, i]), label=name)
        bottom.plot(response.frequency, np.degrees(np.angle(response.response[:, i])))
    for j, f in enumerate(response.natural_frequencies):
        for axes in (top, bottom):
            axes.axvline(f, color="C3", linestyle="--", linewidth=1,
                         label=rf"$f_{j + 1}$ = {f:.4g} Hz" if axes is top else None)
    for axes in (top, bottom):
        axes.grid(True, which="both", alpha=0.3)
    top.set_ylabel("|H| per unit force")
    bottom.set_ylabel("phase [deg]")
    bottom.set_xlabel("forcing frequency [Hz]")
    top.set_title(f"{response.library.TITLE}: a harmonic force on "
                  f"{response.coordinates[response.drive]}", fontsize=10)
    top.legend(loc="best", fontsize=8)
    return fig


def plot(response: FrequencyResponse | MultibodyFrequencyResponse, path: str | Path) -> Path:
    """``figure`` written to ``path`` (.png or .svg); the path. Raises ValueError for another
    extension, figures.PlotUnavailable without matplotlib."""
    path = figures.check_path(path)
    return figures.save(figure(response), path)
