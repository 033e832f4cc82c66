"""Layer 6: one compiled mechanism library from Python, with plain floats or numpy batches.

A ``Library`` wraps the cffi module built from one mechanism's generated/ folder. Every C
function of its emission plan is reachable by name, e.g. ``lib.sigma(params)`` or
``lib.linearisation(params, theta)``. A call with scalars returns floats and 1-D arrays; a
call where ``params`` is a ``params_array`` (or any input has a leading batch dimension)
runs the C batch entry point over numpy arrays without copying them in. Failures raise
``LibraryError`` (a ValueError) naming the parameter and the reason. Angles are radians.
"""
from __future__ import annotations

import json
import math
from collections import namedtuple
from dataclasses import asdict, dataclass, make_dataclass
from typing import Any

import numpy as np


class LibraryError(ValueError):
    """A non-OK status from a C library, explained."""

    def __init__(self, status: int, code: str, reason: str, parameter: str | None = None,
                 index: int | None = None):
        self.status, self.code, self.parameter, self.index = status, code, parameter, index
        where = f"{parameter}: " if parameter else ""
        item = f" (batch item {index})" if index is not None else ""
        super().__init__(f"{where}{reason}{item}")


class Library:
    """The functions, parameters and status codes of one mechanism's compiled library."""

    def __init__(self, module):
        self.ffi, self.lib = module.ffi, module.lib
        self.SPEC = json.loads(self.ffi.string(self.lib.codegen_api_spec()).decode())
        self.PREFIX = self.SPEC["prefix"]
        self.TITLE = self.SPEC["title"]
        self.ROOT_KINDS = tuple(self.SPEC["root_kinds"])
        self.PARAMETER_NAMES = tuple(p["name"] for p in self.SPEC["parameters"])
        self.UNITS = {p["name"]: p["unit"] for p in self.SPEC["parameters"]}
        self.STATUS = {s["name"]: s["value"] for s in self.SPEC["statuses"]}
        self._status_names = {v: k for k, v in self.STATUS.items()}
        self._status_parameters = {s["value"]: s["parameters"] for s in self.SPEC["statuses"]}
        #: One parameter set (SI units); fields in the order of the C struct.
        self.Params = make_dataclass(f"{self.PREFIX}_params",
                                     [(n, float) for n in self.PARAMETER_NAMES], frozen=True)
        self.Params.__doc__ = f"Parameters of {self.TITLE}: " + ", ".join(
            f"{p['name']} [{p['unit']}] {p['description']}" for p in self.SPEC["parameters"])
        self.Params.library = self
        self.PARAMS_DTYPE = np.dtype([(n, np.float64) for n in self.PARAMETER_NAMES])
        self.FUNCTIONS = {
            f["name"]: Function(self, f["name"], f["summary"], f["equation"],
                                tuple((a["name"], a["size"]) for a in f["inputs"]),
                                tuple((o["name"], o["size"]) for o in f["outputs"]))
            for f in self.SPEC["functions"]}
        self.LibraryError = LibraryError

    def __getattr__(self, name: str) -> "Function":
        try:
            return self.__dict__["FUNCTIONS"][name]
        except KeyError:
            raise AttributeError(f"{self.__dict__.get('PREFIX', 'library')} has no function "
                                 f"{name!r}") from None

    def __dir__(self):
        return sorted(list(super().__dir__()) + list(self.FUNCTIONS))

    def __repr__(self) -> str:
        return f"<Library {self.PREFIX}: {self.TITLE}>"

    @property
    def has_polynomial(self) -> bool:
        """Whether G is algebraic, so that the polynomial route exists (isolation always does)."""
        return "sigma" in self.FUNCTIONS

    @property
    def modes(self) -> int:
        """The number of assembly modes (the enclosure's mode argument ranges below it)."""
        return int(self.SPEC["sizes"]["N_MODES"])

    def enclosure(self, params, lo: float, hi: float, mode: int = 0):
        """Rigorous bounds on G and G' over lo <= theta <= hi [rad] on an assembly mode:
        ((G_lo, G_hi), (dG_lo, dG_hi), flags); flags or-s 1 (a divisor may vanish), 2 (a
        square root may reach 0 or the mode may not exist on part of it), 4 (nowhere)."""
        theta = self.ffi.new("double[2]", [lo, hi])
        g, dg = self.ffi.new("double[2]"), self.ffi.new("double[2]")
        flags = self.ffi.new("unsigned *")
        status = getattr(self.lib, f"{self.PREFIX}_enclosure")(self._c_params(params), mode,
                                                               theta, g, dg, flags)
        self.check(status, self._as_mapping(params))
        return (g[0], g[1]), (dg[0], dg[1]), int(flags[0])

    def example_params(self, **overrides: float) -> Any:
        """The model's example parameters, with optional overrides by name."""
        values = {p["name"]: float(p["example"]) for p in self.SPEC["parameters"]}
        unknown = set(overrides) - set(values)
        if unknown:
            raise ValueError(f"unknown parameter(s): {', '.join(sorted(unknown))}; "
                             f"{self.PREFIX} has {', '.join(values)}")
        return self.Params(**{**values, **overrides})

    def params_array(self, sets) -> np.ndarray:
        """A structured array (the C struct's layout) from an iterable of Params or dicts."""
        rows = [tuple(getattr(s, n) if not isinstance(s, dict) else s[n]
                      for n in self.PARAMETER_NAMES) for s in sets]
        return np.array(rows, dtype=self.PARAMS_DTYPE)

    def error(self, status: int, params=None, index: int | None = None) -> LibraryError:
        reason = self.ffi.string(getattr(self.lib, f"{self.PREFIX}_status_message")(status))
        parameter = self._culprit(status, params) if params is not None else None
        return LibraryError(status, self._status_names.get(status, str(status)),
                            reason.decode(), parameter, index)

    def check(self, status: int, params=None, index: int | None = None) -> None:
        if status != self.STATUS["OK"]:
            raise self.error(status, params, index)

    def _culprit(self, status: int, params) -> str | None:
        """Name the parameter(s) behind a parameter failure."""
        if status == self.STATUS["ERR_NONFINITE_PARAM"]:
            return next((n for n in self.PARAMETER_NAMES if not math.isfinite(float(params[n]))),
                        None)
        return ", ".join(self._status_parameters.get(status, ())) or None

    def _c_params(self, params) -> Any:
        if isinstance(params, dict):
            params = self.Params(**params)
        return self.ffi.new(f"{self.PREFIX}_params *", asdict(params))

    @staticmethod
    def _as_mapping(params):
        return params if isinstance(params, dict) else asdict(params)

    def analyze(self, params=None, method: str = "auto"):
        """Every equilibrium, classified and linearised (see codegen.analysis)."""
        from .analysis import analyze
        return analyze(params if params is not None else self.example_params(), method)

    def analyze_batch(self, table, method: str = "auto"):
        from .analysis import analyze_batch
        return analyze_batch(table, self, method)


