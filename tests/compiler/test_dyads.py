"""Issue 30: the position analysis of dyads, whatever order the user declares them in, and
what it refuses, in one line.

The gallery (test_gallery.py) checks each of these models against the independent numerical
reference; here: the same model with its coordinates declared in every order gives the same
derivation and the same C for every function of the independent angle; angles written as sums
(a bracket at psi + beta) are expanded; a chain of dyads (a Watt-II six-bar) keeps each dyad
small and closes its loops; a loop of more unknowns than a dyad is refused in one line, naming
the angles, with exit status 2.
"""
from __future__ import annotations

import dataclasses
import itertools
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))   # whatever pytest's import mode
from gallery import MODELS, load_model  # noqa: E402

from codegen.compiler.derivation import derive  # noqa: E402
from codegen.compiler.derivation.positions import NotSolvable  # noqa: E402
from codegen.compiler.emission.plan import build_plan  # noqa: E402
from codegen.compiler.generate import files_of  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def _reordered(mechanism, order):
    return dataclasses.replace(mechanism, coordinates=tuple(mechanism.coordinates[i]
                                                            for i in order))


def _by_name(derivation):
    """Each coordinate's closed form, by name, and the results in the independent angle."""
    solution = derivation.reduction.solution
    names = [c.name for c in derivation.mechanism.coordinates]
    return ({name: q for name, q in zip(names, solution.positions)},
            derivation.equilibrium.residual, derivation.reduction.e,
            derivation.equilibrium.sigma, tuple(r.radicand for r in solution.roots))


def _angle_functions(files: dict[str, str]) -> dict[str, str]:
    """The C functions (name -> text) whose arguments hold no coordinate array: those of the
    independent angle and the parameters, which the declaration order must not change
    (but dependent_state and the fused kernels of the other sign choices, motion_signs<k>,
    which write the coordinates in the declared order)."""
    source = next(text for name, text in files.items()
                  if name.endswith(".c") and not name.endswith("_model.c"))
    functions = re.findall(r"^(\w[^\n;]*\b(\w+)\([^;{]*\)\n\{\n.*?^\})", source,
                           re.MULTILINE | re.DOTALL)
    return {name: text for text, name in functions
            if "COORDS" not in text.split("{", 1)[0] and "coords" not in text
            and "dependent_state" not in name and "motion_signs" not in name}


@pytest.mark.parametrize("model", ["collar_on_link", "whitworth"])
def test_declaration_order_never_changes_the_derivation(model):
    mechanism = load_model(model)
    first = _by_name(derive(mechanism))
    for order in itertools.permutations(range(len(mechanism.coordinates))):
        assert _by_name(derive(_reordered(mechanism, order))) == first, order


def test_declaration_order_never_changes_the_C_of_the_angle():
    mechanism = load_model("collar_on_link")
    reversed_order = _reordered(mechanism, range(len(mechanism.coordinates))[::-1])
    functions = [_angle_functions(files_of(build_plan(derive(m))))
                 for m in (mechanism, reversed_order)]
    assert len(functions[0]) >= 8     # residual, branches, reduced, sigma, linearisation ...
    assert functions[0] == functions[1]


def test_an_angle_written_as_a_sum_is_expanded():
    """The bracket's mass at psi + beta: G and M hold cos(psi) and sin(psi) of the solved
    dyad, never psi itself (the gallery checks the values against the reference)."""
    derivation = derive(load_model("collar_on_link"))
    psi = sp.Symbol("psi", real=True)
    assert not derivation.equilibrium.residual.has(psi)
    assert not any(e.has(psi) for e in derivation.reduction.e)
    assert derivation.equilibrium.polynomial is not None


