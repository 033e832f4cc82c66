"""Layer 6: the compiled library from Python, with plain floats or numpy batches.

Every C function of the emission plan is reachable by name, e.g. ``api.sigma(params)``
or ``api.linearisation(params, theta)``. A call with scalars returns floats and 1-D
arrays; a call where ``params`` is a ``params_array`` (or any input has a leading batch
dimension) runs the C batch entry point over numpy arrays without copying them in.
Failures raise ``LibraryError`` (a ValueError) naming the parameter and the reason.
"""
from __future__ import annotations

import json
import math
from collections import namedtuple
from dataclasses import asdict, dataclass, make_dataclass
from typing import Any

import numpy as np

from ._native import ffi, lib

SPEC = json.loads(ffi.string(lib.codegen_api_spec()).decode())
PREFIX = SPEC["prefix"]
PARAMETER_NAMES = tuple(p["name"] for p in SPEC["parameters"])
STATUS = {s["name"]: s["value"] for s in SPEC["statuses"]}
_STATUS_NAMES = {v: k for k, v in STATUS.items()}

#: One parameter set (SI units); fields in the order of the C struct.
Params = make_dataclass("Params", [(n, float) for n in PARAMETER_NAMES], frozen=True)
Params.__doc__ = "Parameters of the mechanism: " + ", ".join(
    f"{p['name']} [{p['unit']}] {p['description']}" for p in SPEC["parameters"])
PARAMS_DTYPE = np.dtype([(n, np.float64) for n in PARAMETER_NAMES])


def example_params(**overrides: float) -> Any:
    """The paper's Table 2, with optional overrides by name."""
    values = {p["name"]: float(p["example"]) for p in SPEC["parameters"]}
    unknown = set(overrides) - set(values)
    if unknown:
        raise ValueError(f"unknown parameter(s): {', '.join(sorted(unknown))}")
    return Params(**{**values, **overrides})


def params_array(sets) -> np.ndarray:
    """A structured array (the C struct's layout) from an iterable of Params or dicts."""
    rows = [tuple(getattr(s, n) if not isinstance(s, dict) else s[n] for n in PARAMETER_NAMES)
            for s in sets]
    return np.array(rows, dtype=PARAMS_DTYPE)


class LibraryError(ValueError):
    """A non-OK status from the C library, explained."""

    def __init__(self, status: int, parameter: str | None = None, index: int | None = None):
        self.status = status
        self.code = _STATUS_NAMES.get(status, str(status))
        self.parameter = parameter
        self.index = index
        reason = ffi.string(lib.doughty_status_message(status)).decode()
        where = f"{parameter}: " if parameter else ""
        item = f" (batch item {index})" if index is not None else ""
        super().__init__(f"{where}{reason}{item}")


_STATUS_PARAMETERS = {s["value"]: s["parameters"] for s in SPEC["statuses"]}


def _culprit(status: int, params) -> str | None:
    """Name the parameter(s) behind a parameter failure."""
    if status == STATUS["ERR_NONFINITE_PARAM"]:
        return next((n for n in PARAMETER_NAMES if not math.isfinite(float(params[n]))), None)
    return ", ".join(_STATUS_PARAMETERS.get(status, ())) or None


def check(status: int, params=None, index: int | None = None) -> None:
    if status != STATUS["OK"]:
        parameter = _culprit(status, params) if params is not None else None
        raise LibraryError(status, parameter, index)


def _c_params(params) -> Any:
    if isinstance(params, dict):
        params = Params(**params)
    return ffi.new(f"{PREFIX}_params *", asdict(params))


def _as_mapping(params):
    return params if isinstance(params, dict) else asdict(params)


@dataclass(frozen=True)
class Function:
    """One C function of the library and its batch twin."""

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
        c_args = [_c_params(params)]
        for value, (name, size) in zip(args, self.inputs):
            if size:
                value = np.asarray(value, dtype=np.float64)
                if value.shape != (size,):
                    raise ValueError(f"{name} must have {size} values, got shape {value.shape}")
                c_args.append(ffi.new("double[]", value.tolist()))
            else:
                c_args.append(float(value))
        outs = [ffi.new(f"double[{size}]" if size else "double *") for _, size in self.outputs]
        status = getattr(lib, f"{PREFIX}_{self.name}")(*c_args, *outs)
        check(status, _as_mapping(params))
        values = [np.frombuffer(ffi.buffer(o), dtype=np.float64).copy() if size else o[0]
                  for o, (_, size) in zip(outs, self.outputs)]
        return values[0] if len(values) == 1 else self.result_type(*values)

    def batch(self, params, *args, raise_on_error: bool = True):
        """Evaluate over arrays; returns (outputs, statuses) when raise_on_error is False."""
        lengths = [len(params)] if isinstance(params, np.ndarray) else []
        lengths += [np.atleast_2d(a).shape[0] if size else np.atleast_1d(a).shape[0]
                    for a, (_, size) in zip(args, self.inputs)]
        count = max(lengths, default=1)
        table = params if isinstance(params, np.ndarray) else params_array([params])
        table = np.ascontiguousarray(np.broadcast_to(table, (count,)), dtype=PARAMS_DTYPE)
        arrays = []
        for value, (name, size) in zip(args, self.inputs):
            shape = (count, size) if size else (count,)
            arrays.append(np.ascontiguousarray(np.broadcast_to(
                np.asarray(value, dtype=np.float64), shape)))
        outputs = [np.empty((count, size) if size else (count,)) for _, size in self.outputs]
        statuses = np.zeros(count, dtype=np.intc)
        getattr(lib, f"{PREFIX}_{self.name}_batch")(
            count, ffi.from_buffer(f"{PREFIX}_params[]", table),
            *(ffi.from_buffer("double[]", a) for a in arrays),
            *(ffi.from_buffer("double[]", o, require_writable=True) for o in outputs),
            ffi.from_buffer(f"{PREFIX}_status[]", statuses, require_writable=True))
        result = outputs[0] if len(outputs) == 1 else self.result_type(*outputs)
        if not raise_on_error:
            return result, statuses
        bad = np.flatnonzero(statuses != STATUS["OK"])
        if bad.size:
            i = int(bad[0])
            check(int(statuses[i]), {n: table[n][i] for n in PARAMETER_NAMES}, index=i)
        return result


FUNCTIONS = {
    f["name"]: Function(f["name"], f["summary"], f["equation"],
                        tuple((a["name"], a["size"]) for a in f["inputs"]),
                        tuple((o["name"], o["size"]) for o in f["outputs"]))
    for f in SPEC["functions"]
}


def __getattr__(name: str) -> Function:
    try:
        return FUNCTIONS[name]
    except KeyError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None


def __dir__():
    return sorted(list(globals()) + list(FUNCTIONS))
