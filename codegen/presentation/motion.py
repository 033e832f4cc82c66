"""The figure of a time response: a ``Trajectory`` (``codegen.runtime.simulation``) or a
``MultibodyTrajectory`` (``codegen.runtime.multibody_motion``), with the linearised response
beside it when given.

``figure(trajectory, linear)`` draws the coordinates against t above their rates and gives the
matplotlib Figure; ``plot(trajectory, path, linear)`` writes it to .png or .svg. Both read
the results as data; matplotlib comes through ``figures``.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from . import figures
from ..runtime.multibody_motion import MultibodyLinearResponse, MultibodyTrajectory
from ..runtime.simulation import LinearResponse, Trajectory


def figure(trajectory: Trajectory | MultibodyTrajectory,
           linear: LinearResponse | MultibodyLinearResponse | None = None) -> Any:
    """A matplotlib Figure of ``trajectory``: theta(t) [deg] above thetadot(t) [deg/s], and
    the linearised response (dashed) with its equilibrium (dotted) when given; with several
    coordinates each coordinate above each rate. Raises figures.PlotUnavailable without
    matplotlib."""
    if isinstance(trajectory, MultibodyTrajectory):
        return _several_coordinates(trajectory, linear)  # type: ignore[arg-type]
    plt = figures.pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      constrained_layout=True)
    t = trajectory.t
    top.plot(t, trajectory.theta_deg, color="C0", label="nonlinear")
    bottom.plot(t, trajectory.theta_d_deg, color="C0")
    if linear is not None:
        e = linear.equilibrium
        about = (rf"linearised about $\theta_E$ = {math.degrees(linear.theta_e):.2f} deg "
                 rf"($\zeta$ = {e.zeta.real:.3g})")
        top.plot(t, linear.theta_deg, "--", color="C1", label=about)
        bottom.plot(t, linear.theta_d_deg, "--", color="C1")
        top.axhline(math.degrees(linear.theta_e), color="0.5", linestyle=":", linewidth=1,
                    label=r"$\theta_E$")
    top.set_ylabel(r"$\theta$ [deg]")
    bottom.set_ylabel(r"$\dot\theta$ [deg/s]")
    bottom.set_xlabel("t [s]")
    top.set_title(rf"{trajectory.library.TITLE}: $\theta_0$ = {trajectory.theta_deg[0]:.4g} deg, "
                  rf"$\dot\theta_0$ = {trajectory.theta_d_deg[0]:.4g} deg/s", fontsize=10)
    for axes in (top, bottom):
        axes.grid(True, alpha=0.3)
    top.legend(loc="best", fontsize=8)   # the lower panel's lines are the same
    return fig


def _several_coordinates(trajectory: MultibodyTrajectory,
                         linear: MultibodyLinearResponse | None) -> Any:
    """Each coordinate against t above each rate, and the linearised response dashed."""
    plt = figures.pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      constrained_layout=True)
    coordinates, rates = trajectory.labels()
    for i, name in enumerate(coordinates):
        line, = top.plot(trajectory.t, trajectory.theta_shown[:, i], label=name)
        bottom.plot(trajectory.t, trajectory.theta_d_shown[:, i], color=line.get_color(),
                    label=rates[i])
        if linear is not None:
            top.plot(trajectory.t, linear.theta_shown[:, i], "--", color=line.get_color(),
                     linewidth=1, label=f"{name}, linearised")
            bottom.plot(trajectory.t, linear.theta_d_shown[:, i], "--",
                        color=line.get_color(), linewidth=1)
    top.set_ylabel("coordinates")
    bottom.set_ylabel("rates")
    bottom.set_xlabel("t [s]")
    top.set_title(trajectory.library.TITLE, fontsize=10)
    for axes in (top, bottom):
        axes.grid(True, alpha=0.3)
        axes.legend(loc="best", fontsize=8)
    return fig


def plot(trajectory: Trajectory | MultibodyTrajectory, path: str | Path,
         linear: LinearResponse | MultibodyLinearResponse | None = None) -> Path:
    """``figure`` written to ``path`` (.png or .svg); the path. Raises ValueError for another
    extension, figures.PlotUnavailable without matplotlib."""
    path = figures.check_path(path)
    return figures.save(figure(trajectory, linear), path)
