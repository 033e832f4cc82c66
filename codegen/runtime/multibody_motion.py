"""The time response of a mechanism with n coordinates: M thetaddot + h + B thetadot + G = 0
integrated in C, the linearised response beside it, and its table.

``simulate(library, params, theta0, theta_d0, t)`` calls the library's ``NAME_simulate``
(the runtime's Dormand-Prince 5(4) on thetaddot = -M^-1 (h + B thetadot + G)) and returns a
``MultibodyTrajectory``: each coordinate and its rate at every time of t. ``linearised``
is the response of M x'' + B x' + K x = 0 about the stable equilibrium nearest the start,
exp(A t) x0 with A = [[0, I], [-M^-1 K, -M^-1 B]] at the equilibrium (the library's
M, B, K), from the same state. ``write`` saves both as CSV or JSON (angles in degrees, as
the command line prints them); ``codegen.presentation.motion`` draws them.
"""
from __future__ import annotations

import csv
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import multibody
from .simulation import integration_error, ode_options, times_of
from .. import files
from .library import params_shown

#: Statuses of a failure after the start: the outputs before it are a trajectory.
_AFTER_START = ("ERR_STEP_BUDGET", "ERR_STEP_SIZE", "ERR_SINGULAR_STATE")


class _Shown:
    """Coordinates and rates in the units the command line shows: angles in degrees."""

    library: Any
    theta: np.ndarray
    theta_d: np.ndarray

    @property
    def coordinates(self) -> list[str]:
        return [c["name"] for c in self.library.SPEC["coordinates"]]

    @property
    def angular(self) -> np.ndarray:
        """Which coordinates are angles (shown in degrees)."""
        return np.array([c["unit"] == "rad" for c in self.library.SPEC["coordinates"]])

    @property
    def theta_shown(self) -> np.ndarray:
        return np.where(self.angular, np.degrees(self.theta), self.theta)

    @property
    def theta_d_shown(self) -> np.ndarray:
        return np.where(self.angular, np.degrees(self.theta_d), self.theta_d)

    def labels(self) -> tuple[list[str], list[str]]:
        """Each coordinate's column name with its unit, and its rate's."""
        units = [("deg" if c["unit"] == "rad" else c["unit"])
                 for c in self.library.SPEC["coordinates"]]
        return ([f"{n}_{u}" for n, u in zip(self.coordinates, units)],
                [f"{n}dot_{u}_s" for n, u in zip(self.coordinates, units)])


@dataclass(frozen=True, eq=False)
class MultibodyTrajectory(_Shown):
    """A time response: theta (len(t), n) and theta_d at the times t [s] (the first is the
    initial state), at the tolerances rtol, atol."""

    library: Any
    params: Any
    t: np.ndarray
    theta: np.ndarray
    theta_d: np.ndarray
    rtol: float
    atol: float


def simulate(library: Any, params: Any, theta0: Any, theta_d0: Any, t: Any, *,
             rtol: float | None = None, atol: float | None = None,
             max_steps: int | None = None, h_max: float = math.inf) -> MultibodyTrajectory:
    """The motion from theta0, theta_d0 (n values each) at t[0], at every time of ``t`` [s],
    integrated in C (NAME_simulate); the options as ``codegen.runtime.simulation.simulate``'s.
    Raises LibraryError for bad parameters or a bad initial state, IntegrationError (with
    the trajectory before it) when the integration fails after the start."""
    n = library.dof
    times = times_of(t)
    start = [np.asarray(x, dtype=float).reshape(n) for x in (theta0, theta_d0)]
    options = ode_options(library, rtol, atol, max_steps, h_max)
    ffi = library.ffi
    y = np.empty((len(times), 2 * n))
    reached = ffi.new("size_t *")
    status = getattr(library.lib, f"{library.PREFIX}_simulate")(
        library._c_params(params), ffi.from_buffer("double[]", start[0]),
        ffi.from_buffer("double[]", start[1]), ffi.from_buffer("double[]", times), len(times),
        options, ffi.from_buffer("double[]", y, require_writable=True), reached)

    def trajectory(count: int) -> MultibodyTrajectory:
        return MultibodyTrajectory(library, params, times[:count], y[:count, :n],
                                   y[:count, n:], options.rtol, options.atol)

    code = {v: k for k, v in library.STATUS.items()}.get(status)
    if code in _AFTER_START and reached[0] >= 1:
        count = int(reached[0])
        raise integration_error(library, status, float(times[count - 1]), options.max_steps,
                                trajectory(count))
    library.check(status, params, inputs={"theta0": start[0].tolist(),
                                          "theta_d0": start[1].tolist()})
    return trajectory(len(times))


# --------------------------------------------------------------------------- linearisation

@dataclass(frozen=True, eq=False)
class MultibodyLinearResponse(_Shown):
    """The response of M x'' + B x' + K x = 0 about a stable ``equilibrium``, theta =
    theta_e + x, at a trajectory's times (theta_e: the equilibrium moved by whole turns next
    to the start on a periodic coordinate)."""

    library: Any
    equilibrium: multibody.MultibodyEquilibrium
    theta_e: np.ndarray
    theta: np.ndarray
    theta_d: np.ndarray


