"""Section 6 of `make bench`: the library's time response against scipy's.

For each mechanism's example, from rest 0.3 rad off its least damped stable equilibrium, for
SPAN seconds with output at POINTS times: ``Library.simulate`` (the C integrator through
the Python API, Dormand-Prince 5(4)) against ``scipy.integrate.solve_ivp`` with the same
method (RK45) and tolerances on thetaddot lambdified from the derivation to Python's math
module (the fastest right-hand side a float-by-float caller can have), measured in the
same run. Both are compared with a tight reference: DOP853 at rtol 1e-13 on the same
lambdified thetaddot. Issue 13's target: the library at least 100 times faster on doughty.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from codegen.runtime.library import Library
from codegen.runtime.simulation import is_stable
from symbolic import Symbolic, scalar_function

SPAN = 2.0            # [s]
POINTS = 201
RTOL, ATOL = 1e-9, 1e-12
OFFSET = 0.3          # [rad] from the equilibrium
REFERENCE = {"method": "DOP853", "rtol": 1e-13, "atol": 1e-15}


def start(library: Library) -> float:
    """theta0 [rad]: OFFSET from the example's least damped stable equilibrium."""
    stable = [e for e in library.analyze().equilibria if is_stable(e)]
    return min(stable, key=lambda e: e.zeta.real).theta + OFFSET


def _scipy(thetaddot: Callable[..., Any], values: list[float], theta0: float,
           times: np.ndarray, **options: Any) -> Any:
    result = solve_ivp(lambda t, y: [y[1], thetaddot(y[0], y[1], *values)], (0.0, SPAN),
                       [theta0, 0.0], t_eval=times, **options)
    if not result.success:
        raise RuntimeError(f"solve_ivp failed: {result.message}")
    return result


def _error(theta: np.ndarray, theta_d: np.ndarray, reference: Any) -> tuple[float, float]:
    """max |theta - theta_ref| [rad] and max |thetadot - ref| / max |ref thetadot|."""
    return (float(np.max(np.abs(theta - reference.y[0]))),
            float(np.max(np.abs(theta_d - reference.y[1])) / np.max(np.abs(reference.y[1]))))


def measure(library: Library, symbols: Symbolic, repeats: int,
            median_seconds: Callable[[Callable[[], object], int], float]) -> dict[str, Any]:
    """Times, work and accuracy of both integrations of one mechanism."""
    params = library.example_params()
    values = [getattr(params, n) for n in library.PARAMETER_NAMES]
    thetaddot = scalar_function((symbols.theta, symbols.theta_d, *symbols.parameters),
                                symbols.thetaddot, modules="math")
    theta0, times = start(library), np.linspace(0.0, SPAN, POINTS)

    def ours() -> Any:
        return library.simulate(params, theta0, 0.0, times, rtol=RTOL, atol=ATOL)

    def theirs() -> Any:
        return _scipy(thetaddot, values, theta0, times, method="RK45", rtol=RTOL, atol=ATOL)

    reference = _scipy(thetaddot, values, theta0, times, **REFERENCE)
    trajectory, scipy = ours(), theirs()
    library_seconds, scipy_seconds = median_seconds(ours, repeats), median_seconds(theirs,
                                                                                   repeats)
    return {"theta0_deg": math.degrees(theta0), "span_s": SPAN, "points": POINTS,
            "rtol": RTOL, "atol": ATOL,
            "library_ms": library_seconds * 1e3, "library_steps": trajectory.steps,
            "library_rejected": trajectory.rejected,
            "library_evaluations": trajectory.evaluations,
            "scipy_ms": scipy_seconds * 1e3, "scipy_evaluations": int(scipy.nfev),
            "speedup": scipy_seconds / library_seconds,
            "library_error": _error(trajectory.theta, trajectory.theta_d, reference),
            "scipy_error": _error(scipy.y[0], scipy.y[1], reference)}
