"""Layer 6: one compiled mechanism library from Python, with plain floats or numpy batches.

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
"""
from __future__ import annotations

import inspect
import json
import keyword
import math
import textwrap
from collections import namedtuple
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import make_dataclass
from operator import attrgetter
from types import GenericAlias, ModuleType
from typing import Any, ClassVar, Protocol, cast

import numpy as np

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

#: A scalar input or output: a float, or an array of them for a batch.
Scalar = float | np.ndarray


class Argument(namedtuple("Argument", ["name", "size"])):
    """An input or output of a C function: the pair (name, size), size None for a scalar
    or the number of doubles of an array, and its ``description`` (what it is, with its
    unit in brackets, from the emission plan)."""

    name: str
    size: int | None
    description: str

    def __new__(cls, name: str, size: int | None, description: str = "") -> Argument:
        self = super().__new__(cls, name, size)
        self.description = description
        return self


class LibraryError(ValueError):
    """A non-OK status from a C library, explained.

    ``str(error)`` reads ``"NAME: reason (NAME=value, batch item i)"``, e.g.
    ``"k: a result is too large to represent (k=1e+300)"``. Attributes: ``status`` (the C
    status value), ``code`` (its name, e.g. ``"ERR_OVERFLOW"``), ``reason`` (the library's
    message), ``parameter`` (the names of the parameters, or inputs, responsible, comma
    separated; None where none is), ``values`` (their values), ``index`` (the batch item,
    or None). Which parameter is responsible is decided on first use of the message,
    ``parameter`` or ``values``: for a status that names no parameter of its own
    (an overflow, a singular state, ...) it takes re-running the failed call.
    """

    def __init__(self, status: int, code: str, reason: str, parameter: str | None = None,
                 index: int | None = None, values: Mapping[str, Any] | None = None, *,
                 find: Callable[[], tuple[str | None, dict[str, Any]]] | None = None) -> None:
        self.status, self.code, self.reason, self.index = status, code, reason, index
        self._parameter, self._values = parameter, dict(values or {})
        self._find = find
        super().__init__(self._message() if find is None else reason)

    def _resolve(self) -> None:
        find, self._find = self._find, None
        if find is not None:
            self._parameter, self._values = find()
            self.args = (self._message(),)

    def _message(self) -> str:
        where = f"{self._parameter}: " if self._parameter else ""
        notes = [f"{n}={_format_value(v)}" for n, v in self._values.items()]
        notes += [f"batch item {self.index}"] if self.index is not None else []
        return f"{where}{self.reason}" + (f" ({', '.join(notes)})" if notes else "")

    @property
    def parameter(self) -> str | None:
        """The parameter(s) or input(s) responsible, comma separated (None if unknown)."""
        self._resolve()
        return self._parameter

    @property
    def values(self) -> dict[str, Any]:
        """The values of those parameters or inputs (floats, or tuples for arrays)."""
        self._resolve()
        return dict(self._values)

    def __str__(self) -> str:
        self._resolve()
        return str(self.args[0])

    def __repr__(self) -> str:
        return f"{type(self).__name__}({str(self)!r})"

    def __reduce__(self) -> tuple[Any, ...]:
        self._resolve()
        return (type(self), (self.status, self.code, self.reason, self._parameter, self.index,
                             self._values))


def _format_value(value: Any) -> str:
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_format_value(v) for v in value) + "]"
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return repr(int(value))
    return repr(float(value))


