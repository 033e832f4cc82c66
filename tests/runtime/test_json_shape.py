"""One shape for `mechvib analyze --json` and ``to_dict()`` (issue 50, "Two conventions"):
whatever the number of coordinates, the same top-level keys, ``params`` and ``method`` beside
the list of equilibria (``roots``), every angle in degrees under a ``_deg`` name, no radians
under a bare name, no NaN or Infinity. One Python API (``analyze(params, method)`` for any
library, ``to_dict`` on both results) and one stability vocabulary."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from codegen.api import load
from codegen.runtime import multibody
from codegen.runtime.analysis import (KINDS, STABILITY, UNCERTAINTIES, MultibodyAnalysis,
                                      UncertainBox, analyze, coordinates_of)

REPO = Path(__file__).resolve().parents[2]

#: The top level of every analysis's JSON, in order.
TOP = ["params", "method", "coordinates", "sigma", "roots", "singular_roots_deg",
       "unassembled_roots_deg", "uncertain"]
#: What every root has, whatever the number of coordinates.
ROOT = {"kind", "genuine", "certified", "mode", "M", "B", "K", "omega_n", "zeta",
        "eigenvalues", "stability"}
NAMES = ["doughty", "four_bar", "double_pendulum", "flexible_doughty"]


def refuse(token):
    raise ValueError(f"non-standard JSON constant {token}")


@pytest.fixture(scope="module", params=NAMES)
def printed(request):
    """(library, the JSON `mechvib analyze --json` prints for its example)."""
    out = subprocess.run([sys.executable, "-m", "codegen", "analyze", "--mechanism",
                          request.param, "--json"], cwd=REPO, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    return load(request.param), json.loads(out.stdout, parse_constant=refuse)


def is_pair(x) -> bool:
    return (isinstance(x, list) and len(x) == 2
            and all(v is None or isinstance(v, float) for v in x))


def check_shape(library, data) -> None:
    """The rules every analysis's JSON keeps."""
    assert list(data) == TOP
    # params as a file shows them: an angle parameter in degrees under NAME_deg
    expected = {(f"{n}_deg" if library.UNITS[n] == "rad" else n) for n in library.PARAMETER_NAMES}
    assert set(data["params"]) == expected
    for name, value in library.EXAMPLE.items():
        shown = data["params"][f"{name}_deg" if library.UNITS[name] == "rad" else name]
        assert shown == pytest.approx(math.degrees(value) if library.UNITS[name] == "rad"
                                      else value)
    assert data["method"] in ("polynomial", "isolate")
    assert data["method"] == "polynomial" or data["sigma"] == []
    coordinates = data["coordinates"]
    assert len(coordinates) == library.dof
    for c in coordinates:
        assert set(c) == {"name", "unit", "key"}
        assert c["key"] == (f"{c['name']}_deg" if c["unit"] == "deg" else c["name"])
    keys = [c["key"] for c in coordinates]
    intervals = [f"{c['name']}_interval_deg" if c["unit"] == "deg"
                 else f"{c['name']}_interval" for c in coordinates]
    bare = {c["name"] for c in coordinates if c["unit"] == "deg"}
    assert data["roots"]
    for root in data["roots"]:
        assert ROOT <= set(root) and not bare & set(root)   # no radians under a bare name
        for key, interval in zip(keys, intervals):
            lo, hi = root[interval]
            assert lo <= root[key] <= hi
        assert root["kind"] in KINDS and isinstance(root["genuine"], bool)
        assert isinstance(root["certified"], bool)
        modes = [root["omega_n"]] if library.dof == 1 else root["omega_n"]
        zetas = [root["zeta"]] if library.dof == 1 else root["zeta"]
        assert len(modes) == len(zetas) == library.dof
        assert all(map(is_pair, modes + zetas + root["eigenvalues"]))
        assert len(root["eigenvalues"]) == 2 * library.dof
        if root["kind"] == "extraneous":
            assert root["stability"] is None
            continue
        assert root["stability"] in STABILITY
        for re, im in modes:   # an unstable mode: imaginary, never NaN or null
            assert re is not None and im is not None and (re == 0 or im == 0)
        if root["stability"] == "unstable":
            assert any(im > 0 for _, im in modes)
        if root["stability"] == "stable":
            assert all(im == 0 and re > 0 for re, im in modes)
    for u in data["uncertain"]:
        assert u["kind"] in UNCERTAINTIES and all(len(u[i]) == 2 for i in intervals)


def test_every_mechanisms_json_has_the_one_shape(printed):
    library, data = printed
    check_shape(library, data)
    if library.dof > 1:
        assert data["method"] == "isolate"
        assert all(r["kind"] == "equilibrium" and r["genuine"] and r["certified"]
                   for r in data["roots"])


