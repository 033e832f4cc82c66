"""The frequency response of a mechanism with n coordinates about a stable equilibrium: every
coordinate's amplitude and phase when a harmonic generalised force drives one of them.

``frequency_response(library, params)`` takes a stable equilibrium (the first, or the one
``equilibrium`` indexes in ``analyze``'s list), and evaluates the receptance
H(omega) = (K - omega^2 M + i omega B)^-1 of its linearisation in C (``NAME_receptance``) at
every circular frequency asked for, by default from 0 to three times its highest natural
frequency. Column ``drive`` of H is the response to a unit force on that coordinate.
``write`` saves the table as CSV or JSON; ``codegen.presentation.response`` draws it.
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import multibody
from .. import files
from .response import POINTS, UPTO


@dataclass(frozen=True, eq=False)
class MultibodyFrequencyResponse:
    library: Any
    equilibrium: multibody.MultibodyEquilibrium
    omega: np.ndarray   # [rad/s]
    H: np.ndarray       # (len(omega), n, n), complex
    drive: int          # the coordinate the harmonic force acts on

    @property
    def coordinates(self) -> list[str]:
        return [c["name"] for c in self.library.SPEC["coordinates"]]

    @property
    def frequency(self) -> np.ndarray:
        return self.omega / (2 * math.pi)

    @property
    def response(self) -> np.ndarray:
        """(len(omega), n): each coordinate's complex amplitude per unit force on ``drive``."""
        return self.H[:, :, self.drive]

    @property
    def natural_frequencies(self) -> np.ndarray:
        """[Hz]"""
        return self.equilibrium.frequencies / (2 * math.pi)


def frequency_response(library: Any, params: Any, omega: Any = None,
                       equilibrium: int | None = None, drive: int = 0,
                       points: int = POINTS, upto: float = UPTO) -> MultibodyFrequencyResponse:
    found = library.analyze(params).equilibria
    if equilibrium is None:
        stable = [e for e in found if e.stable]
        if not stable:
            raise ValueError("no stable equilibrium for these parameters: there is no "
                             "steady response to a harmonic force")
        e = stable[0]
    elif not 0 <= equilibrium < len(found):
        raise ValueError(f"equilibrium {equilibrium}: these parameters have {len(found)} "
                         f"equilibria (0 to {len(found) - 1})")
    elif not found[equilibrium].stable:
        raise ValueError(f"equilibrium {equilibrium} is {found[equilibrium].stability}: it has "
                         "no steady response to a harmonic force")
    else:
        e = found[equilibrium]
    if not 0 <= drive < library.dof:
        raise ValueError(f"drive: a coordinate index from 0 to {library.dof - 1}")
    if omega is None:
        omega = np.linspace(0.0, upto * float(np.nanmax(e.frequencies)), points)
    omega = np.array(omega, dtype=np.float64).ravel()
    if not np.all(np.isfinite(omega)) or np.any(omega < 0):
        raise ValueError("omega: finite frequencies >= 0 [rad/s]")
    return MultibodyFrequencyResponse(library, e, omega,
                                      multibody.receptance(library, params, e.theta, omega),
                                      drive)


def columns(response: MultibodyFrequencyResponse) -> list[str]:
    return ["frequency_hz", "omega"] + [f"{kind}_{name}" for name in response.coordinates
                                        for kind in ("amplitude", "phase_deg")]


def rows(response: MultibodyFrequencyResponse) -> np.ndarray:
    parts = [response.frequency, response.omega]
    for i in range(response.H.shape[1]):
        parts += [np.abs(response.response[:, i]), np.degrees(np.angle(response.response[:, i]))]
    return np.column_stack(parts)


def write_csv(stream: Any, response: MultibodyFrequencyResponse) -> None:
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(columns(response))
    for row in rows(response):
        writer.writerow([repr(float(x)) for x in row])


def to_dict(response: MultibodyFrequencyResponse) -> dict[str, Any]:
    """JSON-ready: the driven coordinate, the equilibrium, its natural frequencies [Hz] and a
    list per column of the table."""
    return {"mechanism": response.library.PREFIX,
            "drive": response.coordinates[response.drive],
            "equilibrium": response.equilibrium.theta.tolist(),
            "natural_frequencies_hz": response.natural_frequencies.tolist(),
            **dict(zip(columns(response), rows(response).T.tolist()))}


def write(response: MultibodyFrequencyResponse, path: str | Path) -> Path:
    """The table as .csv (``write_csv``) or .json (``to_dict``)."""
    return files.write_table(path, "a frequency response", lambda: to_dict(response),
                             lambda stream: write_csv(stream, response))

