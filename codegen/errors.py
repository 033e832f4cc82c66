"""A C library's non-OK status as a Python exception that names its cause."""
from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np


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


def plain(value: Any) -> float | tuple[float, ...]:
    """A float, or a tuple of floats for an array, for an error's values."""
    array = np.asarray(value, dtype=np.float64)
    return float(array) if array.ndim == 0 else tuple(float(x) for x in array.ravel())


def real_number(name: str, value: Any) -> float:
    """value as a float, or a ValueError naming it; bools and strings are not numbers."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        raise ValueError(f"{name}: {value!r} is not a number")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: {value!r} is not a number") from None
