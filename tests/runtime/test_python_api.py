"""The Python API as a user meets it (issue 10): every C function a real Python function with
its own signature, annotations and docstring (units, sizes, the paper's equation, batches,
errors); parameter sets, results and analyses that pickle across processes; units in the
result types; every error naming the parameter responsible, overflow included."""
from __future__ import annotations

import copy
import inspect
import json
import multiprocessing
import pickle
import pydoc
import shutil
import subprocess
import sys
import time
import typing
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

import codegen
import codegen.runtime.analysis
import codegen.runtime.api
import codegen.presentation
import codegen.runtime.branches
import codegen.runtime.folds
import codegen.runtime.joining
import codegen.runtime.library
import codegen.runtime.sweep
from codegen.runtime.analysis import Analysis, Equilibrium, Uncertain, analyze
from codegen.api import LibraryError, load, load_from, shipped

DOUGHTY = load("doughty")
LIBRARIES = {name: load(name) for name in shipped()}
GENERATED = Path(__file__).resolve().parents[2] / "generated"


def _every_function():
    return [(name, f) for name, lib in sorted(LIBRARIES.items())
            for f in sorted(lib.SPEC["functions"], key=lambda f: f["name"])]


# --------------------------------------------------------------------------- 1. functions


@pytest.mark.parametrize("library, spec", _every_function(),
                         ids=[f"{n}-{f['name']}" for n, f in _every_function()])
def test_every_c_function_is_a_documented_python_function(library, spec):
    lib = LIBRARIES[library]
    f = lib.FUNCTIONS[spec["name"]]
    assert getattr(lib, spec["name"]) is f
    assert inspect.isfunction(f) and inspect.isfunction(f.batch)
    assert f.__name__ == spec["name"] and f.__qualname__ == f"{library}.{spec['name']}"
    assert f.__code__.co_name == spec["name"]  # tracebacks name it
    signature = inspect.signature(f)
    assert list(signature.parameters) == ["params"] + [a["name"] for a in spec["inputs"]]
    assert all(p.annotation is not inspect.Parameter.empty
               for p in signature.parameters.values())
    assert signature.return_annotation is not inspect.Signature.empty
    hints = typing.get_type_hints(f)
    assert set(hints) == set(signature.parameters) | {"return"}
    assert hints["params"] == lib.Params | np.ndarray | None   # None: the example
    assert typing.get_type_hints(f.batch)["params"] == lib.Params | np.ndarray
    for a in spec["inputs"]:
        assert hints[a["name"]] == (Sequence[float] | np.ndarray if a["size"]
                                    else float | np.ndarray)
    if len(spec["outputs"]) > 1:
        assert hints["return"] is f.result_type
        assert f.result_type._fields == tuple(o["name"] for o in spec["outputs"])
    batch = inspect.signature(f.batch)
    assert list(batch.parameters)[:-1] == list(signature.parameters)
    assert batch.parameters["raise_on_error"].kind is inspect.Parameter.KEYWORD_ONLY
    doc = inspect.getdoc(f)
    assert doc.startswith(spec["summary"].split()[0])
    assert f"{library}_{spec['name']}_batch" in doc and "LibraryError" in doc
    if spec["equation"]:
        assert f"equation {spec['equation']}" in doc
    flat = " ".join(doc.split())  # the docstring is wrapped
    for x in spec["inputs"] + spec["outputs"]:
        assert x["description"] and " ".join(x["description"].split()) in flat, x
        assert f"{x['name']}: " + (f"array of {x['size']} floats" if x["size"] else "float") \
            in flat
    for name, unit in lib.UNITS.items():
        assert f"{name} [{unit}]" in flat


def test_help_shows_the_signature_units_and_equation():
    f = DOUGHTY.linearisation
    text = pydoc.render_doc(f, renderer=pydoc.plaintext)
    assert str(inspect.signature(f)) in text
    assert text.splitlines()[2].startswith(
        "linearisation(params: codegen._native_doughty.doughty_params | numpy.ndarray | None, "
        "theta: float | numpy.ndarray) -> codegen._native_doughty.linearisation_result")
    for needle in ("theta", "equilibrium angle theta_E [rad]", "M_EQ [kg m^2]",
                   "B_EQ [N m s]", "K_EQ [N m]", "(46)-(53)", "doughty_linearisation_batch",
                   "raise_on_error=False", "LibraryError", "ERR_OVERFLOW",
                   "k must not be negative", "H [m]", "g [m/s^2]"):
        assert needle in text, needle
    assert "Function(" not in text and "dataclass" not in text


