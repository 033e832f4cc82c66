"""Fast unit tests of each generator layer, on small inputs."""
from __future__ import annotations

import sympy as sp
from hypothesis import given, settings, strategies as st

from codegen.derivation.algebra import square_roots, tidy
from codegen.derivation.equilibrium import split_square_root
from codegen.derivation.half_angle import to_tau
from codegen.emission.printer import RealPrinter

theta, tau, x, y = sp.symbols("theta tau x y", real=True)
S, C = sp.sin(theta), sp.cos(theta)


def _value(poly) -> sp.Expr:
    return sum(c * tau**i for i, c in enumerate(poly.coeffs)) / (1 + tau**2) ** poly.weight


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(-3, 3), st.integers(0, 3), st.integers(0, 3)),
                min_size=1, max_size=4))
def test_half_angle_form_equals_substitution(terms):
    expr = sum((c * x * S**i * C**j for c, i, j in terms), sp.S.Zero) + y
    poly = to_tau(expr, theta)
    direct = expr.subs({S: 2 * tau / (1 + tau**2), C: (1 - tau**2) / (1 + tau**2)})
    assert sp.simplify(_value(poly) - direct) == 0
    assert len(poly.coeffs) <= 2 * poly.weight + 1


def test_half_angle_keeps_structure_instead_of_expanding():
    expr = ((x + y) * S + C) ** 2
    poly = to_tau(expr, theta)
    # The square of a coefficient stays a power of a sum, not expanded into monomials.
    assert poly.coeffs[2] == (2 * x + 2 * y) ** 2 - 2
    assert poly.weight == 2


def test_half_angle_rejects_non_polynomials():
    for bad in (sp.sqrt(S), 1 / C, sp.tan(theta)):
        try:
            to_tau(bad, theta)
        except ValueError:
            continue
        raise AssertionError(f"accepted {bad}")


def test_split_square_root_recovers_alpha_beta():
    R = x**2 + C**2
    G = (3 * S * (sp.sqrt(R) - y) + C * sp.sqrt(R)) / sp.sqrt(R)
    radicand, alpha, beta = split_square_root(G)
    assert sp.simplify(radicand - R) == 0
    assert sp.simplify(alpha + beta * sp.sqrt(R) - G * sp.sqrt(R)) == 0
    assert not alpha.has(sp.sqrt(R)) and not beta.has(sp.sqrt(R))


def test_tidy_cancels_around_square_roots():
    r = sp.sqrt(x**2 + 1)
    expr = (S * (r - y) * 2 * x / (2 * r)) / S
    assert S not in tidy(expr).atoms(sp.sin) and square_roots(tidy(expr)) == [x**2 + 1]


def test_printer_double_and_float():
    e = sp.sin(x) * y**2 + sp.sqrt(x) ** 3 + sp.Rational(1, 3) + 1 / y**2
    double = RealPrinter("double").doprint(e)
    single = RealPrinter("float").doprint(e)
    assert "sin(x)" in double and "pow(" not in double and "(y*y)" in double
    assert "sinf(x)" in single and "sqrtf(x)" in single and "1.0F/3.0F" in single
    assert "sin(" not in single.replace("sinf(", "")


def test_printer_parenthesises_logic():
    cond = sp.Or(x > 0, sp.And(y > 0, x < 1))
    assert RealPrinter().doprint(cond) == "(x > 0) || ((y > 0) && (x < 1))"
