"""One compiled mechanism library from Python, with plain floats or numpy batches.

A ``Library`` wraps the cffi module built from one mechanism's generated/ folder. Every C
function of its emission plan is a Python function of the library, by name, e.g.
``lib.sigma(params)`` or ``lib.linearisation(params, theta)``, with its own signature and
docstring (``help(lib.linearisation)``: every argument with its size and units, the
paper's equation, batches and errors). A call with scalars returns floats and 1-D arrays; a
call where ``params`` is a ``params_array`` (or any input has a leading batch dimension)
runs the C batch entry point over numpy arrays without copying them in. Failures raise
``LibraryError`` (a ValueError) naming the parameter, its value and the reason. Angles are
radians, every quantity SI.

Parameter sets (``lib.Params``) and multi-output results are picklable: they are rebuilt
from where their library came from (``api.load(name)`` or ``api.load_from(folder, name)``),
so they cross process boundaries (multiprocessing, concurrent.futures) and deep-copy.

What is computed with a library (analyses, sweeps, branches, simulations) builds on this
module, so its methods (``lib.analyze``, ``lib.branches``...) and the pickling by origin are
those of the subclass ``codegen.api.Library``, the class ``load`` and ``load_from`` give.
"""
from __future__ import annotations

import json
import math
import textwrap
from collections.abc import Callable, Iterable, Mapping
from dataclasses import make_dataclass
from operator import attrgetter
from types import ModuleType
from typing import Any, ClassVar, Protocol, cast

import numpy as np

from ..errors import LibraryError, plain, real_number
from .functions import Function, LibraryFunction

#: Where a library came from, to load it again in another process: ("load", NAME) for a
#: shipped mechanism, ("load_from", ABSOLUTE_FOLDER, NAME) for a user's build.
Origin = tuple[str, ...]

#: What a status re-run gets: a parameter set as a mapping; it returns the C status.
Rerun = Callable[[Mapping[str, float]], int]

#: The package the shipped libraries are built into (codegen._native_NAME).
_SHIPPED_PREFIX = f"{__package__}._native_"


class ParameterSet(Protocol):
    """One parameter set of a library: an instance of its ``Params`` dataclass, a frozen
    dataclass with one float field per parameter (SI units), whose class knows the library
    it belongs to."""

    library: ClassVar[Library]
    __dataclass_fields__: ClassVar[dict[str, Any]]


#: Where a function takes a parameter set, a mapping of every parameter name to its value
#: [SI units] also does.
ParamsLike = ParameterSet | Mapping[str, float]

def params_shown(values: Mapping[str, float], units: Mapping[str, str]) -> dict[str, float]:
    """Parameter values as a file shows them: an angle (unit rad) in degrees under NAME_deg,
    as every angle of a file is (a bare name would hold radians where the command line reads
    degrees), the rest SI under its own name."""
    return {(f"{name}_deg" if units.get(name) == "rad" else name):
            (math.degrees(value) if units.get(name) == "rad" else value)
            for name, value in values.items()}