def _plain(value: Any) -> float | tuple[float, ...]:
    """A float, or a tuple of floats for an array, for an error's values."""
    array = np.asarray(value, dtype=np.float64)
    return float(array) if array.ndim == 0 else tuple(float(x) for x in array.ravel())


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
        return (_library_of, (self._require_origin(),))

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
        rows = [tuple(self._as_mapping(s)[n] for n in self.PARAMETER_NAMES) for s in sets]
        return np.array(rows, dtype=self.PARAMS_DTYPE)

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
            return (", ".join(bad) or None, {n: _plain(inputs[n]) for n in bad})
        else:
            names = self._recompute(status, values, rerun) if rerun is not None else []
            if not names and rerun is not None and inputs:
                # the example's parameters fail too: the state the inputs describe is at fault
                return ", ".join(inputs), {n: _plain(v) for n, v in inputs.items()}
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

    def analyze(self, params: ParamsLike | None = None, method: analysis.Method = "auto"
                ) -> analysis.Analysis:
        """Every equilibrium of ``params`` (default: the example), classified and linearised,
        by the route ``method`` names: see ``codegen.analysis.analyze``. Angles in radians."""
        if params is None:
            return analysis.analyze(self.example_params(), method)
        if isinstance(params, Mapping):
            return analysis.analyze(cast(ParameterSet, self.Params(**params)), method)
        return analysis.analyze(params, method)

    def analyze_batch(self, table: np.ndarray, method: analysis.Method = "auto"
                      ) -> tuple[list[analysis.Analysis | None], np.ndarray]:
        """``analyze`` over a ``params_array``, in C: (analyses, statuses), None where an
        item failed (its status says why): see ``codegen.analysis.analyze_batch``."""
        return analysis.analyze_batch(table, self, method)


def _origin_of(module: ModuleType) -> Origin | None:
    name = module.__name__
    return ("load", name[len(_SHIPPED_PREFIX):]) if name.startswith(_SHIPPED_PREFIX) else None


def _library_of(origin: Origin) -> Library:
    """The library an origin names, loaded (once per process) as it was the first time."""
    from . import api

    if origin[0] == "load" and len(origin) == 2:
        return api.load(origin[1])
    if origin[0] == "load_from" and len(origin) == 3:
        return api.load_from(origin[1], origin[2])
    raise ValueError(f"unknown library origin {origin!r}")


def _params_of(origin: Origin, values: dict[str, float]) -> ParameterSet:
    return _library_of(origin).Params(**values)


def _reduce_params(self: ParameterSet) -> tuple[Any, ...]:
    library = type(self).library
    values = dict(zip(library.PARAMETER_NAMES, library._fields(self)))
    if library.origin is None:  # copy and deepcopy still work; pickle says why it cannot
        return (_params_of_library, (library, values))
    return (_params_of, (library.origin, values))


def _params_of_library(library: Library, values: dict[str, float]) -> ParameterSet:
    return library.Params(**values)


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
                                                 "__reduce__": _reduce_params})
    cls.__module__ = library._module_name
    return cls


# ------------------------------------------------------------------ functions and results


class LibraryFunction(Protocol):
    """What ``Library.FUNCTIONS`` holds: a Python function calling one C function, with its
    batch twin and its description. ``help()`` and ``inspect.signature`` show its
    arguments; its docstring their sizes and units."""

    __name__: str
    __signature__: inspect.Signature
    library: Library
    summary: str
    equation: str
    inputs: tuple[Argument, ...]
    outputs: tuple[Argument, ...]
    result_type: type | None
    batch: Callable[..., Any]

    def __call__(self, params: Any, *inputs: Any, **named: Any) -> Any: ...


def _result_of(origin: Origin, function: str, values: tuple[Any, ...]) -> tuple[Any, ...]:
    return _result_of_library(_library_of(origin), function, values)


def _result_of_library(library: Library, function: str, values: tuple[Any, ...]
                       ) -> tuple[Any, ...]:
    result_type = library.FUNCTIONS[function].result_type
    assert result_type is not None, f"{function} has one output, no result type"
    return cast(tuple[Any, ...], result_type(*values))


def _reduce_result(self: Any) -> tuple[Any, ...]:
    library = self._library
    if library.origin is None:  # copy and deepcopy still work; pickle says why it cannot
        return (_result_of_library, (library, self._function, tuple(self)))
    return (_result_of, (library.origin, self._function, tuple(self)))


def _python_name(name: str) -> str:
    """A C name as a Python argument name (a Python keyword gets a trailing underscore)."""
    return f"{name}_" if keyword.iskeyword(name) or name == "params" else name


