"""The compiled libraries from Python.

``load(name)`` gives the ``Library`` of a shipped mechanism (built into the package as
``codegen._native_NAME``); ``load_from(folder, name)`` one a user generated and built with
``python -m codegen generate --model FILE --out FOLDER``. Several load side by side; each
loads once per process. A library remembers which of the two loaded it (``Library.origin``),
so its parameter sets and results pickle: another process loads it the same way again.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from . import (analysis, batch, branches, library, multibody, multibody_motion, response,
               simulation, sweep)
from ..errors import LibraryError
from .functions import Argument, Function, LibraryFunction
from .library import Origin, ParameterSet, ParamsLike


class Library(library.Library):
    """A ``codegen.runtime.library.Library`` as ``load`` and ``load_from`` give it: what it computes
    (analyses, simulations, sweeps, branches: modules that build on the library, so its
    base class cannot call them) as methods, and it pickles, loaded again by its origin."""

    def __reduce__(self) -> tuple[Any, ...]:
        # What refers to a library (its Params, results) pickles it along: by its origin.
        return (_unpickled_library, (self._require_origin(),))

    def analyze(self, params: ParamsLike | None = None, method: analysis.Method = "auto"
                ) -> analysis.Analysis | analysis.MultibodyAnalysis:
        """Every equilibrium of ``params`` (default: the example), classified and linearised,
        by the route ``method`` names: ``codegen.runtime.analysis.analyze``, for any number of
        coordinates (several: every equilibrium in the box of their ranges with its modes, a
        ``MultibodyAnalysis``; one route, "isolate", which "auto" takes). Angles in radians."""
        return analysis.analyze(self._params(params), method)

    def receptance(self, params: ParamsLike | None, theta: Any, omega: Any) -> np.ndarray:
        """H(omega) = (K - omega^2 M + i omega B)^-1 at the coordinates theta, for each
        omega [rad/s], of a mechanism with several coordinates: complex (len(omega), n, n)."""
        return multibody.receptance(self, self._params(params), theta, omega)

    def analyze_batch(self, table: np.ndarray, method: analysis.Method = "auto"
                      ) -> tuple[list[analysis.Analysis | analysis.MultibodyAnalysis | None],
                                 np.ndarray]:
        """``analyze`` over a ``params_array``, in C: (analyses, statuses), None where an
        item failed (its status says why): see ``codegen.runtime.analysis.analyze_batch``."""
        return analysis.analyze_batch(table, self, method)

    def analyze_table(self, table: np.ndarray, method: analysis.Method = "auto",
                      workers: int = 1) -> Any:
        """``analyze`` over a ``params_array`` as numpy arrays, one row per root, no Python
        object per set, on ``workers`` threads: see ``codegen.runtime.batch.analyze_table``.
        With several coordinates, a row per proven equilibrium, its coordinates and modes in
        arrays (``codegen.runtime.multibody.roots_dtype``), and ``.uncertain`` per set."""
        return batch.analyze_table(table, self, method, workers)

    def simulate(self, params: ParamsLike | None, theta0: float, theta_d0: float,
                 t: Any, **options: Any) -> Any:
        """The motion from theta0 [rad], theta_d0 [rad/s] at t[0] at every time of ``t`` [s],
        integrated in C, as numpy arrays (a ``codegen.runtime.simulation.Trajectory``: ``.theta``
        [rad], ``.theta_d`` [rad/s]); ``params`` None is the example. Options (rtol, atol,
        max_steps, h_max, progress): see ``codegen.runtime.simulation.simulate``. With several
        coordinates theta0 and theta_d0 hold n values each: ``codegen.runtime.multibody_motion.simulate``."""
        if self.dof > 1:
            return multibody_motion.simulate(self, self._params(params), theta0, theta_d0, t,
                                             **options)
        return simulation.simulate(self._params(params), theta0, theta_d0, t, **options)

    def rk4_step(self, params: ParamsLike | None, theta: float, theta_d: float, h: float
                 ) -> tuple[float, float]:
        """One fixed Runge-Kutta step (order 4) of h [s] from theta [rad], theta_d [rad/s]:
        (theta, theta_d) h later, for real-time loops; see ``codegen.runtime.simulation.rk4_step``."""
        return simulation.rk4_step(self._params(params), theta, theta_d, h)

    def frequency_response(self, params: ParamsLike | None = None, omega: Any = None,
                           **options: Any) -> Any:
        """The receptance H(omega) = 1 / (K - omega^2 M + i omega B) [rad/(N m)] about a stable
        equilibrium of ``params`` (default: the example; the first stable equilibrium, or
        ``equilibrium=i`` of ``analyze(params).equilibria``) at ``omega`` [rad/s] (default:
        0 to 3 omega_n), computed in C, as a ``codegen.runtime.response.FrequencyResponse``
        (``.omega``, ``.H``, ``.amplitude``, ``.phase``, ``.natural_frequency``); options:
        see ``codegen.runtime.response.frequency_response``."""
        return response.frequency_response(self._params(params), omega, **options)

    def sweep(self, sets: Any, **options: Any) -> np.ndarray:
        """Every set of ``sets`` (a params_array, e.g. ``codegen.runtime.sweep.grid`` or ``sample``)
        analysed into one table, a row per equilibrium, locally on threads or on Dask:
        ``codegen.runtime.sweep.sweep(self, sets, **options)`` (see it for the options)."""
        return sweep.sweep(self, sets, **options)

    def branches(self, parameter: str, start: float, stop: float, **options: Any) -> Any:
        """Every equilibrium as ``parameter`` runs from ``start`` to ``stop`` (its unit),
        joined into branches, with folds, pitchforks, branch ends and stability changes
        located by bisection, as a ``codegen.runtime.branches.Branches``: ``codegen.runtime.branches.
        branches(self, parameter, start, stop, **options)`` (see it for the options: points,
        base, method, workers, progress, tolerance). Angles in radians."""
        return branches.branches(self, parameter, start, stop, **options)


def library_of(origin: Origin) -> Library:
    """The library an origin names, loaded (once per process) as it was the first time."""
    if origin[0] == "load" and len(origin) == 2:
        return load(origin[1])
    if origin[0] == "load_from" and len(origin) == 3:
        return load_from(origin[1], origin[2])
    raise ValueError(f"unknown library origin {origin!r}")


def _unpickled_library(origin: Origin) -> Library | Unloadable:
    """library_of, or, where this process cannot load it, an Unloadable that raises on use."""
    try:
        return library_of(origin)
    except Exception as error:  # noqa: BLE001 - every failure becomes the same report
        return Unloadable(origin, f"{type(error).__name__}: {error}")


class Unloadable:
    """A library that this process could not load where it was unpickled (a pool's worker
    whose library folder is gone): each use raises ValueError with the reason. Raising
    while unpickling instead would end the pool's worker before its task starts, and
    multiprocessing's pool would wait for that task forever."""

    def __init__(self, origin: Origin, reason: str) -> None:
        self.origin, self.reason = origin, reason

    def __getattr__(self, name: str) -> Any:
        raise ValueError(f"the library {self.origin[-1]!r} could not be loaded in this "
                           f"process (from {self.origin[1]}): {self.reason}")

    def __reduce__(self) -> tuple[Any, ...]:
        return (_unpickled_library, (self.origin,))


