"""The time response of a mechanism: its reduced equation of motion integrated in C.

``simulate(params, theta0, theta_d0, t)`` integrates thetaddot = f(theta, thetadot), the
reduced equation of motion (36), from the angle theta0 [rad] and rate theta_d0 [rad/s] at
t[0] [s], in the library's C (``PREFIX_simulation_start``/``_advance``: the runtime's adaptive
Dormand-Prince 5(4), codegen_ode.c, on the unchecked kernel of thetaddot), and returns a
``Trajectory``: numpy arrays of theta [rad] and thetadot [rad/s] at every time of t.
``rk4_step`` is one fixed step (``PREFIX_rk4_step``), for real-time loops.

``linearised(trajectory)`` is the response of the linearisation M x'' + B x' + K x = 0
about the stable equilibrium nearest the start (M, B, K from the library's analysis), from
the same initial state, to set beside the nonlinear one; ``write`` saves them as CSV or
JSON (in degrees, as the command line prints them). ``codegen.presentation.motion`` draws
them.
"""
from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import files
from .analysis import Equilibrium, Method, analyze, library_of_params
from ..errors import LibraryError
from .library import Library, ParameterSet, params_shown

#: Output points per progress report: a hundredth of them (a progress bar's resolution).
PROGRESS_STEPS = 100

#: The file types ``write`` writes (by the path's suffix).
FORMATS = (".csv", ".json")


class _InDegrees:
    """theta [rad] and theta_d [rad/s] arrays, also in degrees."""

    theta: np.ndarray
    theta_d: np.ndarray

    @property
    def theta_deg(self) -> np.ndarray:
        """theta [deg]."""
        return np.degrees(self.theta)

    @property
    def theta_d_deg(self) -> np.ndarray:
        """thetadot [deg/s]."""
        return np.degrees(self.theta_d)


@dataclass(frozen=True, eq=False)
class Trajectory(_InDegrees):
    """A time response: theta(t) [rad] and thetadot(t) [rad/s] at the times t [s] (the
    first is the initial state), and what the integration took (accepted and rejected
    steps, evaluations of thetaddot) at the tolerances rtol, atol [rad, rad/s]."""

    params: ParameterSet
    t: np.ndarray
    theta: np.ndarray
    theta_d: np.ndarray
    rtol: float
    atol: float
    steps: int
    rejected: int
    evaluations: int

    @property
    def library(self) -> Library:
        return type(self.params).library


def times_of(t: Sequence[float] | np.ndarray) -> np.ndarray:
    times = np.array(t, dtype=np.float64)   # a copy: the trajectory owns its times
    if times.ndim != 1 or times.size < 1:
        raise ValueError(f"t must be a 1-D array of at least one time, not shape {times.shape}")
    if not np.all(np.isfinite(times)):
        raise ValueError("t: every time must be finite")
    if np.any(np.diff(times) < 0):
        raise ValueError("t: the times must not decrease")
    return times


#: The largest initial angle [rad] double precision resolves to 1e-9 rad (its spacing
#: there is 2^-30 rad): beyond, the motion's angle would be rounding.
MAX_ANGLE = 2.0**22
#: The largest initial rate [rad/s] whose square (in e1 thetadot^2) stays far from overflow.
MAX_RATE = 1e150


def _check_state(theta0: float, theta_d0: float) -> None:
    """ValueError naming an initial state beyond what the arithmetic supports."""
    for name, value, limit, unit in (("theta0", theta0, MAX_ANGLE, "rad"),
                                     ("theta_d0", theta_d0, MAX_RATE, "rad/s")):
        if isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(
                value, bool) and math.isfinite(value) and abs(value) > limit:
            raise ValueError(f"{name}: {value:g} {unit} is beyond what double precision "
                             f"resolves (|{name}| <= {limit:.6g} {unit})")


