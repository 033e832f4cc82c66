"""generate's verification: every plan checked against the model it came from.

Each shipped mechanism passes; a plan perturbed in one quantity on one branch (cos(theta) < 0,
the branch a sign assumption would get wrong) is refused with a message naming that quantity,
the angle and the parameters; the command line refuses it in one line and writes nothing.
The slotted lever of issue 26 (a collar on a lever pinned to a block on a vertical rail; its
spring length is sqrt(N(theta)) / |cos(theta)|) is the model the old derivation got wrong.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
import sympy as sp

from codegen import cli
from codegen.compiler import generate
from codegen.compiler.derivation import derive
from codegen.compiler.emission.plan import build_plan
from codegen.compiler.model import SHIPPED, load
from codegen.compiler.model.mechanism import Mechanism
from codegen.api import load as load_library
from codegen.compiler.verification import VerificationError, parameter_sets, verify, verify_compiled


#: The gallery's model file of the slotted lever (tests/system/test_gallery.py runs it end to end).
LEVER = Path(__file__).resolve().parents[1] / "models" / "slotted_lever.py"


def slotted_lever() -> Mechanism:
    return load(str(LEVER))


@pytest.fixture(scope="module")
def lever():
    mechanism = slotted_lever()
    return mechanism, build_plan(derive(mechanism))


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_mechanism_agrees_with_its_model(name):
    mechanism = load(name)
    report = verify(mechanism, build_plan(derive(mechanism)))
    # most of the sampled angles are compared (the rest sit next to singular states)
    assert report.points > 0.8 * report.sets * 74, report
    assert report.sets == 6


def test_the_slotted_lever_agrees_with_its_model(lever):
    report = verify(*lever)
    assert report.points > 400 and report.zeros > 0, report


def _perturbed(plan, function: str, output: int, change):
    """The plan with one output expression changed where cos(theta) < 0."""
    theta = plan.enclosure.theta
    f = plan.function(function)
    exprs = [e for o in f.outputs for e in o.exprs]
    exprs[output] = sp.Piecewise((exprs[output], sp.cos(theta) >= 0),
                                 (change(exprs[output]), True))
    outputs, start = [], 0
    for o in f.outputs:
        outputs.append(dataclasses.replace(o, exprs=tuple(exprs[start:start + len(o.exprs)])))
        start += len(o.exprs)
    changed = dataclasses.replace(f, outputs=tuple(outputs))
    return dataclasses.replace(plan, **{kind: tuple(changed if g.name == function else g
                                                    for g in getattr(plan, kind))
                                        for kind in ("functions", "mode_functions")})


FLIPS = [  # (function, output index, the quantity the message names)
    ("dependent_state", 1, "position of s"),
    ("dependent_state", 5, "rate of y"),
    ("equilibrium_residual", 0, "G"),
    ("reduced_coefficients", 0, "e0"),
    ("reduced_coefficients", 1, "e1"),
    ("reduced_coefficients", 2, "e2"),
    ("linearisation", 2, "K"),
    ("angular_acceleration", 0, "thetaddot"),
]


@pytest.mark.parametrize("function, output, quantity", FLIPS)
def test_a_sign_flipped_on_one_branch_is_refused(lever, function, output, quantity):
    mechanism, plan = lever
    bad = _perturbed(plan, function, output, lambda e: -e)
    with pytest.raises(VerificationError) as error:
        verify(mechanism, bad)
    message = str(error.value)
    assert f": {quantity} at theta = " in message, message
    assert "the library gives" in message and "the model" in message
    assert "parameters l=" in message and "\n" not in message


@pytest.mark.parametrize("function, output, quantity", [
    ("motion_signs1", 2, "position of phi_"),   # (Newton then moves phi_3 too)
    ("motion_signs1", 9, "thetaddot"),
    ("mode_linearisation", 5, "K")])   # mode 1's K
def test_a_wrong_function_on_another_sign_choice_is_refused(function, output, quantity):
    """The four-bar's functions of one angle on its other assembly mode (which the library
    evaluates where the model's condition holds on that sign) are checked at the states that
    sign gives, as the declared one's are."""
    mechanism = load("four_bar")
    bad = _perturbed(build_plan(derive(mechanism)), function, output, lambda e: -e)
    with pytest.raises(VerificationError) as error:
        verify(mechanism, bad)
    message = str(error.value)
    assert f": {quantity}" in message, message
    assert " on sign choice 1 of the assembly roots at theta = " in message, message