def test_functions_take_keywords_and_check_their_arguments():
    lib, p = DOUGHTY, DOUGHTY.example_params()
    assert lib.linearisation(params=p, theta=0.3) == lib.linearisation(p, 0.3)
    assert lib.linearisation(p, theta=0.3) == lib.linearisation(p, 0.3)
    with pytest.raises(TypeError, match="theta"):
        lib.linearisation(p)
    with pytest.raises(TypeError, match="omega"):
        lib.linearisation(p, 0.3, omega=1.0)
    table = lib.params_array([p, p])
    values, statuses = lib.linearisation.batch(table, theta=[0.1, 0.2], raise_on_error=False)
    assert list(statuses) == [0, 0]
    assert values.K[1] == lib.linearisation(p, 0.2).K
    with pytest.raises(ValueError, match="coords must have 5 values"):
        lib.energies(p, [0.0] * 4, [0.0] * 5)


def test_result_types_are_made_once_and_documented():
    lib, p = DOUGHTY, DOUGHTY.example_params()
    one, other = lib.linearisation(p, 0.1), lib.linearisation(p, 0.2)
    batch = lib.linearisation(lib.params_array([p]), [0.1])
    assert type(one) is type(other) is type(batch) is lib.linearisation.result_type
    assert type(one).__name__ == "linearisation_result"
    assert type(one).M.__doc__ == "M_EQ [kg m^2]"
    assert "K: K_EQ [N m]" in type(one).__doc__
    assert lib.sigma.result_type is None and isinstance(lib.sigma(p), np.ndarray)


def test_params_class_documents_every_field():
    for lib in LIBRARIES.values():
        Params = lib.Params
        assert Params.__name__ == f"{lib.PREFIX}_params"
        assert Params.__annotations__ == {n: float for n in lib.PARAMETER_NAMES}
        assert typing.get_type_hints(Params) == {n: float for n in lib.PARAMETER_NAMES}
        doc = inspect.getdoc(Params)
        for p in lib.SPEC["parameters"]:
            line = next(x for x in doc.splitlines() if x.split()[:1] == [p["name"]])
            assert f"[{p['unit']}]" in line and p["description"] in line, line
        assert f"{lib.TITLE}, in SI units" in " ".join(doc.split())
        assert str(inspect.signature(Params)).startswith(
            f"({lib.PARAMETER_NAMES[0]}: float, {lib.PARAMETER_NAMES[1]}: float")


def test_library_methods_are_documented_with_units():
    lib = DOUGHTY
    assert "[rad]" in inspect.getdoc(lib.enclosure) and "[N m]" in inspect.getdoc(lib.enclosure)
    for method in (lib.example_params, lib.params_array, lib.error, lib.check):
        assert "SI" in inspect.getdoc(method) or "parameter" in inspect.getdoc(method)
    assert "radians" in inspect.getdoc(lib.analyze)
    assert "params_array" in inspect.getdoc(lib.analyze_batch)


PUBLIC_MODULES = (codegen.runtime.library, codegen.runtime.analysis, codegen.runtime.api,
                  codegen.runtime.sweep, codegen.runtime.branches, codegen.runtime.folds,
                  codegen.runtime.joining, codegen.presentation.branches,
                  codegen.presentation.drawing, codegen.presentation.figures,
                  codegen.presentation.motion, codegen.presentation.response)


def _public_callables():
    seen = []
    for module in PUBLIC_MODULES:
        for name, obj in vars(module).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
                continue
            obj = inspect.unwrap(obj) if callable(obj) and not inspect.isclass(obj) else obj
            if inspect.isfunction(obj):
                seen.append((f"{module.__name__}.{name}", obj))
            elif inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    public = not attr.startswith("_") or attr in ("__init__", "__call__")
                    if isinstance(member, property):
                        member = member.fget
                    if public and inspect.isfunction(member) and \
                            member.__module__ == module.__name__:
                        seen.append((f"{module.__name__}.{name}.{attr}", member))
    return seen


@pytest.mark.parametrize("name, function", _public_callables(),
                         ids=[n for n, _ in _public_callables()])
def test_every_public_function_has_full_type_hints(name, function):
    signature = inspect.signature(function)
    for p in signature.parameters.values():
        if p.name != "self":
            assert p.annotation is not inspect.Parameter.empty, (name, p.name)
    assert signature.return_annotation is not inspect.Signature.empty, name
    typing.get_type_hints(function)  # every annotation resolves
    assert inspect.getdoc(function) or function.__name__ in ("__init__", "__call__"), name