class Library:
    """The functions, parameters and status codes of one mechanism's compiled library.

    Attributes: ``PREFIX`` (the C prefix, also the mechanism's name), ``TITLE``,
    ``PARAMETER_NAMES`` (in the C struct's order), ``UNITS`` (name -> SI unit),
    ``EXAMPLE`` (name -> the model's example value), ``Params`` (the parameter dataclass),
    ``PARAMS_DTYPE`` (the C struct as a numpy dtype), ``STATUS`` (status name -> value),
    ``FUNCTIONS`` (name -> the Python function of each C function; each is also an
    attribute: ``lib.linearisation``), ``SPEC`` (the generated NAME_api.json), ``origin``
    (how to load it again: see ``Origin``), ``ffi`` and ``lib`` (the cffi module's).
    """

    def __init__(self, module: ModuleType, origin: Origin | None = None) -> None:
        self.ffi, self.lib = module.ffi, module.lib
        self.SPEC: dict[str, Any] = json.loads(
            self.ffi.string(self.lib.codegen_api_spec()).decode())
        self.PREFIX: str = self.SPEC["prefix"]
        self.TITLE: str = self.SPEC["title"]
        self.origin: Origin | None = origin if origin is not None else _origin_of(module)
        self.ROOT_KINDS: tuple[str, ...] = tuple(self.SPEC["root_kinds"])
        self.PARAMETER_NAMES: tuple[str, ...] = tuple(p["name"] for p in self.SPEC["parameters"])
        self.UNITS: dict[str, str] = {p["name"]: p["unit"] for p in self.SPEC["parameters"]}
        self.EXAMPLE: dict[str, float] = {p["name"]: float(p["example"])
                                          for p in self.SPEC["parameters"]}
        self.STATUS: dict[str, int] = {s["name"]: s["value"] for s in self.SPEC["statuses"]}
        self._status_names = {v: k for k, v in self.STATUS.items()}
        self._status_parameters = {s["value"]: tuple(s["parameters"])
                                   for s in self.SPEC["statuses"]}
        self._module_name = module.__name__
        #: One parameter set (SI units); fields in the order of the C struct.
        self.Params: type = _params_class(self)
        getter = attrgetter(*self.PARAMETER_NAMES)
        #: A parameter set's values as a tuple, in the C struct's order.
        self._fields = cast(Callable[[ParameterSet], tuple[float, ...]],
                            getter if len(self.PARAMETER_NAMES) > 1 else lambda p: (getter(p),))
        self.PARAMS_DTYPE = np.dtype([(n, np.float64) for n in self.PARAMETER_NAMES])
        self.FUNCTIONS: dict[str, LibraryFunction] = {
            f["name"]: Function(self, f).python for f in self.SPEC["functions"]}
        self.LibraryError = LibraryError

    @property
    def dof(self) -> int:
        """The number of independent coordinates."""
        return int(self.SPEC.get("dof", 1))

    def __getattr__(self, name: str) -> LibraryFunction:
        try:
            return self.__dict__["FUNCTIONS"][name]
        except KeyError:
            raise AttributeError(f"{self.__dict__.get('PREFIX', 'library')} has no function "
                                 f"{name!r}") from None

    def __dir__(self) -> list[str]:
        return sorted(list(super().__dir__()) + list(self.FUNCTIONS))

    def __repr__(self) -> str:
        return f"<Library {self.PREFIX}: {self.TITLE}>"

    def __reduce__(self) -> tuple[Any, ...]:
        # What refers to a library (its Params, results) pickles it along, by its origin:
        # codegen.api.Library, which loads it again, does; this class cannot import api.
        raise TypeError(f"cannot pickle the library {self.PREFIX}: only one loaded by "
                        "codegen.api.load or load_from pickles")

    def __copy__(self) -> Library:
        return self   # one handle on a compiled module, with no state of its own to copy

    def __deepcopy__(self, memo: dict[int, Any]) -> Library:
        return self

    def _require_origin(self) -> Origin:
        if self.origin is None:
            raise TypeError(f"cannot pickle what belongs to the library {self.PREFIX}: it was "
                            "not loaded by codegen.api.load or load_from, so another process "
                            "could not load it again")
        return self.origin

    @property
    def has_polynomial(self) -> bool:
        """Whether G is algebraic, so that the polynomial route exists (isolation always does)."""
        return "sigma" in self.FUNCTIONS

    @property
    def modes(self) -> int:
        """The number of assembly modes (the enclosure's mode argument ranges below it)."""
        return int(self.SPEC["sizes"]["N_MODES"])

    def enclosure(self, params: ParamsLike, lo: float, hi: float, mode: int = 0
                  ) -> tuple[tuple[float, float], tuple[float, float], int]:
        """Rigorous bounds on G and G' over ``lo <= theta <= hi`` on an assembly mode.

        Arguments: ``params`` (a parameter set, SI units), ``lo``, ``hi`` (the interval of
        the independent angle [rad], ``lo <= hi``), ``mode`` (0 <= mode < ``modes``; mode 0
        is the mechanism as declared).

        Returns ``((G_lo, G_hi), (dG_lo, dG_hi), flags)``: G = dV/dtheta - Q_theta, the
        generalised force of the angle [N m], and its slope G' = dG/dtheta [N m/rad],
        outward rounded; ``flags`` or-s 1 (a divisor may vanish in the interval), 2 (a square
        root may reach 0, or the mode may not exist on part of it), 4 (the mode exists
        nowhere in it).

        Raises ``LibraryError`` naming the parameter (or ``mode``, or ``lo, hi``) at fault.
        """
        theta = self.ffi.new("double[2]", [lo, hi])
        g, dg = self.ffi.new("double[2]"), self.ffi.new("double[2]")
        flags = self.ffi.new("unsigned *")
        entry = getattr(self.lib, f"{self.PREFIX}_enclosure")

        def rerun(values: Mapping[str, float]) -> int:
            return entry(self._c_params(values), mode, theta, self.ffi.new("double[2]"),
                         self.ffi.new("double[2]"), self.ffi.new("unsigned *"))

        status = entry(self._c_params(params), mode, theta, g, dg, flags)
        if status == self.STATUS["ERR_ARGUMENT"]:
            bad = "mode" if not 0 <= mode < self.modes else "lo, hi"
            raise LibraryError(status, "ERR_ARGUMENT", self._reason(status), bad, values=(
                {"mode": mode} if bad == "mode" else {"lo": lo, "hi": hi}))
        self.check(status, params, rerun=rerun, inputs={"lo": lo, "hi": hi})
        return (g[0], g[1]), (dg[0], dg[1]), int(flags[0])

    def example_params(self, **overrides: float) -> ParameterSet:
        """The model's example parameters (SI units), with optional overrides by name, e.g.
        ``lib.example_params(F=100.0)``. Raises ValueError naming unknown parameters."""
        unknown = set(overrides) - set(self.EXAMPLE)
        if unknown:
            raise ValueError(f"unknown parameter(s): {', '.join(sorted(unknown))}; "
                             f"{self.PREFIX} has {', '.join(self.EXAMPLE)}")
        return self.Params(**{**self.EXAMPLE, **overrides})

    def params_array(self, sets: Iterable[ParamsLike]) -> np.ndarray:
        """A structured array (the C struct's layout: one float64 field per parameter, SI
        units) from an iterable of parameter sets or mappings: the ``params`` of a batch."""
        rows = [tuple(m[n] for n in self.PARAMETER_NAMES) for m in map(self._as_mapping, sets)]
        return np.array(rows, dtype=self.PARAMS_DTYPE)

    def table(self, params: Any) -> np.ndarray:
        """``params`` as a contiguous params_array, its fields matched by name: a structured
        array with exactly this library's parameters as fields, each of a floating type, in
        any order, one-dimensional (zero-dimensional: one set); or one Params or mapping.
        Anything else (a plain or integer array, a missing, extra or non-float field, a 2-D
        table, None) is a ValueError saying what is wrong."""
        if not isinstance(params, np.ndarray):
            if params is None or not (isinstance(params, Mapping)
                                      or hasattr(params, "__dataclass_fields__")):
                raise ValueError(f"params must be a params_array (a structured array with the "
                                 f"fields {', '.join(self.PARAMETER_NAMES)}), a Params or a "
                                 f"mapping, not {type(params).__name__}")
            return self.params_array([params])
        fields = params.dtype.names
        if fields is None:
            raise ValueError(f"a params table must be a structured array with one field per "
                             f"parameter ({', '.join(self.PARAMETER_NAMES)}), not a plain "
                             f"{params.dtype} array of shape {params.shape}: use "
                             f"{self.PREFIX}.params_array(...)")
        missing = [n for n in self.PARAMETER_NAMES if n not in fields]
        extra = [n for n in fields if n not in self.EXAMPLE]
        if missing or extra:
            raise ValueError("the params table's fields are not the parameters of "
                             f"{self.PREFIX}: " + "; ".join(
                                 f"{what} {', '.join(names)}" for what, names in
                                 (("missing", missing), ("unknown", extra)) if names))
        wrong = [f"{n} ({params.dtype[n]})" for n in fields
                 if params.dtype[n].kind != "f" or params.dtype[n].shape]
        if wrong:
            raise ValueError(f"params table fields must be floating-point scalars: "
                             f"{', '.join(wrong)}")
        if params.ndim > 1:
            raise ValueError(f"a params table must be one-dimensional (one set per item), "
                             f"not of shape {params.shape}")
        table = np.empty(params.shape or (1,), dtype=self.PARAMS_DTYPE)
        for name in self.PARAMETER_NAMES:
            table[name] = params[name]
        return table

    def error(self, status: int, params: ParamsLike | None = None, index: int | None = None,
              rerun: Rerun | None = None, inputs: Mapping[str, Any] | None = None
              ) -> LibraryError:
        """The LibraryError for a non-OK ``status`` of a call with ``params``.

        The error names the parameters responsible: those the status names (a failed
        requirement), the non-finite ones, or, for a status about no parameter of its own
        (an overflow, a singular state, every angle an equilibrium, the capacity), those
        whose example value makes ``rerun`` (the failed call, re-run with a modified
        parameter set; it returns the status) succeed or at least fail differently. Where
        the example's parameters fail as well, or an input is NaN or infinite, it names the
        ``inputs`` (the call's other arguments, by name). ``index`` is the batch item.
        The search runs when the message is first read.
        """
        reason, code = self._reason(status), self._status_names.get(status, str(status))
        if params is None:
            return LibraryError(status, code, reason, None, index)
        values = {n: float(v) for n, v in self._as_mapping(params).items()}
        return LibraryError(status, code, reason, index=index,
                            find=lambda: self._culprit(status, values, rerun, inputs))

    def check(self, status: int, params: ParamsLike | None = None, index: int | None = None,
              rerun: Rerun | None = None, inputs: Mapping[str, Any] | None = None) -> None:
        """Raise ``error(status, params, ...)``, a LibraryError naming the parameter
        responsible, unless status is OK (see ``error``)."""
        if status != self.STATUS["OK"]:
            raise self.error(status, params, index, rerun, inputs)

    def _reason(self, status: int) -> str:
        message = getattr(self.lib, f"{self.PREFIX}_status_message")(status)
        return self.ffi.string(message).decode()

    def _culprit(self, status: int, values: Mapping[str, float], rerun: Rerun | None,
                 inputs: Mapping[str, Any] | None) -> tuple[str | None, dict[str, Any]]:
        """(names, their values) of what caused a failure; (None, {}) if nothing is found."""
        inputs = dict(inputs or {})
        code = self._status_names.get(status)
        if code == "ERR_NONFINITE_PARAM":
            names = [n for n in self.PARAMETER_NAMES if not math.isfinite(values[n])]
        elif self._status_parameters.get(status):
            names = list(self._status_parameters[status])
        elif code == "ERR_NONFINITE":
            bad = [n for n, v in inputs.items() if not np.all(np.isfinite(v))]
            return (", ".join(bad) or None, {n: plain(inputs[n]) for n in bad})
        else:
            names = self._recompute(status, values, rerun) if rerun is not None else []
            if not names and rerun is not None and inputs:
                # the example's parameters fail too: the state the inputs describe is at fault
                return ", ".join(inputs), {n: plain(v) for n, v in inputs.items()}
        return ", ".join(names) or None, {n: values[n] for n in names}

    def _recompute(self, status: int, values: Mapping[str, float], rerun: Rerun) -> list[str]:
        """The parameters whose example values make a failed call succeed: those that do
        alone; else a set of them that does restored together (restored in order until the
        call succeeds, then each one put back that is not needed); else those that alone
        make it fail differently; [] if no parameter changes the outcome (the inputs of
        the call, or the example's own values, are at fault)."""
        ok, example = self.STATUS["OK"], self.EXAMPLE
        differing = [n for n in self.PARAMETER_NAMES if values[n] != example[n]]
        outcome = {n: rerun({**values, n: example[n]}) for n in differing}
        alone = [n for n in differing if outcome[n] == ok]
        if alone:
            return alone
        trial, restored = dict(values), []
        for n in differing:
            trial[n] = example[n]
            restored.append(n)
            if rerun(trial) == ok:
                needed = list(restored)
                for m in restored:
                    fewer = [x for x in needed if x != m]
                    if rerun({**values, **{x: example[x] for x in fewer}}) == ok:
                        needed = fewer
                return needed
        return [n for n in differing if outcome[n] != status]

    def _c_params(self, params: ParamsLike) -> Any:
        """A new C struct of the parameters (a Params, or a mapping of every name)."""
        if isinstance(params, Mapping):
            params = cast(ParameterSet, self.Params(**params))
        return self.ffi.new(f"{self.PREFIX}_params *", self._fields(params))

    def _as_mapping(self, params: ParamsLike) -> Mapping[str, float]:
        if isinstance(params, Mapping):
            return params
        return dict(zip(self.PARAMETER_NAMES, self._fields(params)))

    def rows(self, function: str, values: Mapping[str, float], inputs: tuple = ()
             ) -> np.ndarray:
        """``function`` at one parameter set over equal-length arrays of its scalar inputs,
        through its batch entry: one row of all its outputs (in order, arrays flattened) per
        input, NaN where the call reported an error; with no inputs, one row."""
        count = len(inputs[0]) if inputs else 1
        table = self.params_array([values] * count)
        result, statuses = self.FUNCTIONS[function].batch(table, *inputs, raise_on_error=False)
        parts = result if isinstance(result, tuple) else (result,)
        rows = np.column_stack([np.reshape(np.asarray(x, dtype=float), (count, -1))
                                for x in parts])
        rows[np.asarray(statuses) != self.STATUS["OK"]] = np.nan
        return rows

    def _params(self, params: ParamsLike | None) -> ParameterSet:
        """A Params of this library: the example for None, built from a mapping."""
        if params is None:
            return self.example_params()
        if isinstance(params, Mapping):
            return cast(ParameterSet, self.Params(**params))
        return params