def test_a_wrong_assembly_condition_is_refused():
    """The conditions the library decides each state's mode by, for every set, are the
    model's assembly_modes at the model's own states (a quick-return shaper's were written
    with its lever's cosine taken as the slot's X, not X over the slot's length)."""
    mechanism = load("four_bar")
    plan = build_plan(derive(mechanism))
    assert plan.condition_sources == (0,)
    bad = _perturbed(plan, "assembly_conditions", 0, lambda e: -e)
    with pytest.raises(VerificationError, match=r": assembly_modes\[0\] at theta = "):
        verify(mechanism, bad)


def test_a_wrong_coefficient_of_sigma_is_refused(lever):
    mechanism, plan = lever
    f = plan.function("sigma")
    (out,) = f.outputs
    flipped = (out.exprs[0], -out.exprs[1], *out.exprs[2:])
    bad_sigma = dataclasses.replace(f, outputs=(dataclasses.replace(out, exprs=flipped),))
    bad = dataclasses.replace(plan, functions=tuple(
        bad_sigma if g.name == "sigma" else g for g in plan.functions))
    with pytest.raises(VerificationError, match=r": sigma at theta = "):
        verify(mechanism, bad)


def test_parameter_sets_meet_the_requirements_and_vary_zero_values():
    mechanism = load("slider_crank")  # T = 0 in the example
    sets = parameter_sets(mechanism, __import__("numpy").random.default_rng(1), 6)
    assert len(sets) == 6 and sets[0]["T"] == 0
    assert all(s["R"] > 0 and s["k"] >= 0 and s["b"] >= 0 for s in sets)
    assert any(s["T"] != 0 for s in sets[1:])


def test_generate_refuses_a_wrong_derivation_in_one_line_and_writes_nothing(
        tmp_path, monkeypatch, capsys):
    """The command line as a user meets it: the model file's derivation goes wrong (the
    plan's G flipped on one branch), and generate stops before writing a file."""
    model = tmp_path / "slotted_lever.py"
    model.write_bytes(LEVER.read_bytes())
    monkeypatch.setattr(generate, "build_plan", lambda d: _perturbed(
        build_plan(d), "equilibrium_residual", 0, lambda e: -e))
    out = tmp_path / "out"
    status = cli.main(["generate", "--model", str(model), "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2
    # the stages it went through, then one line: the error
    assert "verifying against the model" in err[:-1], err
    assert "error: slotted_lever: the derivation disagrees with the model: G at theta = " \
        in err[-1] and "Traceback" not in "".join(err)
    assert not out.exists()


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_library_computes_its_plan(name):
    """The compiled kernels (printer, templates, compiler) against the plan's expressions."""
    mechanism = load(name)
    compared = verify_compiled(mechanism, build_plan(derive(mechanism)),
                               load_library(name).rows)
    assert compared > 6 * 74 * 10


@pytest.mark.parametrize("function, output", [("equilibrium_residual", 0),
                                              ("reduced_coefficients", 2),
                                              ("dependent_state", 3)])
def test_a_library_built_from_another_plan_is_refused(function, output):
    mechanism = load("doughty")
    plan = _perturbed(build_plan(derive(mechanism)), function, output, lambda e: e * 1.001)
    with pytest.raises(VerificationError, match=f"the compiled library disagrees with the "
                                                f"derivation: output {output} of {function} "
                                                "at theta = "):
        verify_compiled(mechanism, plan, load_library("doughty").rows)