def ode_options(library: Library, rtol: float | None, atol: float | None,
             max_steps: int | None, h_max: float) -> Any:
    """The C options (a pointer), the library's defaults where None; ValueError naming one
    out of range."""
    lib = library.lib
    options = library.ffi.new("codegen_ode_options *", lib.codegen_ode_defaults())
    if max_steps is not None and (not isinstance(max_steps, (int, np.integer))
                                  or not 1 <= max_steps <= np.iinfo(np.int32).max):
        raise ValueError(f"max_steps: must be an integer in [1, 2^31), not {max_steps!r}")
    options.rtol = options.rtol if rtol is None else rtol
    options.atol = options.atol if atol is None else atol
    options.max_steps = options.max_steps if max_steps is None else max_steps
    options.h_max = h_max
    if not lib.CODEGEN_ODE_MIN_RTOL <= options.rtol <= 1.0:
        raise ValueError(f"rtol: must lie in [{lib.CODEGEN_ODE_MIN_RTOL:.3g}, 1], not {rtol!r}")
    if not 0.0 <= options.atol < math.inf:
        raise ValueError(f"atol: must be finite and not negative, not {atol!r}")
    if not options.h_max > 0.0:
        raise ValueError(f"h_max: must be positive, not {h_max!r}")
    return options


