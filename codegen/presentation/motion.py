"""The figure of a time response: a ``Trajectory`` (``codegen.runtime.simulation``) or a
``MultibodyTrajectory`` (``codegen.runtime.multibody_motion``), with the linearised response
beside it when given.

``figure(trajectory, linear)`` draws the coordinates against t above their rates, a panel
per unit (angles in degrees, lengths in m: never two units on one axis), and gives the
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
    coordinates a panel per unit (angles in deg, lengths in m) of the coordinates above one
    per unit of the rates. Raises figures.PlotUnavailable without matplotlib."""
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
    """A panel per unit of the coordinates (angles [deg], lengths [m]), each coordinate of
    that unit against t, then a panel per unit of the rates ([deg/s], [m/s]); the linearised
    response dashed, in the coordinate's colour."""
    plt = figures.pyplot()
    coordinates = trajectory.library.SPEC["coordinates"]
    groups = figures.by_unit(coordinates)
    fig, panels = plt.subplots(2 * len(groups), 1, sharex=True, squeeze=False,
                               figsize=(7.5, 1.0 + 2.25 * len(groups) * 2),
                               constrained_layout=True)
    panels = panels[:, 0]
    for row, (unit, members) in enumerate(groups):
        shown = figures.shown_unit(unit)
        for axes, kind, suffix, values, linearised in (
                (panels[row], "coordinates", "", trajectory.theta,
                 None if linear is None else linear.theta),
                (panels[len(groups) + row], "rates", "dot", trajectory.theta_d,
                 None if linear is None else linear.theta_d)):
            for i in members:
                name = coordinates[i]["name"] + suffix
                color = f"C{i % 10}"
                axes.plot(trajectory.t, figures.shown_values(values[:, i], unit), color=color,
                          label=name)
                if linearised is not None:
                    axes.plot(trajectory.t, figures.shown_values(linearised[:, i], unit), "--",
                              color=color, linewidth=1, label=f"{name}, linearised")
            axes.set_ylabel(f"{kind} [{shown}/s]" if suffix else f"{kind} [{shown}]")
    panels[-1].set_xlabel("t [s]")
    panels[0].set_title(trajectory.library.TITLE, fontsize=10)
    for axes in panels:
        axes.grid(True, alpha=0.3)
        axes.legend(loc="best", fontsize=8)
    return fig


def plot(trajectory: Trajectory | MultibodyTrajectory, path: str | Path,
         linear: LinearResponse | MultibodyLinearResponse | None = None) -> Path:
    """``figure`` written to ``path`` (.png or .svg); the path. Raises ValueError for another
    extension, figures.PlotUnavailable without matplotlib."""
    path = figures.check_path(path)
    return figures.save(figure(trajectory, linear), path)