def _origin_of(module: ModuleType) -> Origin | None:
    name = module.__name__
    return ("load", name[len(_SHIPPED_PREFIX):]) if name.startswith(_SHIPPED_PREFIX) else None


def _params_of(library: Any, values: dict[str, float]) -> Any:
    if not isinstance(library, Library):  # an api.Unloadable: the set fails on use
        return type("Params", (), {"library": library, "values": values})()
    return library.Params(**values)


def _real_fields(self: Any) -> None:
    """Every field a float: a number converts (an int, numpy's scalars), anything else is a
    ValueError naming the parameter (a string or None would fail later, unnamed)."""
    for name in type(self).library.PARAMETER_NAMES:
        value = getattr(self, name)
        if type(value) is not float:
            object.__setattr__(self, name, real_number(name, value))


def _reduce_params(self: ParameterSet) -> tuple[Any, ...]:
    library = type(self).library
    return (_params_of, (library, dict(zip(library.PARAMETER_NAMES, library._fields(self)))))


def _params_class(library: Library) -> type:
    """The frozen dataclass of one parameter set, documented field by field."""
    spec = library.SPEC["parameters"]
    width = max(len(f"{p['name']} [{p['unit']}]") for p in spec)
    lines = [f"{p['name']} [{p['unit']}]".ljust(width) + f"  {p['description']} "
             f"(example {float(p['example']):g})" for p in spec]
    intro = textwrap.fill(f"One parameter set of {library.TITLE}, in SI units: the C struct "
                          f"{library.PREFIX}_params, fields in its order.", 88)
    usage = textwrap.fill(
        f"library.example_params(**overrides) gives the example with overrides, "
        f"{library.PREFIX}_params(**every_field) any set. Frozen; it pickles and copies "
        "(rebuilt from the library's origin: codegen.api.load(name) or load_from(folder, "
        "name)). type(params).library is the library.", 88)
    doc = f"{intro}\n\nFields:\n    " + "\n    ".join(lines) + f"\n\n{usage}"
    cls = make_dataclass(f"{library.PREFIX}_params", [(p["name"], float) for p in spec],
                         frozen=True, namespace={"library": library, "__doc__": doc,
                                                 "__reduce__": _reduce_params,
                                                 "__post_init__": _real_fields})
    cls.__module__ = library._module_name
    return cls

