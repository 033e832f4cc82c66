"""One C function of a library as a real Python function.

``Function`` calls the C function (one set, or its batch twin over numpy arrays) and makes
the face ``Library.FUNCTIONS`` holds: a plain function with the C function's name, a
signature with type hints, and a docstring giving every input and output with its size and
units, the paper's equation, batches and errors. Multi-output results are named tuples,
one class per function, that pickle by their library's origin. ``params`` None is the
model's example (``library.example_params()``), as for the library's other functions; an
n x n matrix (M, B, K of a mechanism with n coordinates) is returned as one.
"""
from __future__ import annotations

import inspect
import keyword
import textwrap
from collections import namedtuple
from collections.abc import Callable, Mapping, Sequence
from types import GenericAlias
from typing import TYPE_CHECKING, Any, Protocol, cast

import numpy as np

from ..errors import real_number

if TYPE_CHECKING:
    from .library import Library, ParamsLike, Rerun

#: A scalar input or output: a float, or an array of them for a batch.
Scalar = float | np.ndarray

#: The functions whose output is an n x n matrix of a mechanism with n coordinates, stored
#: row-major (compiler/emission/multibody.py: mass_matrix, damping_matrix, stiffness_matrix).
MATRIX_SUFFIX = "_matrix"


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


def _result_of(library: Library, function: str, values: tuple[Any, ...]) -> tuple[Any, ...]:
    result_type = library.FUNCTIONS[function].result_type
    assert result_type is not None, f"{function} has one output, no result type"
    return cast(tuple[Any, ...], result_type(*values))


def _reduce_result(self: Any) -> tuple[Any, ...]:
    return (_result_of, (self._library, self._function, tuple(self)))


def _as_matrix(shape: tuple[int, ...]) -> str:
    """', R x C' for an output returned as a matrix, else ''."""
    return f", {shape[0]} x {shape[1]}" if len(shape) == 2 else ""


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
        #: The shape of each output of one call: () for a float, (size,), or (n, n) for a
        #: matrix of n coordinates.
        self.shapes = tuple(self._shape(o) for o in self.outputs)
        self.result_type: type | None = self._result_type() if len(self.outputs) > 1 else None
        self.python: LibraryFunction = self._python()

    def _shape(self, x: Argument) -> tuple[int, ...]:
        n = self.library.dof
        if x.size == n * n and self.name.endswith(MATRIX_SUFFIX):
            return (n, n)
        return (x.size,) if x.size else ()

    # -- the Python face

    def _result_type(self) -> type:
        """The named tuple of the outputs, made once: instances pickle by the library's
        origin."""
        base = namedtuple(f"{self.name}_result",  # type: ignore[misc]  # a name from the spec
                          [o.name for o in self.outputs], module=self.library._module_name)
        for o, shape in zip(self.outputs, self.shapes):
            getattr(base, o.name).__doc__ = self._describe(o, shape)
        fields = "\n".join(f"    {o.name}: {self._describe(o, shape)}"
                           for o, shape in zip(self.outputs, self.shapes))
        cls = type(base.__name__, (base,), {
            "__slots__": (), "__module__": self.library._module_name,
            "__doc__": f"The outputs of {self.library.PREFIX}.{self.name}: floats for one "
                       f"call, arrays with a leading batch dimension for a batch.\n\n"
                       f"Fields:\n{fields}",
            "__annotations__": {o.name: np.ndarray if o.size else Scalar
                                for o in self.outputs},
            "__reduce__": _reduce_result, "_library": self.library, "_function": self.name})
        return cls

    def _describe(self, x: Argument, shape: tuple[int, ...]) -> str:
        size = f"array of {x.size} floats{_as_matrix(shape)}: " if x.size else ""
        return f"{size}{x.description or '(no description)'}"

    def _annotations(self, batch: bool = False) -> tuple[dict[str, Any], Any]:
        params = self.library.Params | np.ndarray if batch else \
            self.library.Params | np.ndarray | None
        args = {_python_name(a.name): (Sequence[float] | np.ndarray) if a.size else Scalar
                for a in self.inputs}
        result: Any = self.result_type
        if result is None:
            result = np.ndarray if self.outputs[0].size else Scalar
        return {"params": params, **args}, result

    def signature(self, batch: bool = False) -> inspect.Signature:
        """The Python signature: params, then the C inputs by name (batch: and the
        keyword raise_on_error)."""
        arguments, result = self._annotations(batch)  # result: Any, an annotation object
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

        def entry(x: Argument, what: str, shape: tuple[int, ...]) -> None:
            kind = f"array of {x.size} floats{_as_matrix(shape)}" if x.size else "float"
            batch_shape = ", ".join(["n", *map(str, shape)]) if shape else "n,"
            para(f"{what}: {kind}; in a batch, shape ({batch_shape})", 4)
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
        para(f"params: {P}_params, a mapping of every parameter to its value, "
             + ("" if batch else "None (the example, lib.example_params()), ")
             + "or (a batch) a params_array of n sets", 4)
        para(f"the mechanism's parameters, SI units: {units}", 8)
        for a in self.inputs:
            entry(a, _python_name(a.name), (a.size,) if a.size else ())
        if batch:
            para("raise_on_error: bool, keyword only (default True)", 4)
            para("False: return (outputs, statuses) instead of raising", 8)
        para("")
        if self.result_type is not None:
            para(f"Returns a {self.result_type.__name__}, a named tuple of:")
        else:
            para("Returns:")
        for o, shape in zip(self.outputs, self.shapes):
            entry(o, o.name, shape)
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

    def __call__(self, params: ParamsLike | np.ndarray | None, *args: Any) -> Any:
        if len(args) != len(self.inputs):
            names = ", ".join(a.name for a in self.inputs)
            raise TypeError(f"{self.name}(params, {names}) takes {len(self.inputs)} inputs")
        if params is None:
            params = self.library.example_params()
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
                c_args.append(real_number(x.name, value))
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
        values = [np.frombuffer(ffi.buffer(o), dtype=np.float64).reshape(shape).copy()
                  if x.size else o[0] for o, x, shape in zip(outs, self.outputs, self.shapes)]
        return values[0] if self.result_type is None else self.result_type(*values)

    def batch(self, params: ParamsLike | np.ndarray, *args: Any,
              raise_on_error: bool = True) -> Any:
        """Evaluate over arrays; returns (outputs, statuses) when raise_on_error is False."""
        lib, ffi = self.library, self.library.ffi
        table = lib.table(params)
        lengths = [len(table)] if isinstance(params, np.ndarray) else []
        lengths += [np.atleast_2d(a).shape[0] if x.size else np.atleast_1d(a).shape[0]
                    for a, x in zip(args, self.inputs)]
        count = max(lengths, default=1)
        table = np.ascontiguousarray(np.broadcast_to(table, (count,)))
        arrays = []
        for value, x in zip(args, self.inputs):
            shape = (count, x.size) if x.size else (count,)
            arrays.append(np.ascontiguousarray(np.broadcast_to(
                np.asarray(value, dtype=np.float64), shape)))
        outputs = [np.empty((count, *shape)) for shape in self.shapes]
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