def expm(A: np.ndarray) -> np.ndarray:
    """exp(A) by scaling and squaring of its Taylor series: A / 2^s with norm <= 1/2, where 20
    terms leave an error below 2^-21 / 21!, far under double precision's; then squared s
    times. Exact for every matrix, defective (a critically damped mode) included."""
    norm = float(np.abs(A).sum(axis=0).max()) if A.size else 0.0
    s = max(0, math.ceil(math.log2(norm / 0.5))) if norm > 0.5 else 0
    scaled = A / 2.0**s
    term = result = np.eye(len(A))
    for k in range(1, 21):
        term = term @ scaled / k
        result = result + term
    for _ in range(s):
        result = result @ result
    return result


def state_matrix(library: Any, params: Any, theta: np.ndarray) -> np.ndarray:
    """A = [[0, I], [-M^-1 K, -M^-1 B]] of the linearisation at theta (the library's M, B, K)."""
    n = library.dof
    M, B, K = (np.reshape(f(params, theta), (n, n)) for f in
               (library.mass_matrix, library.damping_matrix, library.stiffness_matrix))
    return np.block([[np.zeros((n, n)), np.eye(n)],
                     [-np.linalg.solve(M, K), -np.linalg.solve(M, B)]])


def nearest_stable(library: Any, params: Any, theta: np.ndarray
                   ) -> tuple[multibody.MultibodyEquilibrium, np.ndarray] | None:
    """The stable equilibrium nearest theta (each periodic coordinate moved by whole turns
    next to theta's), and its coordinates so moved; None if there is none."""
    turns = np.where(library.SPEC["periodic"], 2 * math.pi, 0.0)
    best = None
    for e in multibody.analyze(library, params).equilibria:
        if not e.stable:
            continue
        shift = np.where(turns > 0, np.round((theta - e.theta) / np.where(turns > 0, turns, 1))
                         * turns, 0.0)
        moved = e.theta + shift
        if best is None or np.linalg.norm(theta - moved) < np.linalg.norm(theta - best[1]):
            best = (e, moved)
    return best


def linearised(trajectory: MultibodyTrajectory) -> MultibodyLinearResponse:
    """The linearised response beside a trajectory: about the stable equilibrium nearest its
    start, from its initial state, at its times. ValueError if there is none."""
    library, params = trajectory.library, trajectory.params
    found = nearest_stable(library, params, trajectory.theta[0])
    if found is None:
        raise ValueError(f"{library.PREFIX} has no stable equilibrium for these parameters: "
                         "there is no linearised response to compare")
    e, theta_e = found
    n = library.dof
    A = state_matrix(library, params, e.theta)
    x0 = np.concatenate([trajectory.theta[0] - theta_e, trajectory.theta_d[0]])
    x = np.array([expm(A * (t - trajectory.t[0])) @ x0 for t in trajectory.t]).reshape(-1, 2 * n)
    return MultibodyLinearResponse(library, e, theta_e, theta_e + x[:, :n], x[:, n:])


# --------------------------------------------------------------------------- files

def write_csv(stream: Any, trajectory: MultibodyTrajectory,
              linear: MultibodyLinearResponse | None = None) -> None:
    """A row per time: t [s], each coordinate and each rate (angles in deg, deg/s), and the
    linearised response's (suffix _lin); every value to 17 digits."""
    coordinates, rates = trajectory.labels()
    header = ["t_s", *coordinates, *rates]
    columns = [trajectory.t[:, None], trajectory.theta_shown, trajectory.theta_d_shown]
    if linear is not None:
        header += [f"{c}_lin" for c in (*coordinates, *rates)]
        columns += [linear.theta_shown, linear.theta_d_shown]
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header)
    writer.writerows([f"{v:.17g}" for v in row] for row in np.hstack(columns))


def to_dict(trajectory: MultibodyTrajectory, linear: MultibodyLinearResponse | None = None
            ) -> dict[str, Any]:
    """JSON-ready: the coordinates' names and units, the parameters (SI), the times [s] and a
    list per coordinate and rate (angles in deg and deg/s)."""
    coordinates, rates = trajectory.labels()

    def table(motion: _Shown) -> dict[str, list[float]]:
        return dict(zip([*coordinates, *rates],
                        np.hstack([motion.theta_shown, motion.theta_d_shown]).T.tolist()))

    result: dict[str, Any] = {
        "mechanism": trajectory.library.PREFIX, "coordinates": trajectory.coordinates,
        "params": params_shown(asdict(trajectory.params), trajectory.library.UNITS),
        "rtol": trajectory.rtol, "atol": trajectory.atol,
        "t_s": trajectory.t.tolist(), **table(trajectory), "linearised": None}
    if linear is not None:
        e = linear.equilibrium
        result["linearised"] = {
            "equilibrium": linear.theta_e.tolist(),
            "eigenvalues": [[s.real, s.imag] for s in e.eigenvalues], **table(linear)}
    return result


def write(trajectory: MultibodyTrajectory, path: str | Path,
          linear: MultibodyLinearResponse | None = None) -> Path:
    """The trajectory (and the linearised response) as .csv (``write_csv``) or .json
    (``to_dict``)."""
    return files.write_table(path, "a trajectory", lambda: to_dict(trajectory, linear),
                             lambda stream: write_csv(stream, trajectory, linear))