class IntegrationError(LibraryError):
    """The integration failed after the start (the step budget, the step size, a singular
    state): ``trajectory`` holds what was computed before, the outputs up to the time the
    failure happened (at least the initial state)."""

    def __init__(self, *args: Any, trajectory: Trajectory | None = None, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.trajectory = trajectory

    def __reduce__(self) -> tuple[Any, ...]:
        cls, arguments = super().__reduce__()[:2]
        return (_rebuild_integration_error, (cls, arguments, self.trajectory))


def _rebuild_integration_error(cls: type, arguments: tuple[Any, ...],
                               trajectory: Trajectory | None) -> IntegrationError:
    error = cls(*arguments)
    error.trajectory = trajectory
    return error


def integration_error(library: Library, status: int, t: float, max_steps: int,
                      partial: Any) -> IntegrationError:
    """A failure after the start, at time t: the reason and the time it happened, no
    parameter to blame, and the trajectory up to there (of one coordinate or several)."""
    code = {v: k for k, v in library.STATUS.items()}[status]
    values: dict[str, Any] = {"t": t}
    if code == "ERR_STEP_BUDGET":
        values["max_steps"] = max_steps
    return IntegrationError(status, code, library._reason(status), values=values,
                            trajectory=partial)


def simulate(params: ParameterSet, theta0: float, theta_d0: float,
             t: Sequence[float] | np.ndarray, *, rtol: float | None = None,
             atol: float | None = None, max_steps: int | None = None,
             h_max: float = math.inf,
             progress: Callable[[int, int], None] | None = None) -> Trajectory:
    """The motion from theta0 [rad], theta_d0 [rad/s] at t[0], at every time of ``t`` [s]
    (1-D, finite, non-decreasing), integrated in C.

    Options (None: the C defaults, ``codegen_ode_defaults``: rtol 1e-9, atol 1e-12, 10^6
    steps): ``rtol`` (in [CODEGEN_ODE_MIN_RTOL, 1]) and ``atol`` (>= 0, in rad and rad/s)
    bound each step's error by atol + rtol |y|; ``max_steps`` the steps tried in all;
    ``h_max`` [s] the longest step. ``progress(done, total)`` is called as the output points
    are computed, a hundredth at a time (the integration is the same bit for bit with or
    without it: outputs are interpolated and never shorten a step).

    The motion is on the assembly mode the model's conditions declare at theta0 (decided
    for this parameter set, and kept along the motion); where they decide none there, the
    start fails with ERR_MODE_UNDECIDED.

    Raises ValueError for t or an option out of range; LibraryError for bad parameters or
    initial state (naming them). When the integration fails (ERR_STEP_BUDGET,
    ERR_STEP_SIZE: a singular or too stiff motion, or the library's status for a thetaddot
    that is not finite, ERR_SINGULAR_STATE or ERR_OVERFLOW) it raises IntegrationError (a
    LibraryError) with the time reached, whose ``trajectory`` holds the outputs before it.
    """
    library = library_of_params(params)
    times = times_of(t)
    _check_state(theta0, theta_d0)
    ffi, lib, P = library.ffi, library.lib, library.PREFIX
    options = ode_options(library, rtol, atol, max_steps, h_max)
    start, advance = getattr(lib, f"{P}_simulation_start"), getattr(lib, f"{P}_simulation_advance")
    simulation = ffi.new(f"{P}_simulation *")

    def rerun(values: Any) -> int:
        return start(ffi.new(f"{P}_simulation *"), library._c_params(values), times[0], theta0,
                     theta_d0, options)

    library.check(start(simulation, library._c_params(params), times[0], theta0, theta_d0,
                        options),
                  params, rerun=rerun, inputs={"theta0": theta0, "theta_d0": theta_d0})
    theta, theta_d = np.empty_like(times), np.empty_like(times)
    theta[0], theta_d[0] = theta0, theta_d0
    c_times = ffi.from_buffer("double[]", times)
    c_theta, c_theta_d = (ffi.from_buffer("double[]", a, require_writable=True)
                          for a in (theta, theta_d))
    count = len(times)
    piece = count if progress is None else max(1, -(-count // PROGRESS_STEPS))
    reached = ffi.new("size_t *")

    def trajectory(n: int) -> Trajectory:
        state = simulation.state
        return Trajectory(params, times[:n], theta[:n], theta_d[:n], options.rtol,
                          options.atol, int(state.steps), int(state.rejected),
                          int(state.evaluations))

    for first in range(0, count, piece):
        n = min(piece, count - first)
        status = advance(simulation, c_times + first, n, c_theta + first, c_theta_d + first,
                         reached)
        if status != library.STATUS["OK"]:
            written = max(first + int(reached[0]), 1)   # t[0] holds the initial state
            raise integration_error(library, status, simulation.state.t,
                                    simulation.options.max_steps, trajectory(written))
        if progress is not None:
            progress(first + n, count)
    return trajectory(count)


def rk4_step(params: ParameterSet, theta: float, theta_d: float, h: float
             ) -> tuple[float, float]:
    """One classical Runge-Kutta step (order 4) of ``h`` [s] from theta [rad], theta_d
    [rad/s]: (theta, thetadot) h later, for fixed-step (real-time) loops; four evaluations
    of thetaddot in C (``PREFIX_rk4_step``). Raises LibraryError naming what is at fault."""
    library = library_of_params(params)
    ffi, P = library.ffi, library.PREFIX
    entry = getattr(library.lib, f"{P}_rk4_step")
    out = ffi.new("double[2]")

    def rerun(values: Any) -> int:
        return entry(library._c_params(values), h, theta, theta_d, out, out + 1)

    library.check(entry(library._c_params(params), h, theta, theta_d, out, out + 1), params,
                  rerun=rerun, inputs={"h": h, "theta": theta, "theta_d": theta_d})
    return out[0], out[1]


# --------------------------------------------------------------------------- linearisation

@dataclass(frozen=True, eq=False)
class LinearResponse(_InDegrees):
    """The response of M x'' + B x' + K x = 0 about a stable ``equilibrium``, theta = theta_e +
    x: theta_e [rad] is its angle (moved by whole turns next to the start on a periodic
    coordinate), theta [rad] and theta_d [rad/s] at the trajectory's times."""

    equilibrium: Equilibrium
    theta_e: float
    theta: np.ndarray
    theta_d: np.ndarray


def linear_response(M: float, B: float, K: float, x0: float, v0: float, t: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
    """x(t) and x'(t) of M x'' + B x' + K x = 0 from x(0) = x0, x'(0) = v0 (M > 0), in closed
    form for every damping: x = x0 e^(a t) C + (v0 - a x0) e^(a t) S with a = -B/(2M),
    q = K/M - a^2, C = cos, cosh or 1 and S = sin/w, sinh/m or t (S' = C, C' = -q S)."""
    a, q = -B / (2 * M), K / M - (B / (2 * M)) ** 2
    t = np.asarray(t, dtype=np.float64)
    if q > 0:
        w = math.sqrt(q)
        decay = np.exp(a * t)
        ec, es = decay * np.cos(w * t), decay * np.sin(w * t) / w
    elif q < 0:  # as two exponentials, so that neither overflows nor cancels
        m = math.sqrt(-q)
        ec = 0.5 * (np.exp((a + m) * t) + np.exp((a - m) * t))
        es = np.exp((a + m) * t) * -np.expm1(-2 * m * t) / (2 * m)
    else:
        ec = np.exp(a * t)
        es = t * ec
    x = x0 * ec + (v0 - a * x0) * es
    v = x0 * (a * ec - q * es) + (v0 - a * x0) * (a * es + ec)
    return x, v


def is_stable(e: Equilibrium) -> bool:
    """Whether the linearisation about e stays bounded: K > 0, M > 0, B >= 0 (a stable
    equilibrium, or an undamped centre)."""
    return e.K > 0 and e.M > 0 and e.B >= 0


def nearest_stable(params: ParameterSet, theta: float, method: Method = "auto"
                   ) -> tuple[Equilibrium, float] | None:
    """The stable equilibrium of ``params`` (``analyze``, by ``method``) nearest ``theta``
    [rad], and its angle moved by whole turns next to theta on a periodic coordinate; None
    if there is none."""
    library = library_of_params(params)
    turn = 2 * math.pi if library.SPEC["periodic"] else 0.0
    best = None
    for e in analyze(params, method).equilibria:
        if not is_stable(e):
            continue
        theta_e = e.theta + (turn * round((theta - e.theta) / turn) if turn else 0.0)
        if best is None or abs(theta - theta_e) < abs(theta - best[1]):
            best = (e, theta_e)
    return best


def linearised(trajectory: Trajectory, method: Method = "auto") -> LinearResponse:
    """The linearised response beside a trajectory: about the stable equilibrium nearest
    its start, from its initial state, at its times. ValueError if there is none."""
    found = nearest_stable(trajectory.params, float(trajectory.theta[0]), method)
    if found is None:
        raise ValueError(f"{trajectory.library.PREFIX} has no stable equilibrium for these "
                         "parameters: there is no linearised response to compare")
    e, theta_e = found
    x, v = linear_response(e.M, e.B, e.K, float(trajectory.theta[0]) - theta_e,
                           float(trajectory.theta_d[0]), trajectory.t - trajectory.t[0])
    return LinearResponse(e, theta_e, theta_e + x, v)


# --------------------------------------------------------------------------- files

def to_dict(trajectory: Trajectory, linear: LinearResponse | None = None) -> dict[str, Any]:
    """JSON-ready: angles in degrees (an angle parameter too, as NAME_deg), rates in deg/s,
    times in s, other parameters SI."""
    library = trajectory.library
    result: dict[str, Any] = {
        "mechanism": library.PREFIX, "params": params_shown(asdict(trajectory.params), library.UNITS),
        "rtol": trajectory.rtol, "atol": trajectory.atol, "steps": trajectory.steps,
        "rejected": trajectory.rejected, "evaluations": trajectory.evaluations,
        "t_s": trajectory.t.tolist(), "theta_deg": trajectory.theta_deg.tolist(),
        "thetadot_deg_s": trajectory.theta_d_deg.tolist(), "linearised": None}
    if linear is not None:
        e = linear.equilibrium
        result["linearised"] = {
            "theta_e_deg": math.degrees(linear.theta_e), "M": e.M, "B": e.B, "K": e.K,
            "eigenvalues": [[z.real, z.imag] for z in e.eigenvalues],
            "theta_deg": linear.theta_deg.tolist(),
            "thetadot_deg_s": linear.theta_d_deg.tolist()}
    return result


def write(trajectory: Trajectory, path: str | Path, linear: LinearResponse | None = None
          ) -> Path:
    """The trajectory (and the linearised response) as .csv (a row per time: t [s], theta
    [deg], thetadot [deg/s], and theta_lin, thetadot_lin) or .json (``to_dict``)."""
    return files.write_table(path, "a trajectory", lambda: to_dict(trajectory, linear),
                             lambda stream: write_csv(stream, trajectory, linear))


def write_csv(stream: Any, trajectory: Trajectory, linear: LinearResponse | None = None
              ) -> None:
    """The CSV of ``write`` to an open text stream (e.g. stdout); every value to 17 digits."""
    header = ["t_s", "theta_deg", "thetadot_deg_s"]
    columns = [trajectory.t, trajectory.theta_deg, trajectory.theta_d_deg]
    if linear is not None:
        header += ["theta_lin_deg", "thetadot_lin_deg_s"]
        columns += [linear.theta_deg, linear.theta_d_deg]
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header)
    writer.writerows([f"{v:.17g}" for v in row] for row in zip(*columns))
