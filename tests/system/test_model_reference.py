"""The generic reference of ``model_reference`` must be trusted before it judges the gallery:

* on Doughty's mechanism it finds the paper's six equilibria (Table 3's genuine rows, angles
  as test_table3 restores them and with its tolerances), with Table 3's M_EQ and stability;
* on the four shipped mechanisms its equilibria and G equal those of the hand-written
  references of ``reference_mechanisms`` (a second implementation: geometric guesses and
  per-mechanism formulas, where this one reads the Mechanism data);
* on the slotted lever (issue 26) it finds the issue's equilibria, -149.4215 and 0.7649 deg,
  and its G, K, M, B equal the closed form of that one-loop mechanism (y = d tan(theta)).
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))   # whatever pytest's import mode
import reference_mechanisms as hand_written  # noqa: E402
from gallery import example, load_model  # noqa: E402
from model_reference import Reference, angle_gap  # noqa: E402

from codegen.compiler.model import doughty, four_bar, slider_crank, torsion_pendulum  # noqa: E402

SHIPPED = {m.__name__.rsplit(".", 1)[1]: m for m in (doughty, four_bar, slider_crank,
                                                     torsion_pendulum)}

#: Table 3's genuine rows: printed angle as restored [deg], its tolerance [deg] (half a unit
#: in the last digit, or test_table3's ANGLE_TOLERANCE), printed M_EQ, stable (K > 0).
TABLE3_GENUINE = [
    ("12.4726", 5e-5, "2.5812", True),
    ("-8.8980", 1e-4, "2.5803", True),
    ("-0.7032", 5e-5, "2.5793", False),
    ("-92.3711", 3e-4, "2.6205", False),
    ("176.715", 5e-4, "2.5794", True),
    ("92.5475", 3e-4, "2.6205", False),
]


@pytest.fixture(scope="module")
def shipped_references():
    cache = {}

    def get(name):
        if name not in cache:
            mechanism = SHIPPED[name].build()
            cache[name] = Reference(mechanism, example(mechanism))
        return cache[name]

    return get


@pytest.fixture(scope="module")
def doughty_equilibria(shipped_references):
    return shipped_references("doughty").equilibria()


def test_doughty_equilibria_are_table3s(doughty_equilibria):
    found = sorted(doughty_equilibria)
    assert len(found) == len(TABLE3_GENUINE), [math.degrees(t) for t in found]
    for printed, tolerance, _, _ in TABLE3_GENUINE:
        gap = min(abs(math.degrees(angle_gap(t, math.radians(float(printed))))) for t in found)
        assert gap <= tolerance, (printed, gap)


def test_doughty_table3_M_and_stability(shipped_references, doughty_equilibria):
    reference = shipped_references("doughty")
    for printed, _, M, stable in TABLE3_GENUINE:
        theta = min(doughty_equilibria, key=lambda t: angle_gap(t, math.radians(float(printed))))
        v = reference.values(theta)
        half_unit = 0.5 * 10.0 ** -len(M.split(".")[1])
        assert abs(float(v.M) - float(M)) <= half_unit, (printed, float(v.M), M)
        assert (v.K > 0) == stable, (printed, float(v.K))
        assert abs(float(v.G)) <= 1e-12 * abs(float(v.K))   # the root to ~1e-15 rad


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_equilibria_equal_the_hand_written_reference(name, shipped_references):
    mine = shipped_references(name).equilibria()
    theirs = hand_written.REFERENCES[name].equilibria(None, +1)
    assert len(mine) == len(theirs), ([math.degrees(t) for t in mine],
                                      [math.degrees(t) for t in theirs])
    assert all(angle_gap(a, b) <= 1e-10 for a, b in zip(mine, theirs))


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_G_equals_the_hand_written_reference(name, shipped_references):
    reference = shipped_references(name)
    theirs = hand_written.REFERENCES[name]
    for theta in reference.centre + np.linspace(-math.pi, math.pi, 17)[1:] + 0.01:
        v = reference.values(theta)
        if v is None:
            assert not theirs.assembles(None, theta), theta
            continue
        G = theirs.generalized_force(None, theta, +1)
        with mpmath.workdps(40):   # both are good to about 30 digits
            assert abs(v.G - G) <= 1e-20 * max(1, abs(G)), (theta, float(v.G), float(G))


# --------------------------------------------------------------------------- slotted lever


SLOTTED = dict(l=1.0, m=2.0, m_b=1.0, d=0.4, k=400.0, l_0=0.3, x_A=0.9, y_A=0.2, c=5.0, g=9.81)


def slotted_closed_form(theta: float, h: float = 1e-6, h2: float = 1e-4) -> dict[str, float]:
    """The slotted lever by hand: the block at y = d tan(theta), so
    V = m g l/2 sin + m_b g d tan + k/2 (|(d, y) - A| - l_0)^2, M = m l^2/3 + m_b (dy)^2,
    B = c (dy)^2 with dy = d / cos^2; G and K by central differences of V (steps h, h2)."""
    p = SLOTTED

    def V(t):
        y = p["d"] * math.tan(t)
        spring = math.hypot(p["d"] - p["x_A"], y - p["y_A"])
        return (p["m"] * p["g"] * p["l"] / 2 * math.sin(t) + p["m_b"] * p["g"] * y
                + p["k"] / 2 * (spring - p["l_0"]) ** 2)

    dy = p["d"] / math.cos(theta) ** 2
    return {"G": (V(theta + h) - V(theta - h)) / (2 * h),
            "K": (V(theta + h2) - 2 * V(theta) + V(theta - h2)) / h2**2,
            "M": p["m"] * p["l"] ** 2 / 3 + p["m_b"] * dy**2, "B": p["c"] * dy**2}


@pytest.fixture(scope="module")
def slotted():
    mechanism = load_model("slotted_lever")
    assert example(mechanism) == SLOTTED
    return Reference(mechanism, SLOTTED)


def test_slotted_lever_equilibria_are_the_issues(slotted):
    found = [math.degrees(t) for t in slotted.equilibria()]
    assert found == pytest.approx([-149.4215, 0.7649], abs=5e-5)


@pytest.mark.parametrize("degrees", [-170.0, -135.0, -100.0, -45.0, 10.0, 45.0, 100.0, 135.0])
def test_slotted_lever_values_equal_the_closed_form(slotted, degrees):
    v = slotted.values(math.radians(degrees))
    hand = slotted_closed_form(math.radians(degrees))
    for name, rtol in (("G", 1e-8), ("K", 1e-6), ("M", 1e-13), ("B", 1e-13)):
        assert float(getattr(v, name)) == pytest.approx(hand[name], rel=rtol, abs=1e-9), name
