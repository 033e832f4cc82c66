"""The frequency response about a stable equilibrium: how far the mechanism swings when a
harmonic torque drives it, against the forcing frequency (the picture that keeps a machine's
running speeds away from resonance).

``frequency_response(params)`` takes a stable equilibrium of ``params`` (the analysis'
first, or the one ``equilibrium`` indexes) and evaluates the receptance
H(omega) = 1 / (K - omega^2 M + i omega B) of its linearisation in the library's C
(``PREFIX_frequency_response``: the runtime's codegen_response.c and codegen_modal.c) at
every circular frequency asked for, by default from 0 to three times the natural frequency.
It returns a ``FrequencyResponse``: omega [rad/s] and H [rad/(N m)] as numpy arrays, with
the amplitude |H|, the phase and the equilibrium's natural frequency and damping ratio.
``write`` saves the table as CSV or JSON; ``codegen.presentation.response`` draws amplitude
and phase against the forcing frequency [Hz] with the natural frequency marked.
"""
from __future__ import annotations

import csv
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import files
from .analysis import Equilibrium, Method, analyze, library_of_params
from .library import Library, ParameterSet, params_shown
from .simulation import is_stable

#: The file types ``write`` writes (by the path's suffix).
FORMATS = (".csv", ".json")

#: The default table: this many frequencies, from 0 to UPTO times the natural frequency.
POINTS = 801
UPTO = 3.0


@dataclass(frozen=True, eq=False)
class FrequencyResponse:
    """The receptance H = 1 / (K - omega^2 M + i omega B) [rad/(N m)] about ``equilibrium``
    (its M, B, K) at the circular frequencies omega [rad/s]."""

    params: ParameterSet
    equilibrium: Equilibrium
    omega: np.ndarray
    H: np.ndarray

    @property
    def library(self) -> Library:
        return type(self.params).library

    @property
    def frequency(self) -> np.ndarray:
        """The forcing frequencies [Hz]."""
        return self.omega / (2 * math.pi)

    @property
    def amplitude(self) -> np.ndarray:
        """|H| [rad/(N m)]: the swing per unit torque amplitude."""
        return np.abs(self.H)

    @property
    def phase(self) -> np.ndarray:
        """arg H [rad], in [-pi, 0] for omega >= 0: how far the swing lags the torque."""
        return np.angle(self.H)

    @property
    def natural_frequency(self) -> float:
        """The undamped natural frequency omega_n / (2 pi) [Hz] of the equilibrium."""
        return float(self.equilibrium.omega_n.real) / (2 * math.pi)

    @property
    def peak(self) -> tuple[float, float]:
        """(frequency [Hz], |H| [rad/(N m)]) of the largest amplitude in the table."""
        i = int(np.argmax(self.amplitude))
        return float(self.frequency[i]), float(self.amplitude[i])


def about(params: ParameterSet, equilibrium: int | None = None, method: Method = "auto"
          ) -> Equilibrium:
    """The equilibrium of ``params`` the response is taken about: the ``equilibrium``-th of
    ``analyze(params, method).equilibria`` (ValueError unless it is stable), or the first
    stable one (ValueError if there is none)."""
    found = analyze(params, method).equilibria
    if equilibrium is None:
        stable = [e for e in found if is_stable(e)]
        if not stable:
            raise ValueError("no stable equilibrium for these parameters: there is no "
                             "steady response to a harmonic torque")
        return stable[0]
    if not 0 <= equilibrium < len(found):
        raise ValueError(f"equilibrium {equilibrium}: these parameters have {len(found)} "
                         f"equilibria (0 to {len(found) - 1})")
    e = found[equilibrium]
    if not is_stable(e):
        raise ValueError(f"equilibrium {equilibrium} (theta_E = {math.degrees(e.theta):.4f} "
                         f"deg) is {e.stability}: it has no steady response to a harmonic torque")
    return e


def receptance(params: ParameterSet, theta: float, omega: np.ndarray) -> np.ndarray:
    """H(omega) [rad/(N m)] of the linearisation at theta [rad], in C, as a complex array."""
    library = library_of_params(params)
    omega = np.ascontiguousarray(omega, dtype=np.float64)
    re, im = np.empty_like(omega), np.empty_like(omega)
    ffi = library.ffi
    entry = getattr(library.lib, f"{library.PREFIX}_frequency_response")

    def call(values: Any, re: np.ndarray = re, im: np.ndarray = im) -> int:
        return int(entry(library._c_params(values), theta, omega.size,
                         ffi.from_buffer("double[]", omega), ffi.from_buffer("double[]", re),
                         ffi.from_buffer("double[]", im)))

    library.check(call(params), params, rerun=lambda values: call(
        values, np.empty_like(omega), np.empty_like(omega)), inputs={"theta": theta})
    return re + 1j * im


def frequency_response(params: ParameterSet, omega: Any = None, equilibrium: int | None = None,
                       method: Method = "auto", points: int = POINTS, upto: float = UPTO
                       ) -> FrequencyResponse:
    """The receptance about a stable equilibrium of ``params`` (see ``about``) at ``omega``
    [rad/s] (default: ``points`` frequencies from 0 to ``upto`` times its natural frequency)."""
    e = about(params, equilibrium, method)
    if omega is None:
        if points < 2 or not upto > 0:
            raise ValueError("points: at least 2; upto: positive")
        omega = np.linspace(0.0, upto * float(e.omega_n.real), points)
    omega = np.array(omega, dtype=np.float64).ravel()
    if not np.all(np.isfinite(omega)) or np.any(omega < 0):
        raise ValueError("omega: finite frequencies >= 0 [rad/s]")
    return FrequencyResponse(params, e, omega, receptance(params, e.theta, omega))


# --------------------------------------------------------------------------- files

def to_dict(response: FrequencyResponse) -> dict[str, Any]:
    """JSON-ready: frequencies in Hz and rad/s, H as amplitude, phase [deg] and parts."""
    e = response.equilibrium
    return {
        "mechanism": response.library.PREFIX, "params": params_shown(asdict(response.params), response.library.UNITS),
        "equilibrium": {"theta_deg": math.degrees(e.theta), "M": e.M, "B": e.B, "K": e.K,
                        "natural_frequency_hz": response.natural_frequency,
                        "zeta": float(e.zeta.real)},
        "frequency_hz": response.frequency.tolist(), "omega": response.omega.tolist(),
        "amplitude": response.amplitude.tolist(),
        "phase_deg": np.degrees(response.phase).tolist(),
        "H_re": response.H.real.tolist(), "H_im": response.H.imag.tolist(),
    }


COLUMNS = ("frequency_hz", "omega", "amplitude", "phase_deg", "H_re", "H_im")


def write_csv(stream: Any, response: FrequencyResponse) -> None:
    """A row per frequency: COLUMNS (Hz, rad/s, rad/(N m), deg, rad/(N m), rad/(N m))."""
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in zip(response.frequency, response.omega, response.amplitude,
                   np.degrees(response.phase), response.H.real, response.H.imag):
        writer.writerow([repr(float(x)) for x in row])


def write(response: FrequencyResponse, path: str | Path) -> Path:
    """The table as .csv (``write_csv``) or .json (``to_dict``)."""
    return files.write_table(path, "a frequency response", lambda: to_dict(response),
                             lambda stream: write_csv(stream, response))