def test_result_dataclasses_have_resolvable_hints_and_radian_docs():
    for cls in (Analysis, Equilibrium, Uncertain):
        assert typing.get_type_hints(cls)
        assert "radians" in inspect.getdoc(cls)


# --------------------------------------------------------------------------- api spec


def test_api_spec_describes_inputs_and_outputs_deterministically():
    import sympy as sp

    from codegen.compiler.emission.plan import CFunction, Enclosure, Input, Output, Plan
    from codegen.compiler.emission.render import api_spec

    x, k = sp.Symbol("x", real=True), sp.Symbol("k", real=True)
    f = CFunction("force", "A spring's force.", "(1)",
                  (Input("x", (x,), "elongation [m]"),),
                  (Output("f", (k * x,), "force [N]"), Output("e", (k * x**2 / 2,), "[J]")))
    plan = Plan(prefix="toy", title="a toy", parameters=(("k", "N/m", "stiffness", "2"),),
                sizes={"N_PARAMS": 1, "N_MODES": 1}, requirements=(), singular_state="never",
                functions=(f,), enclosure=Enclosure(x, (), ()))
    text = api_spec(plan)
    assert text == api_spec(plan)
    spec = json.loads(text)
    assert json.dumps(spec, indent=1, sort_keys=True) + "\n" == text  # keys sorted
    (function,) = spec["functions"]
    assert function["inputs"] == [{"description": "elongation [m]", "name": "x", "size": None}]
    assert [o["description"] for o in function["outputs"]] == ["force [N]", "[J]"]


@pytest.mark.skipif(not GENERATED.is_dir(), reason="no generated/ beside the tests")
def test_installed_libraries_carry_the_committed_spec():
    for name, lib in LIBRARIES.items():
        assert lib.SPEC == json.loads((GENERATED / name / f"{name}_api.json").read_text()), (
            f"{name}: the installed extension is older than generated/: reinstall")
        for f in lib.SPEC["functions"]:
            assert all("description" in x for x in f["inputs"] + f["outputs"]), f["name"]


# --------------------------------------------------------------------------- 2. pickling


@pytest.fixture(scope="module")
def user_library(tmp_path_factory):
    """A library loaded with load_from: the shipped doughty extension, copied to a folder."""
    folder = tmp_path_factory.mktemp("user_library")
    so = next(p for p in Path(codegen.__file__).parent.glob("_native_doughty.*")
              if p.suffix in (".so", ".pyd"))
    shutil.copy(so, folder / so.name)
    keep = {k: v for k, v in sys.modules.items() if k.startswith("codegen._native_doughty")}
    library = load_from(folder, "doughty")
    sys.modules.update(keep)  # the copy registers its lib under the shipped name too
    assert library is not DOUGHTY
    return library


def _round_trips(value):
    for protocol in range(2, pickle.HIGHEST_PROTOCOL + 1):
        yield pickle.loads(pickle.dumps(value, protocol))
    yield copy.deepcopy(value)
    yield copy.copy(value)


def test_params_results_and_analyses_round_trip_in_process():
    lib = DOUGHTY
    p = lib.example_params(F=90.0)
    for q in _round_trips(p):
        assert q == p and type(q) is lib.Params and type(q).library is lib
    assert analyze(pickle.loads(pickle.dumps(p))) == analyze(p)
    single = lib.linearisation(p, 0.3)
    for r in _round_trips(single):
        assert r == single and type(r) is lib.linearisation.result_type
    batch = lib.point_kinematics(lib.params_array([p, p]), np.zeros((2, 5)), np.ones((2, 5)))
    for r in _round_trips(batch):
        assert type(r) is type(batch)
        assert all(np.array_equal(x, y) for x, y in zip(r, batch))
    for method in ("polynomial", "isolate"):
        analysis = analyze(p, method)
        for a in _round_trips(analysis):
            assert a == analysis and type(a.params) is lib.Params
    pendulum = LIBRARIES["torsion_pendulum"].analyze()
    assert pickle.loads(pickle.dumps(pendulum)) == pendulum
    u = Uncertain(0.1, 0.2, "cluster", 0, False)
    assert pickle.loads(pickle.dumps(u)) == u
    assert pickle.loads(pickle.dumps(lib)) is lib
    assert copy.deepcopy(lib) is lib


