"""Fast unit tests of each generator layer, on small inputs."""
from __future__ import annotations

import math

import sympy as sp
from hypothesis import given, settings, strategies as st

from codegen.compiler.derivation.algebra import square_roots, tidy
from codegen.compiler.derivation.elimination import eliminate
from codegen.compiler.derivation.positions import Root
from codegen.compiler.derivation.half_angle import to_tau
from codegen.compiler.emission.printer import RealPrinter

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


def test_elimination_is_the_product_over_branches():
    """Nested roots rho_1 = sqrt(2 + cos), rho_2 = sqrt(1 + x^2 + rho_1): the polynomial equals
    the numerator's product over the four sign choices, times (1+tau^2)^weight (up to one
    constant), at every angle."""
    r1, r2 = sp.symbols("rho_1 rho_2", positive=True)
    roots = (Root(r1, 2 + C, "assembly", "a"), Root(r2, 1 + x**2 + r1, "length", ""))
    numerator = r2 * S - x * r1 + C
    poly = eliminate(numerator, theta, roots, (x,))
    values = {x: sp.Rational(3, 7)}
    coeffs = [c.subs(values) for c in poly.explicit()]
    ratios = []
    for t in (sp.Rational(1, 5), sp.Rational(-2, 3), sp.Rational(7, 4)):
        th = 2 * sp.atan(t)
        product = sp.S.One
        for s1 in (1, -1):
            for s2 in (1, -1):
                rho1 = s1 * sp.sqrt(2 + sp.cos(th))
                rho2 = s2 * sp.sqrt(1 + values[x]**2 + rho1)
                product *= (rho2 * sp.sin(th) - values[x] * rho1 + sp.cos(th))
        value = sum(c * t**i for i, c in enumerate(coeffs))
        ratios.append(sp.N(value / (product * (1 + t**2) ** poly.weight), 30))
    assert all(abs(r / ratios[0] - 1) < 1e-20 for r in ratios)
    assert poly.degree == 2 * poly.weight


def test_tidy_cancels_around_square_roots():
    r = sp.sqrt(x**2 + 1)
    expr = (S * (r - y) * 2 * x / (2 * r)) / S
    assert S not in tidy(expr).atoms(sp.sin) and square_roots(tidy(expr)) == [x**2 + 1]


def test_printer_writes_literals_of_the_library_type():
    """codegen_real is float or double when the C is compiled: literals must take that type
    (a double literal would promote a float expression), libm is called through the
    codegen_ names that codegen_real.h maps to sinf or sin, and numbers too large for float
    go through CODEGEN_R."""
    e = sp.sin(x) * y**2 + sp.sqrt(x) ** 3 + sp.Rational(1, 3) + 1 / y**2 + sp.pi * x
    text = RealPrinter().doprint(e)
    assert "codegen_sin(x)" in text and "(y*y)" in text and "((codegen_real)1/3)" in text
    assert "M_PI" not in text and "CODEGEN_R(3.14159265358979323846" in text
    assert RealPrinter().doprint(x**6) == "(x*x*x*x*x*x)"        # products: pow is slow
    assert RealPrinter().doprint(x**-5) == "1/(x*x*x*x*x)"
    assert RealPrinter().doprint(x**9) == "codegen_pow(x, CODEGEN_R(9.0))"
    assert RealPrinter().doprint(2**30 * x) == "CODEGEN_R(1073741824.0)*x"
    assert RealPrinter().doprint(sp.Max(x, 1)) == "codegen_fmax(CODEGEN_R(1.0), x)"
    assert "1.0/" not in text and "F" not in text.replace("CODEGEN_R", "")


def test_printer_parenthesises_logic():
    cond = sp.Or(x > 0, sp.And(y > 0, x < 1))
    assert RealPrinter().doprint(cond) == "(x > 0) || ((y > 0) && (x < 1))"


def test_a_length_root_keeps_the_sign_of_its_denominator():
    """sqrt(n / (s^2 d)) is sqrt(n d s^2) / (s^2 d): right for either sign of s (written
    sqrt(n d) / (s d) it was the negative length wherever s < 0, issue 26); the sign of d
    is taken only where every parameter set the requirements allow makes it positive."""
    from codegen.compiler.derivation.positions import NotSolvable, PositionSolution

    e = sp.Symbol("e", real=True)
    empty = PositionSolution(theta, (), sp.Matrix([]), (), {})
    # a distance to a point (x, tan(theta)), as a model's constraints give it
    solution, expr = empty.with_length_roots(sp.sqrt(x**2 + (S / C)**2))
    (root,) = solution.roots
    assert sp.expand(root.radicand - (x**2 * C**2 + S**2) * C**2) == 0
    value = expr.subs(root.symbol, sp.sqrt(root.radicand))
    for angle, at in ((0.3, 0.7), (2.5, 0.7), (-2.0, -1.3)):
        exact = math.hypot(at, math.tan(angle))
        assert abs(float(value.subs({theta: angle, x: at})) - exact) < 1e-12
    odd = sp.sqrt(x**2 + S**2 / (e * C**2))
    try:
        empty.with_length_roots(odd)
        raise AssertionError("the sign of e was assumed")
    except NotSolvable as error:
        assert "sign of e in a length" in str(error) and "Requirement(" in str(error)
    declared = PositionSolution(theta, (), sp.Matrix([]), (), {}, (e > 0,))
    assert declared.with_length_roots(odd)[0].roots
