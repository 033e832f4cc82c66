"""generate's verification: every plan checked against the model it came from.

Each shipped mechanism passes; a plan perturbed in one quantity on one branch (cos(theta) < 0,
the branch a sign assumption would get wrong) is refused with a message naming that quantity,
the angle and the parameters; the command line refuses it in one line and writes nothing.
The slotted lever of issue 26 (a collar on a lever pinned to a block on a vertical rail; its
spring length is sqrt(N(theta)) / |cos(theta)|) is the model the old derivation got wrong.
"""
from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

from codegen import cli, generate
from codegen.derivation import derive
from codegen.emission.plan import build_plan
from codegen.model import SHIPPED, load
from codegen.model.mechanism import Mechanism
from codegen.api import load as load_library
from codegen.verification import VerificationError, parameter_sets, verify, verify_compiled


LEVER_MODEL = '''\
"""A slotted lever: a collar on a lever pivoted at the origin, pinned to a block on x = d."""
import sympy as sp

from codegen.model.mechanism import (Body, Coordinate, Damper, Mechanism, Requirement, Spring,
                                     distance, parameter)

PARAMETERS = (
    parameter("l", "m", "lever length", "1"), parameter("m", "kg", "lever mass", "2"),
    parameter("m_b", "kg", "block mass", "1"), parameter("d", "m", "abscissa of the rail", "0.4"),
    parameter("k", "N/m", "spring stiffness", "400"),
    parameter("l_0", "m", "free length of the spring", "0.3"),
    parameter("x_A", "m", "abscissa of the anchor", "0.9"),
    parameter("y_A", "m", "ordinate of the anchor", "0.2"),
    parameter("c", "N s/m", "damper on the block", "5"),
    parameter("g", "m/s^2", "gravitational acceleration", "9.81"),
)
COORDINATES = (Coordinate("theta", "rad", "lever angle"),
               Coordinate("s", "m", "distance of the collar along the lever"),
               Coordinate("y", "m", "height of the block"))


def build() -> Mechanism:
    l, m, m_b, d, k, l_0, x_A, y_A, c, g = (p.symbol for p in PARAMETERS)
    theta, s, y = (q.function for q in COORDINATES)
    return Mechanism(
        name="slotted_lever", title="a slotted lever", parameters=PARAMETERS,
        coordinates=COORDINATES, independent="theta",
        constraints=(s * sp.cos(theta) - d, s * sp.sin(theta) - y),
        bodies=(Body("lever", m, (l / 2 * sp.cos(theta), l / 2 * sp.sin(theta)),
                     inertia=m * l**2 / 12, angle=theta),
                Body("block", m_b, (d, y))),
        springs=(Spring(k, l_0, distance((d, y), (x_A, y_A))),),
        dampers=(Damper(c, y),), forces=(), gravity=g, points={"B": (d, y)},
        requirements=(
            Requirement(sp.And(l > 0, d > 0), "LENGTH", "l and d must be positive"),
            Requirement(sp.And(m >= 0, m_b >= 0), "MASS", "masses must not be negative"),
            Requirement(sp.And(k >= 0, l_0 >= 0, c >= 0), "SPRING",
                        "k, l_0 and c must not be negative")),
    )
'''


def slotted_lever() -> Mechanism:
    namespace: dict = {}
    exec(LEVER_MODEL, namespace)
    return namespace["build"]()


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
    return dataclasses.replace(plan, functions=tuple(
        changed if g.name == function else g for g in plan.functions))


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
    model.write_text(LEVER_MODEL)
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