def test_user_library_round_trips_to_itself(user_library, monkeypatch):
    folder = Path(user_library.origin[1])
    assert user_library.origin == ("load_from", str(folder), "doughty") and folder.is_absolute()
    monkeypatch.chdir(folder.parent)
    assert load_from(folder.name, "doughty") is user_library  # one library per folder
    p = user_library.example_params(k=3000.0)
    q = pickle.loads(pickle.dumps(p))
    assert type(q) is user_library.Params and type(q) is not DOUGHTY.Params
    assert analyze(q) == analyze(p)
    r = user_library.linearisation(p, 0.3)
    assert type(pickle.loads(pickle.dumps(r))) is user_library.linearisation.result_type


def test_errors_round_trip_with_their_message():
    with pytest.raises(LibraryError) as info:  # the spring anchored 1e200 m away: r^2 overflows
        analyze(DOUGHTY.example_params(H=1e200))
    for e in _round_trips(info.value):
        assert isinstance(e, LibraryError) and str(e) == str(info.value)
        assert (e.code, e.parameter, e.values) == ("ERR_OVERFLOW", "H", {"H": 1e200})


FRESH_PROCESS = """
import json, pickle, sys
from codegen.runtime.analysis import analyze
sets, analyses, result = pickle.load(open(sys.argv[1], "rb"))
print(json.dumps({
    "fresh": [analyze(s).to_dict() for s in sets],
    "unpickled": [a.to_dict() for a in analyses],
    "origins": [type(s).library.origin for s in sets],
    "result": [type(result).__name__, list(result)],
}))
"""