NATIVE = "_native_{}"
#: The package the shipped libraries are built into (setup.py): codegen, one level up.
PACKAGE = __package__.rpartition(".")[0]


@lru_cache(maxsize=None)
def load(name: str) -> Library:
    """The Library of a shipped mechanism, by one of the names ``shipped()`` lists. Raises
    ValueError if this installation has no compiled library of that name."""
    try:
        module = importlib.import_module(f"{PACKAGE}.{NATIVE.format(name)}")
    except ModuleNotFoundError:
        raise ValueError(f"no compiled library for {name!r} in this installation") from None
    return Library(module, origin=("load", name))


def shipped() -> list[str]:
    """Names of the mechanisms compiled into this installation (no import needed)."""
    from ..resources import compiled

    return compiled()


def load_from(folder: str | os.PathLike[str], name: str) -> Library:
    """The Library a user built into ``folder`` (see codegen.compiler.build.build_into), e.g.
    ``load_from("build/mine", "spring_pendulum")``. The folder is taken as an absolute path,
    so the same library loads once whichever way the folder is written. Raises ValueError
    if the folder holds no compiled library of that name."""
    return _load_from(str(Path(folder).resolve()), name)


@lru_cache(maxsize=None)
def _load_from(folder: str, name: str) -> Library:
    module_name = NATIVE.format(name)
    candidates = sorted(Path(folder).glob(f"{module_name}.*.so")) + sorted(
        Path(folder).glob(f"{module_name}.*.pyd"))
    if not candidates:
        raise ValueError(f"no compiled library {module_name} in {folder}")
    spec = importlib.util.spec_from_file_location(module_name, candidates[0])
    if spec is None or spec.loader is None:
        raise ValueError(f"{candidates[0]} is not an extension module Python can load")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return Library(module, origin=("load_from", folder, name))


__all__ = ["Argument", "Function", "Library", "LibraryError", "LibraryFunction",
           "ParameterSet", "ParamsLike", "load", "load_from", "shipped"]