class Function:
    """One C function of a library and its batch twin. ``python`` is the function
    ``Library.FUNCTIONS`` holds: a real Python function with this one's name, signature
    and docstring, calling ``__call__``."""

    def __init__(self, library: Library, spec: Mapping[str, Any]) -> None:
        self.library = library
        self.name: str = spec["name"]
        self.summary: str = spec["summary"]
        self.equation: str = spec["equation"]
        self.inputs = tuple(Argument(a["name"], a["size"], a.get("description", ""))
                            for a in spec["inputs"])
        self.outputs = tuple(Argument(o["name"], o["size"], o.get("description", ""))
                             for o in spec["outputs"])
        self.c_name = f"{library.PREFIX}_{self.name}"
        self._entry = getattr(library.lib, self.c_name)
        self._batch_entry = getattr(library.lib, f"{self.c_name}_batch")
        self.result_type: type | None = self._result_type() if len(self.outputs) > 1 else None
        self.python: LibraryFunction = self._python()

    # -- the Python face

    def _result_type(self) -> type:
        """The named tuple of the outputs, made once: instances pickle by the library's
        origin."""
        base = namedtuple(f"{self.name}_result",  # type: ignore[misc]  # a name from the spec
                          [o.name for o in self.outputs], module=self.library._module_name)
        for o in self.outputs:
            getattr(base, o.name).__doc__ = self._describe(o)
        fields = "\n".join(f"    {o.name}: {self._describe(o)}" for o in self.outputs)
        cls = type(base.__name__, (base,), {
            "__slots__": (), "__module__": self.library._module_name,
            "__doc__": f"The outputs of {self.library.PREFIX}.{self.name}: floats for one "
                       f"call, arrays with a leading batch dimension for a batch.\n\n"
                       f"Fields:\n{fields}",
            "__annotations__": {o.name: np.ndarray if o.size else Scalar
                                for o in self.outputs},
            "__reduce__": _reduce_result, "_library": self.library, "_function": self.name})
        return cls

    def _describe(self, x: Argument) -> str:
        size = f"array of {x.size} floats: " if x.size else ""
        return f"{size}{x.description or '(no description)'}"

    def _annotations(self) -> tuple[dict[str, Any], Any]:
        params = self.library.Params | np.ndarray
        args = {_python_name(a.name): (Sequence[float] | np.ndarray) if a.size else Scalar
                for a in self.inputs}
        result: Any = self.result_type
        if result is None:
            result = np.ndarray if self.outputs[0].size else Scalar
        return {"params": params, **args}, result

    def signature(self, batch: bool = False) -> inspect.Signature:
        """The Python signature: params, then the C inputs by name (batch: and the
        keyword raise_on_error)."""
        arguments, result = self._annotations()  # result: Any, an annotation object
        kind = inspect.Parameter.POSITIONAL_OR_KEYWORD
        parameters = [inspect.Parameter(n, kind, annotation=a) for n, a in arguments.items()]
        if batch:
            parameters.append(inspect.Parameter("raise_on_error", inspect.Parameter.KEYWORD_ONLY,
                                                default=True, annotation=bool))
            result = result | GenericAlias(tuple, (result, np.ndarray))  # (outputs, statuses)
        return inspect.Signature(parameters, return_annotation=result)

    def _doc(self, batch: bool = False) -> str:
        """The docstring: summary, equation, every argument and output with its size and
        units, batches, errors; wrapped to 88 columns."""
        lib, P = self.library, self.library.PREFIX
        units = ", ".join(f"{n} [{lib.UNITS[n]}]" for n in lib.PARAMETER_NAMES)
        out: list[str] = []

        def para(text: str, indent: int = 0) -> None:
            out.extend(textwrap.wrap(text, 88, initial_indent=" " * indent,
                                     subsequent_indent=" " * indent, break_long_words=False,
                                     break_on_hyphens=False) or [""])

        def entry(x: Argument, what: str) -> None:
            kind = f"array of {x.size} floats" if x.size else "float"
            shape = f"(n, {x.size})" if x.size else "(n,)"
            para(f"{what}: {kind}; in a batch, shape {shape}", 4)
            para(x.description or "(no description)", 8)

        para(self.summary)
        para("")
        if self.equation:
            para(f"The paper's equation {self.equation}.")
        para(f"C: {self.c_name} (one call), {self.c_name}_batch (a batch).")
        if batch:
            para("")
            para("The batch form: every argument may carry a leading dimension n (params as "
                 "a params_array of n sets); they broadcast against each other and each "
                 "output gains it.")
        para("")
        para("Arguments:")
        para(f"params: {P}_params, a mapping of every parameter to its value, or (a batch) "
             "a params_array of n sets", 4)
        para(f"the mechanism's parameters, SI units: {units}", 8)
        for a in self.inputs:
            entry(a, _python_name(a.name))
        if batch:
            para("raise_on_error: bool, keyword only (default True)", 4)
            para("False: return (outputs, statuses) instead of raising", 8)
        para("")
        if self.result_type is not None:
            para(f"Returns a {self.result_type.__name__}, a named tuple of:")
        else:
            para("Returns:")
        for o in self.outputs:
            entry(o, o.name)
        if batch:
            para("With raise_on_error=False: (outputs, statuses), statuses an int array of "
                 "the C status of each item (0: OK); the outputs of a failed item are "
                 "undefined.")
        para("")
        para("Batches:")
        para(f"{self.name}(...) runs {self.c_name}_batch when params is a params_array or "
             "an input carries a leading batch dimension; the items run independently in C. "
             "The first failing item raises, naming its index; "
             f"{self.name}.batch(..., raise_on_error=False) returns (outputs, statuses) "
             "instead.", 4)
        para("")
        para("Raises:")
        para("LibraryError (a ValueError) on a non-OK status, naming the parameter(s) "
             "responsible, their values and, in a batch, the item: e.g. 'k: a result is too "
             "large to represent (k=1e+300)'. Its code is the status name:", 4)
        statuses = {s["name"]: s for s in lib.SPEC["statuses"]}
        generic = ["ERR_NONFINITE_PARAM"] + (["ERR_NONFINITE"] if self.inputs else []) + [
            "ERR_SINGULAR_STATE", "ERR_OVERFLOW"]
        for name in generic + [s for s, v in statuses.items() if v["parameters"]]:
            if name in statuses:
                para(f"{name}: {statuses[name]['message']}", 8)
        para("ValueError if an array input has the wrong size; TypeError on a missing or "
             "unexpected argument.", 4)
        return "\n".join(out)

    def _python(self) -> LibraryFunction:
        """A real function: its own name, qualified name, signature, annotations and doc."""
        signature, call = self.signature(), self.__call__
        positional = len(self.inputs) + 1

        def function(*args: Any, **named: Any) -> Any:
            if named or len(args) != positional:
                args = signature.bind(*args, **named).args
            return call(*args)

        batch_signature, batch = self.signature(batch=True), self.batch

        def batch_function(*args: Any, raise_on_error: bool = True, **named: Any) -> Any:
            if named or len(args) != positional:
                args = batch_signature.bind(*args, **named).args
            return batch(*args, raise_on_error=raise_on_error)

        faces: tuple[tuple[Any, str, inspect.Signature, str], ...] = (
            (function, self.name, signature, self._doc()),
            (batch_function, f"{self.name}.batch", batch_signature, self._doc(batch=True)))
        for f, name, sig, doc in faces:
            short = name.rpartition(".")[2]
            qualname = f"{self.library.PREFIX}.{name}"
            f.__code__ = f.__code__.replace(co_name=short)  # tracebacks name the function
            if hasattr(f.__code__, "co_qualname"):  # Python 3.11+
                f.__code__ = getattr(f.__code__, "replace")(co_qualname=qualname)
            f.__name__, f.__qualname__ = short, qualname
            f.__module__ = self.library._module_name
            f.__doc__, f.__signature__ = doc, sig
            f.__annotations__ = {p.name: p.annotation for p in sig.parameters.values()}
            f.__annotations__["return"] = sig.return_annotation
        face = cast(Any, function)
        face.batch = batch_function
        for attr in ("library", "summary", "equation", "inputs", "outputs", "result_type",
                     "c_name"):
            setattr(face, attr, getattr(self, attr))
        return cast(LibraryFunction, face)

    # -- calls

    def __call__(self, params: ParamsLike | np.ndarray, *args: Any) -> Any:
        if len(args) != len(self.inputs):
            names = ", ".join(a.name for a in self.inputs)
            raise TypeError(f"{self.name}(params, {names}) takes {len(self.inputs)} inputs")
        if isinstance(params, np.ndarray) or any(
                np.ndim(a) > (1 if x.size else 0) for a, x in zip(args, self.inputs)):
            return self.batch(params, *args)
        return self._single(params, args)

    def _c_inputs(self, args: Sequence[Any]) -> list[Any]:
        ffi, c_args = self.library.ffi, []
        for value, x in zip(args, self.inputs):
            if x.size:
                value = np.asarray(value, dtype=np.float64)
                if value.shape != (x.size,):
                    raise ValueError(f"{x.name} must have {x.size} values, got shape "
                                     f"{value.shape}")
                c_args.append(ffi.new("double[]", value.tolist()))
            else:
                c_args.append(float(value))
        return c_args

    def _outputs(self) -> list[Any]:
        return [self.library.ffi.new(f"double[{o.size}]" if o.size else "double *")
                for o in self.outputs]

    def _rerun(self, c_args: list[Any]) -> Rerun:
        """The call with these inputs, as a function of the parameters: its status."""
        return lambda values: self._entry(self.library._c_params(values), *c_args,
                                          *self._outputs())

    def _single(self, params: ParamsLike, args: Sequence[Any]) -> Any:
        lib, ffi = self.library, self.library.ffi
        c_args = self._c_inputs(args)
        outs = self._outputs()
        status = self._entry(lib._c_params(params), *c_args, *outs)
        if status != lib.STATUS["OK"]:
            raise lib.error(status, params, rerun=self._rerun(c_args),
                            inputs={x.name: v for x, v in zip(self.inputs, args)})
        values = [np.frombuffer(ffi.buffer(o), dtype=np.float64).copy() if x.size else o[0]
                  for o, x in zip(outs, self.outputs)]
        return values[0] if self.result_type is None else self.result_type(*values)

    def batch(self, params: ParamsLike | np.ndarray, *args: Any,
              raise_on_error: bool = True) -> Any:
        """Evaluate over arrays; returns (outputs, statuses) when raise_on_error is False."""
        lib, ffi = self.library, self.library.ffi
        lengths = [len(params)] if isinstance(params, np.ndarray) else []
        lengths += [np.atleast_2d(a).shape[0] if x.size else np.atleast_1d(a).shape[0]
                    for a, x in zip(args, self.inputs)]
        count = max(lengths, default=1)
        table = params if isinstance(params, np.ndarray) else lib.params_array([params])
        table = np.ascontiguousarray(np.broadcast_to(table, (count,)), dtype=lib.PARAMS_DTYPE)
        arrays = []
        for value, x in zip(args, self.inputs):
            shape = (count, x.size) if x.size else (count,)
            arrays.append(np.ascontiguousarray(np.broadcast_to(
                np.asarray(value, dtype=np.float64), shape)))
        outputs = [np.empty((count, o.size) if o.size else (count,)) for o in self.outputs]
        statuses = np.zeros(count, dtype=np.intc)
        self._batch_entry(
            count, ffi.from_buffer(f"{lib.PREFIX}_params[]", table),
            *(ffi.from_buffer("double[]", a) for a in arrays),
            *(ffi.from_buffer("double[]", o, require_writable=True) for o in outputs),
            ffi.from_buffer(f"{lib.PREFIX}_status[]", statuses, require_writable=True))
        result = outputs[0] if self.result_type is None else self.result_type(*outputs)
        if not raise_on_error:
            return result, statuses
        bad = np.flatnonzero(statuses != lib.STATUS["OK"])
        if bad.size:
            i = int(bad[0])
            item = [a[i] for a in arrays]
            lib.check(int(statuses[i]), {n: float(table[n][i]) for n in lib.PARAMETER_NAMES},
                      index=i, rerun=self._rerun(self._c_inputs(item)),
                      inputs={x.name: v for x, v in zip(self.inputs, item)})
        return result


# analysis imports Library from here: imported last, as a module, so either may come first.
from . import analysis  # noqa: E402