def test_pickles_load_and_analyze_in_a_fresh_process(tmp_path, user_library):
    sets = [DOUGHTY.example_params(F=90.0), LIBRARIES["torsion_pendulum"].example_params(),
            user_library.example_params(k=3000.0)]
    analyses = [analyze(s) for s in sets]
    result = DOUGHTY.linearisation(sets[0], 0.3)
    path = tmp_path / "sets.pickle"
    path.write_bytes(pickle.dumps((sets, analyses, result)))
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    run = subprocess.run([sys.executable, "-c", FRESH_PROCESS, str(path)], cwd=elsewhere,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    expected = [a.to_dict() for a in analyses]
    assert out["fresh"] == expected and out["unpickled"] == expected
    assert [tuple(o) for o in out["origins"]] == [
        ("load", "doughty"), ("load", "torsion_pendulum"), user_library.origin]
    assert out["result"] == ["linearisation_result", list(result)]


def test_a_spawn_pool_maps_analyze_like_a_loop():
    sets = [DOUGHTY.example_params(F=f) for f in (60.0, 110.0, 150.0)] + [
        LIBRARIES["torsion_pendulum"].example_params(),
        LIBRARIES["slider_crank"].example_params(F=-20.0)]
    start = time.perf_counter()
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        mapped = pool.map(analyze, sets)
        with pytest.raises(LibraryError) as info:  # an error crosses back, still naming F
            pool.map(analyze, [DOUGHTY.example_params(H=1e200)])
    assert mapped == [analyze(s) for s in sets]
    assert str(info.value) == "H: a result is too large to represent (H=1e+200)"
    assert time.perf_counter() - start < 30


# --------------------------------------------------------------------------- 3. units


def test_angles_are_radians_with_degree_properties():
    analysis = DOUGHTY.analyze()
    r = analysis.equilibria[0]
    assert r.theta_deg == pytest.approx(np.degrees(r.theta))
    assert (r.theta_lo_deg, r.theta_hi_deg) == (np.degrees(r.theta_lo), np.degrees(r.theta_hi))
    assert analysis.library is DOUGHTY
    data = analysis.to_dict()
    assert data["roots"][0]["theta_deg"] == analysis.roots[0].theta_deg
    assert data["roots"][0]["theta_interval_deg"] == [analysis.roots[0].theta_lo_deg,
                                                       analysis.roots[0].theta_hi_deg]
    singular = DOUGHTY.analyze(DOUGHTY.example_params(a=0.9))  # a = L: r = 0 at a root
    assert singular.singular and data.keys() == singular.to_dict().keys()
    assert singular.to_dict()["singular_roots_deg"] == list(singular.singular_deg)
    assert singular.singular_deg == tuple(np.degrees(t) for t in singular.singular)
    fields = inspect.getsource(Equilibrium)
    for field in ("theta", "theta_lo", "theta_hi"):
        assert any(line.strip().startswith(f"{field}:") and "[rad]" in line
                   for line in fields.splitlines()), field


# --------------------------------------------------------------------------- 4. culprits


@pytest.mark.parametrize("name, value, analysed", [("F", 1e308, True), ("k", 1e300, True),
                                                   ("H", 1e200, False)])
def test_overflow_names_the_parameter(name, value, analysed):
    """sigma ~ F^2 or k^2 overflows; the analysis answers where its results fit (the
    isolation's, in units of the parameters' own scale) and names the parameter where not."""
    p = DOUGHTY.example_params(**{name: value})
    message = f"{name}: a result is too large to represent ({name}={value!r})"
    calls = [lambda: DOUGHTY.sigma(p)]
    if analysed:
        assert len(analyze(p).equilibria) >= 2
    else:
        calls.append(lambda: analyze(p))
    for call in calls:
        with pytest.raises(LibraryError, match="too large") as info:
            call()
        assert info.value.code == "ERR_OVERFLOW" and info.value.parameter == name
        assert str(info.value) == message and info.value.values == {name: value}


def test_overflow_in_a_batch_names_the_item_and_the_parameter():
    table = DOUGHTY.params_array([DOUGHTY.example_params(), DOUGHTY.example_params(F=1e308),
                                  DOUGHTY.example_params(k=1e300)])
    with pytest.raises(LibraryError) as info:
        DOUGHTY.sigma(table)
    assert str(info.value) == "F: a result is too large to represent (F=1e+308, batch item 1)"
    assert (info.value.index, info.value.parameter) == (1, "F")
    _, statuses = DOUGHTY.sigma.batch(table, raise_on_error=False)
    assert list(statuses) == [0] + [DOUGHTY.STATUS["ERR_OVERFLOW"]] * 2


def test_two_parameters_overflowing_together_are_both_named():
    with pytest.raises(LibraryError) as info:
        DOUGHTY.sigma(DOUGHTY.example_params(F=1e308, k=1e300))
    assert str(info.value) == ("k, F: a result is too large to represent "
                               "(k=1e+300, F=1e+308)")


def test_statuses_without_parameters_of_their_own_name_one():
    lib = DOUGHTY
    with pytest.raises(LibraryError) as info:  # H = 0, a = L/2, no load: G vanishes
        analyze(lib.example_params(H=0.0, a=0.45, F=0.0, g=0.0))
    assert info.value.code == "ERR_EVERY_ANGLE" and info.value.parameter == "H, a, F, g"
    with pytest.raises(LibraryError) as info:  # H = a: r = 0 at theta = 0
        lib.reduced_coefficients(lib.example_params(H=0.135), 0.0)
    assert str(info.value).startswith("H: the spring length r is zero")
    with pytest.raises(LibraryError, match=r"^theta: .* \(theta=nan\)$"):
        lib.linearisation(lib.example_params(), float("nan"))
    with pytest.raises(LibraryError, match=r"^mode: .*\(mode=7\)$"):
        lib.enclosure(lib.example_params(), 0.1, 0.2, mode=7)
    with pytest.raises(LibraryError, match=r"^lo, hi: .*\(lo=0.2, hi=0.1\)$"):
        lib.enclosure(lib.example_params(), 0.2, 0.1)
    with pytest.raises(LibraryError, match=r"^g: a parameter is NaN or infinite \(g=inf\)$"):
        lib.sigma(lib.example_params(g=float("inf")))
    with pytest.raises(LibraryError, match=r"^b: b must not be negative \(b=-1.0\)$"):
        lib.sigma(lib.example_params(b=-1.0))


def test_the_culprit_is_searched_only_when_the_message_is_read():
    lib, calls = DOUGHTY, []
    overflow = lib.STATUS["ERR_OVERFLOW"]

    def rerun(values):  # fails unless F is restored
        calls.append(dict(values))
        return overflow if values["F"] != lib.EXAMPLE["F"] else lib.STATUS["OK"]

    error = lib.error(overflow, lib.example_params(F=1e308, k=2.0), rerun=rerun)
    assert calls == []
    assert error.parameter == "F" and len(calls) == 2  # F, k each restored alone
    assert str(error) == "F: a result is too large to represent (F=1e+308)"
    assert len(calls) == 2

    # where the example's parameters fail as well, the inputs of the call are named
    stuck = lib.error(overflow, lib.example_params(F=1e308), rerun=lambda values: overflow,
                      inputs={"theta": 0.5})
    assert str(stuck) == "theta: a result is too large to represent (theta=0.5)"
    # without a way to re-run the call, nothing is guessed
    assert str(lib.error(overflow, lib.example_params(F=1e308))) == \
        "a result is too large to represent"
