"""What the gallery and the random-mechanism tests share: loading a model file as the command
line does, the angles to compare at, the emission plan's G, e0 and e2 as functions, and the
comparison against ``model_reference`` with its tolerance.
"""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import mpmath
import numpy as np
import sympy as sp

MODELS = Path(__file__).resolve().parents[1] / "models"

#: Relative agreement required of G, M, B (relative to max(|reference|, the scale of the
#: values compared): near a zero of G its size elsewhere is what rounding is measured by).
RTOL = 1e-7

#: Offsets from the range's centre [deg]: every quadrant, both sides of +-90 (a pole of the
#: slotted lever) and close to both ends of the range (centre - 180, centre + 180].
OFFSETS_DEG = (-179.999, -179.0, -150.0, -120.0, -95.0, -85.0, -60.0, -30.0, -1.0, 1.0, 30.0,
               60.0, 85.0, 95.0, 120.0, 150.0, 179.0, 179.999, 180.0)


def load_model(name: str):
    """The Mechanism of tests/models/NAME.py (its build()), imported as a user file."""
    path = MODELS / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"gallery_{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.build()


def example(mechanism) -> dict[str, float]:
    return {p.symbol.name: float(p.example_value) for p in mechanism.parameters}


def angles(reference) -> list[float]:
    """OFFSETS_DEG from the centre of a Reference's range."""
    return [reference.centre + math.radians(d) for d in OFFSETS_DEG]


class PlanValues:
    """G (equilibrium_residual), e0 and e2 (reduced_coefficients) of the emission plan: the
    expressions printed to C, evaluated in mpmath at 30 digits."""

    def __init__(self, mechanism):
        from codegen.compiler.derivation import derive
        from codegen.compiler.emission.plan import build_plan

        plan = build_plan(derive(mechanism))
        residual = plan.function("equilibrium_residual")
        reduced = plan.function("reduced_coefficients")
        G = residual.explicit(residual.outputs[0].exprs)[0]
        e0, _, e2 = reduced.explicit(reduced.outputs[0].exprs)
        (theta,) = residual.inputs[0].symbols
        self._f = sp.lambdify([theta, *mechanism.symbols], [G, e0, e2], modules="mpmath")
        self._names = [p.symbol.name for p in mechanism.parameters]

    def __call__(self, params: dict, theta: float) -> tuple[float, float, float]:
        with mpmath.workdps(30):
            return tuple(float(v) for v in self._f(mpmath.mpf(theta),
                                                  *(mpmath.mpf(params[n]) for n in self._names)))


def mismatches(mine: dict, reference: dict) -> list[str]:
    """Each quantity (name -> values at the same angles) outside RTOL of the reference,
    relative to max(|reference value|, the median |reference value| of that quantity)."""
    out = []
    for name, ref in reference.items():
        ref, got = np.asarray(ref, dtype=float), np.asarray(mine[name], dtype=float)
        scale = np.maximum(np.abs(ref), np.median(np.abs(ref)))
        bad = ~(np.abs(got - ref) <= RTOL * scale)
        out += [f"{name}[{i}]: {got[i]!r} vs reference {ref[i]!r}" for i in np.nonzero(bad)[0]]
    return out