def _generate(model: Path, tmp_path: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run([sys.executable, "-m", "codegen", "generate", "--model", str(model),
                           "--out", str(tmp_path / "out")], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)


def _one_line_refusal(process: subprocess.CompletedProcess) -> str:
    assert process.returncode == 2, process.stderr[-2000:]
    errors = [line for line in process.stderr.splitlines() if "error" in line]
    assert len(errors) == 1 and "Traceback" not in process.stderr, process.stderr[-2000:]
    return errors[0]


FIVE_BAR = '''
import sympy as sp
from codegen.model.mechanism import Body, Coordinate, Mechanism, parameter

PARAMETERS = tuple(parameter(n, "m", n, v) for n, v in
                   [("a", "0.2"), ("b", "0.5"), ("c", "0.5"), ("e", "0.3"), ("d", "0.6")])
COORDINATES = tuple(Coordinate(n, "rad", n) for n in ("theta", "phi", "psi", "chi"))


def build():
    a, b, c, e, d = (p.symbol for p in PARAMETERS)
    theta, phi, psi, chi = (q.function for q in COORDINATES)
    cos, sin = sp.cos, sp.sin
    return Mechanism(
        name="five_bar", parameters=PARAMETERS, coordinates=COORDINATES, independent="theta",
        constraints=(a * cos(theta) + b * cos(phi) - c * cos(psi) - e * cos(chi) - d,
                     a * sin(theta) + b * sin(phi) - c * sin(psi) - e * sin(chi)),
        bodies=(Body("bar", 1, (b * cos(phi), b * sin(phi))),),
        springs=(), dampers=(), forces=(), gravity=sp.Rational(981, 100), points={})
'''


def test_a_loop_of_more_unknown_angles_than_a_dyad_is_refused_by_name(tmp_path):
    """Three unknown angles in one loop (a five-bar driven by one crank: two degrees of freedom
    declared as one) have no closed form: one line naming them."""
    model = tmp_path / "five_bar.py"
    model.write_text(FIVE_BAR)
    message = _one_line_refusal(_generate(model, tmp_path))
    assert "no closed form for the angles chi, phi, psi" in message


def _six_bar_positions():
    from codegen.compiler.derivation.kinematics import derive_kinematics
    from codegen.compiler.derivation.names import internal
    from codegen.compiler.derivation.positions import solve_positions
    from codegen.compiler.derivation.state import StateSymbols

    mechanism = internal(load_model("watt_six_bar"))
    state = StateSymbols.of(mechanism)
    constraints = derive_kinematics(mechanism).constraints.subs(state.freezer(mechanism))
    return mechanism, state, constraints, solve_positions(mechanism, state.coords, constraints)


def test_a_chain_of_dyads_stays_small_and_closes_its_loops():
    """The Watt-II six-bar: the first dyad's cosine and sine are definitions the second dyad
    is written in, and so are the centre of the circle the second dyad's line comes from
    (U, V) and the second dyad's cosine and sine, so each assembly root's radicand stays
    small (substituted, the second had over 40 000 operations, then 2 500 with the first
    dyad's definitions alone); written out, the positions satisfy both loops' constraints to 25
    digits at every assembled angle, in the declared modes. (The chain's expressions are in
    the symbols of its straight-line program, which the library computes once per angle.)"""
    from codegen.compiler.derivation.positions import branch_program
    from codegen.compiler.emission.plan import written_out

    mechanism, state, constraints, solution = _six_bar_positions()
    assert [r.coordinate for r in solution.roots if r.kind == "assembly"] == ["phi_4", "phi_6"]
    assert [d.symbol.name for d in solution.definitions] == [
        "C_phi_4", "S_phi_4", "U_phi_6", "V_phi_6", "C_phi_6", "S_phi_6"]
    assert max(sp.count_ops(r.radicand) for r in solution.roots) < 100
    example = mechanism.example()
    theta = solution.theta
    in_program = list(solution.explicit(solution.positions))
    assert max(sp.count_ops(q) for q in in_program) < 100
    explicit = written_out(branch_program(solution.roots, solution.definitions), in_program)
    positions = sp.lambdify([theta], sp.Matrix(explicit).subs(example), "mpmath")
    residual = sp.lambdify(list(state.coords), constraints.subs(example), "mpmath")
    import mpmath
    closed = 0
    with mpmath.workdps(40):
        for k in range(24):
            q = positions(mpmath.mpf(-3.1) + k * mpmath.mpf("0.26"))
            if any(isinstance(x, mpmath.mpc) and x.imag != 0 for x in q):
                continue          # not assembled at this angle
            q = [mpmath.re(x) for x in q]
            assert max(abs(r) for r in residual(*q)) < mpmath.mpf("1e-25"), q
            closed += 1
    assert closed >= 6