def test_the_printed_json_is_the_analysis(printed):
    """The command line prints to_dict() of the analysis, its coordinates in degrees."""
    library, data = printed
    result = library.analyze()
    assert data == json.loads(json.dumps(result.to_dict()))
    keys = [c.key for c in coordinates_of(library)]
    for root, e in zip(data["roots"], result.roots):
        theta = [e.theta] if library.dof == 1 else list(e.theta)
        assert [root[k] for k in keys] == [math.degrees(t) for t in theta]


def test_both_shapes_share_their_top_level_keys():
    one, several = load("doughty").analyze().to_dict(), load("double_pendulum").analyze().to_dict()
    assert list(one) == list(several) == TOP
    assert one["coordinates"] == [{"name": "theta", "unit": "deg", "key": "theta_deg"}]
    assert [c["key"] for c in several["coordinates"]] == ["theta_1_deg", "delta_deg"]


def test_an_unstable_mode_is_imaginary_in_json_and_table():
    """The upright double pendulum: its first mode's omega_n = i sqrt(-omega^2), its zeta
    imaginary as one coordinate's is (B / (2 M omega_n)), never NaN."""
    lib = load("double_pendulum")
    result = lib.analyze({**lib.EXAMPLE, "k_1": 20.0})
    upright = next(e for e in result.equilibria if e.stability == "unstable")
    w2 = upright.omega_squared[0]
    assert w2 < 0 and upright.omega_n[0] == pytest.approx(1j * math.sqrt(-w2))
    phi = upright.shapes[:, 0]
    assert upright.zeta[0] == pytest.approx(phi @ upright.B @ phi / (2 * upright.omega_n[0]))
    assert upright.zeta[1] == upright.modal_damping[1]   # a stable mode: the C's own
    data = result.to_dict()
    root = data["roots"][result.equilibria.index(upright)]
    assert root["omega_n"][0] == [0.0, math.sqrt(-w2)]
    out = subprocess.run([sys.executable, "-m", "codegen", "analyze", "--mechanism",
                          "double_pendulum", "--set", "k_1=20"], cwd=REPO, capture_output=True,
                         text=True, timeout=300)
    row = next(line for line in out.stdout.splitlines() if line.startswith("2 "))
    assert "nan" not in out.stdout and f"{math.sqrt(-w2):.6g} i" in row


def test_uncertain_boxes_name_each_coordinate():
    lib = load("double_pendulum")
    result = lib.analyze()
    box = UncertainBox(np.array([0.1, -0.2]), np.array([0.2, -0.1]), "at the end of a range")
    data = MultibodyAnalysis(result.params, result.coordinates, result.equilibria, (box,)
                             ).to_dict()
    assert data["uncertain"] == [{"theta_1_interval_deg": [math.degrees(0.1), math.degrees(0.2)],
                                  "delta_interval_deg": [math.degrees(-0.2), math.degrees(-0.1)],
                                  "kind": "at the end of a range"}]


def test_one_analyze_for_any_library():
    """analysis.analyze(params, method) works for any library; "polynomial" is refused with
    several coordinates; Library.analyze and multibody.analyze (an alias) are the same."""
    lib = load("double_pendulum")
    params = lib.example_params(k_1=20.0)
    for method in ("auto", "isolate"):
        result = analyze(params, method)
        assert isinstance(result, MultibodyAnalysis) and result.method == "isolate"
        assert result.params == params and result.roots == result.equilibria
    with pytest.raises(ValueError, match="several coordinates there is no polynomial"):
        analyze(params, "polynomial")
    with pytest.raises(ValueError, match="method must be one of"):
        analyze(params, "magic")
    expected = analyze(params).to_dict()
    assert lib.analyze(params).to_dict() == expected
    assert multibody.analyze(lib, params).to_dict() == expected
    assert multibody.analyze(lib, {**lib.EXAMPLE, "k_1": 20.0}).to_dict() == expected
    batch, statuses = lib.analyze_batch(lib.params_array([params, params]))
    assert list(statuses) == [0, 0] and [a.to_dict() for a in batch] == [expected] * 2
    assert not hasattr(result, "as_dict")


def test_one_stability_vocabulary():
    """The words of stability are one tuple for every number of coordinates: the tables'
    codes index it, and an undecided equilibrium of several coordinates is "undecided" in
    its table too, never "marginal" (which is one coordinate's decided verdict)."""
    assert STABILITY == ("stable", "marginal", "unstable", "undecided")
    lib = load("double_pendulum")
    sets = lib.params_array([{**lib.EXAMPLE, "k_1": k} for k in (5.0, 20.0, 40.0)])
    table = lib.analyze_table(sets)
    for s in range(len(sets)):
        single = lib.analyze({n: float(sets[n][s]) for n in lib.PARAMETER_NAMES})
        rows = table.roots[table.roots["set"] == s]
        assert [STABILITY[c] for c in rows["stability"]] == [e.stability for e in single.roots]
    assert list(multibody._STABILITY_CODES) == [STABILITY.index(w) for w in
                                                ("undecided", "unstable", "stable")]