@dataclass(frozen=True)
class Function:
    """One C function of a library and its batch twin."""

    library: Library
    name: str
    summary: str
    equation: str
    inputs: tuple[tuple[str, int | None], ...]
    outputs: tuple[tuple[str, int | None], ...]

    @property
    def result_type(self):
        return namedtuple(f"{self.name}_result", [n for n, _ in self.outputs])

    def __call__(self, params, *args):
        if len(args) != len(self.inputs):
            names = ", ".join(n for n, _ in self.inputs)
            raise TypeError(f"{self.name}(params, {names}) takes {len(self.inputs)} inputs")
        if isinstance(params, np.ndarray) or any(
                np.ndim(a) > (1 if size else 0) for a, (_, size) in zip(args, self.inputs)):
            return self.batch(params, *args)
        return self._single(params, args)

    def _single(self, params, args):
        lib, ffi = self.library, self.library.ffi
        c_args = [lib._c_params(params)]
        for value, (name, size) in zip(args, self.inputs):
            if size:
                value = np.asarray(value, dtype=np.float64)
                if value.shape != (size,):
                    raise ValueError(f"{name} must have {size} values, got shape {value.shape}")
                c_args.append(ffi.new("double[]", value.tolist()))
            else:
                c_args.append(float(value))
        outs = [ffi.new(f"double[{size}]" if size else "double *") for _, size in self.outputs]
        status = getattr(lib.lib, f"{lib.PREFIX}_{self.name}")(*c_args, *outs)
        lib.check(status, lib._as_mapping(params))
        values = [np.frombuffer(ffi.buffer(o), dtype=np.float64).copy() if size else o[0]
                  for o, (_, size) in zip(outs, self.outputs)]
        return values[0] if len(values) == 1 else self.result_type(*values)

    def batch(self, params, *args, raise_on_error: bool = True):
        """Evaluate over arrays; returns (outputs, statuses) when raise_on_error is False."""
        lib, ffi = self.library, self.library.ffi
        lengths = [len(params)] if isinstance(params, np.ndarray) else []
        lengths += [np.atleast_2d(a).shape[0] if size else np.atleast_1d(a).shape[0]
                    for a, (_, size) in zip(args, self.inputs)]
        count = max(lengths, default=1)
        table = params if isinstance(params, np.ndarray) else lib.params_array([params])
        table = np.ascontiguousarray(np.broadcast_to(table, (count,)), dtype=lib.PARAMS_DTYPE)
        arrays = []
        for value, (name, size) in zip(args, self.inputs):
            shape = (count, size) if size else (count,)
            arrays.append(np.ascontiguousarray(np.broadcast_to(
                np.asarray(value, dtype=np.float64), shape)))
        outputs = [np.empty((count, size) if size else (count,)) for _, size in self.outputs]
        statuses = np.zeros(count, dtype=np.intc)
        getattr(lib.lib, f"{lib.PREFIX}_{self.name}_batch")(
            count, ffi.from_buffer(f"{lib.PREFIX}_params[]", table),
            *(ffi.from_buffer("double[]", a) for a in arrays),
            *(ffi.from_buffer("double[]", o, require_writable=True) for o in outputs),
            ffi.from_buffer(f"{lib.PREFIX}_status[]", statuses, require_writable=True))
        result = outputs[0] if len(outputs) == 1 else self.result_type(*outputs)
        if not raise_on_error:
            return result, statuses
        bad = np.flatnonzero(statuses != lib.STATUS["OK"])
        if bad.size:
            i = int(bad[0])
            lib.check(int(statuses[i]), {n: table[n][i] for n in lib.PARAMETER_NAMES}, index=i)
        return result
