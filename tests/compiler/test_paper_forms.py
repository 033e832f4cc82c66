"""The generator's expressions equal the forms printed in the paper (SPEC.md).

The generator *derives* everything from the mechanism's description; the forms below are
typed in by hand from the paper's equations, (4)-(55). Each pair is compared twice:

* exactly: the difference is put over a common denominator, sin/cos become s, c, the
  spring length sqrt(R) becomes rho, and the numerator is reduced modulo the relations
  s^2 + c^2 = 1 (for theta and for phi) and rho^2 = R(s, c). Those three polynomials have
  pairwise coprime leading monomials in lex order rho > s_theta > c_theta > s_phi > c_phi,
  so they form a Groebner basis and the remainder is zero iff the forms are identical;
* numerically: at 200 random points (parameters near Table 2 and far from it, arbitrary
  states), evaluated with mpmath at 50 digits, relative difference < 1e-30.
"""
from __future__ import annotations

import functools
import zlib

import mpmath
import numpy as np
import pytest
import sympy as sp

from codegen.api import load

api = load("doughty")

# ----------------------------------------------------------------------------- symbols

P = {n: sp.Symbol(n, real=True) for n in api.PARAMETER_NAMES}
H, L, a, m_A, m_B, m_C, k, b, l_ND, F, g = (P[n] for n in api.PARAMETER_NAMES)
NAMES = ("p", "q", "r", "theta", "phi")
p, q, r, theta, phi = (sp.Symbol(n, real=True) for n in NAMES)
p_d, q_d, r_d, theta_d, phi_d = (sp.Symbol(f"{n}_d", real=True) for n in NAMES)
p_dd, q_dd, r_dd, theta_dd, phi_dd = (sp.Symbol(f"{n}_dd", real=True) for n in NAMES)
lam = sp.Matrix(sp.symbols("lambda_1:5", real=True))
COORDS = sp.Matrix([p, q, r, theta, phi])
RATES = sp.Matrix([p_d, q_d, r_d, theta_d, phi_d])
ACCELS = sp.Matrix([p_dd, q_dd, r_dd, theta_dd, phi_dd])
sin, cos, sqrt = sp.sin, sp.cos, sp.sqrt

# ----------------------------------------------------------------------------- the paper

# (4)-(7)
f_paper = sp.Matrix([
    a * cos(theta) - H + r * cos(phi),
    q - a * sin(theta) - r * sin(phi),
    p - H - (L - a) * cos(theta) + r * cos(phi),
    (L - a) * sin(theta) - r * sin(phi),
])
# (25)
A_paper = sp.Matrix([
    [0, 0, cos(phi), -a * sin(theta), -r * sin(phi)],
    [0, 1, -sin(phi), -a * cos(theta), -r * cos(phi)],
    [1, 0, cos(phi), (L - a) * sin(theta), -r * sin(phi)],
    [0, 0, -sin(phi), (L - a) * cos(theta), -r * cos(phi)],
])
# step 5: A qddot + (dA/dt) qdot, dA/dt = sum_j dA/dq_j qdot_j
Adot_paper = sum((A_paper.diff(c) * v for c, v in zip(COORDS, RATES)), sp.zeros(4, 5))
# (12)-(14): A, B, C, each (x, y)
points_paper = [p, 0, 0, q, p - L / 2 * cos(theta), L / 2 * sin(theta)]
point_velocities_paper = [p_d, 0, 0, q_d, p_d + L / 2 * theta_d * sin(theta),
                          L / 2 * theta_d * cos(theta)]
# (16)-(22)
T_paper = (m_A * p_d**2 / 2 + m_B * q_d**2 / 2
           + m_C / 2 * (p_d**2 + L * p_d * theta_d * sin(theta) + L**2 * theta_d**2 / 3))
V_G_paper = m_B * g * q + m_C * g * (L / 2) * sin(theta)
V_E_paper = k * (r - l_ND)**2 / 2
# (26)-(29)
QNC_paper = [0, F, 0, 0, 0]
VD_paper = [0, 0, b * r_d, 0, 0]
# (30)-(35)
C2 = L**2 - 2 * L * a
r_paper = sqrt(((L - a) * sin(theta))**2 + (H - a * cos(theta))**2)                  # (34)
positions_paper = [L * cos(theta), L * sin(theta), r_paper, theta]
rates_paper = [-L * theta_d * sin(theta), L * theta_d * cos(theta),
               (H * a + C2 * cos(theta)) * theta_d * sin(theta) / r_paper,          # (35)
               theta_d]
# (37)-(41)
e_paper = [
    (m_A * sin(theta)**2 + m_B * cos(theta)**2 + m_C / 3) * L**2,
    (m_A - m_B) * L**2 * sin(theta) * cos(theta),
    b * ((H * a + C2 * cos(theta)) / r_paper)**2 * sin(theta)**2,
    k * (r_paper - l_ND) * (H * a + C2 * cos(theta)) / r_paper,
    (-F + (m_B + m_C / 2) * g) * L,
]
# (36)
reduced_paper = (e_paper[0] * theta_dd + e_paper[1] * theta_d**2 + e_paper[2] * theta_d
                 + e_paper[3] * sin(theta) + e_paper[4] * cos(theta))
theta_dd_paper = -(reduced_paper - e_paper[0] * theta_dd) / e_paper[0]
# (42)-(43), theta standing for theta_E
G_paper = (k * (r_paper - l_ND) * (H * a + C2 * cos(theta)) * sin(theta) / r_paper
           + (-F + (m_B + m_C / 2) * g) * L * cos(theta))
# r G = beta r + alpha, isolating the root before squaring it into (45)
beta_paper = (k * (H * a + C2 * cos(theta)) * sin(theta)
              + (-F + (m_B + m_C / 2) * g) * L * cos(theta))
alpha_paper = -k * l_ND * (H * a + C2 * cos(theta)) * sin(theta)
# (53), (50)-(52)
rho_E = sqrt(a**2 + H**2 - 2 * a * H * cos(theta) + C2 * sin(theta)**2)
M_paper = L**2 / 2 * (m_A + m_B + sp.Rational(2, 3) * m_C
                      + (m_B - m_A) * (2 * cos(theta)**2 - 1))
B_paper = b * ((H * a + C2 * cos(theta)) * sin(theta))**2 / rho_E**2
K_paper = ((F * L - g * L * (m_B + m_C / 2)) * sin(theta)
           + k * ((H * a * cos(theta) + C2 * (cos(theta)**2 - sin(theta)**2))
                  * (rho_E - l_ND) / rho_E
                  + ((H * a + C2 * cos(theta)) * sin(theta))**2 * l_ND / rho_E**3))
# (54)-(55): omega_n^2 = K/M, zeta omega_n = B / (2 M)

# ----------------------------------------------------------------------------- comparisons


def _flat(x):
    if isinstance(x, sp.MatrixBase):
        return list(x)
    return list(x) if isinstance(x, (list, tuple)) else [x]


def _outputs(plan, function, output):
    fn = plan.function(function)
    return fn.explicit(next(o for o in fn.outputs if o.name == output).exprs)


def _comparisons(d, plan):
    """label -> (derived expressions, the paper's)."""
    fr = d.frozen
    kin, red = d.kinematics, d.reduction
    out = functools.partial(_outputs, plan)
    tau = sp.Symbol("tau", real=True)
    half_angle = {sin(theta): 2 * tau / (1 + tau**2), cos(theta): (1 - tau**2) / (1 + tau**2)}
    sigma_poly = sum(s * tau**i for i, s in enumerate(out("sigma", "sigma")))
    squared_paper = beta_paper**2 * r_paper**2 - alpha_paper**2
    return {
        "(4)-(7) position constraints": (out("position_constraints", "f"), f_paper),
        "(25) velocity-constraint matrix A": (out("constraint_jacobian", "A"), A_paper),
        "(25) A = df/dq of the derivation": (fr(kin.jacobian), A_paper),
        "(8)-(11) velocity constraints A qdot":
            (out("velocity_constraints", "f_d"), A_paper * RATES),
        "step 5 acceleration constraints":
            (out("acceleration_constraints", "f_dd"), A_paper * ACCELS + Adot_paper * RATES),
        "(12)-(14) point positions": (out("point_kinematics", "positions"), points_paper),
        "(12)-(14) point velocities":
            (out("point_kinematics", "velocities"), point_velocities_paper),
        "(16)-(19) kinetic energy T": (out("energies", "T"), T_paper),
        "(20) V_G": (out("energies", "V_G"), V_G_paper),
        "(21) V_E": (out("energies", "V_E"), V_E_paper),
        "(22) Lagrangian": (out("energies", "lagrangian"), T_paper - V_G_paper - V_E_paper),
        "(27) A^T lambda": (out("lagrange_terms", "constraint_forces"), A_paper.T * lam),
        "(28) Q_nc": (out("lagrange_terms", "applied_forces"), QNC_paper),
        "(29) V_D": (out("lagrange_terms", "dissipative_forces"), VD_paper),
        "(30)-(31), (34) positions": (out("dependent_state", "coords")[:4], positions_paper),
        "(32), (35) rates": (out("dependent_state", "rates")[:4], rates_paper),
        "(4), (7): r cos(phi), r sin(phi)": (
            [red.positions[2] * cos(red.positions[4]), red.positions[2] * sin(red.positions[4])],
            [H - a * cos(theta), (L - a) * sin(theta)]),
        "(37)-(39) e0..e2": (out("reduced_coefficients", "e"), e_paper[:3]),
        # The paper's split of G: the spring's contribution is e3 sin, gravity's and F's e4 cos.
        "(40)-(41) e3 sin, e4 cos: G's contributions": (
            [red.solution.explicit(red.static_terms[0]),
             red.solution.explicit(sum(red.static_terms[1:], sp.S.Zero))],
            [e_paper[3] * sin(theta), e_paper[4] * cos(theta)]),
        "(36) reduced equation": (red.equation, reduced_paper),
        "(36) angular acceleration": (out("angular_acceleration", "theta_dd"), theta_dd_paper),
        "(42)-(43) equilibrium residual G": (out("equilibrium_residual", "residual"), G_paper),
        "(43) G on both branches: (alpha + beta r)/r, (beta r - alpha)/r": (
            out("equilibrium_branches", "residuals"),
            [(alpha_paper + beta_paper * r_paper) / r_paper,
             (beta_paper * r_paper - alpha_paper) / r_paper]),
        "(44)-(45) sigma polynomial": (
            sigma_poly, ((1 + tau**2)**6 * squared_paper).subs(half_angle)),
        "(50) M_EQ": (out("linearisation", "M"), M_paper),
        "(51) B_EQ": (out("linearisation", "B"), B_paper),
        "(52)-(53) K_EQ": (out("linearisation", "K"), K_paper),
        "(54) omega_n^2 = K/M": (out("vibration", "omega_n_squared"), K_paper / M_paper),
        "(55) zeta omega_n = B/(2M)": (out("vibration", "zeta_omega_n"), B_paper / (2 * M_paper)),
        "(50)-(52) derivation's M, B, K": (
            [d.linearisation.mass, d.linearisation.damping, d.linearisation.stiffness],
            [M_paper, B_paper, K_paper]),
    }


LABELS = [
    "(4)-(7) position constraints", "(25) velocity-constraint matrix A",
    "(25) A = df/dq of the derivation", "(8)-(11) velocity constraints A qdot",
    "step 5 acceleration constraints", "(12)-(14) point positions",
    "(12)-(14) point velocities", "(16)-(19) kinetic energy T", "(20) V_G", "(21) V_E",
    "(22) Lagrangian", "(27) A^T lambda", "(28) Q_nc", "(29) V_D",
    "(30)-(31), (34) positions", "(32), (35) rates", "(4), (7): r cos(phi), r sin(phi)",
    "(37)-(39) e0..e2", "(40)-(41) e3 sin, e4 cos: G's contributions",
    "(36) reduced equation", "(36) angular acceleration",
    "(42)-(43) equilibrium residual G",
    "(43) G on both branches: (alpha + beta r)/r, (beta r - alpha)/r",
    "(44)-(45) sigma polynomial", "(50) M_EQ",
    "(51) B_EQ", "(52)-(53) K_EQ", "(54) omega_n^2 = K/M", "(55) zeta omega_n = B/(2M)",
    "(50)-(52) derivation's M, B, K",
]


@pytest.fixture(scope="module")
def comparisons(derivation, plan):
    return _comparisons(derivation, plan)


# ----------------------------------------------------------------------------- exact zero test

_rho = sp.Symbol("rho", positive=True)
_s, _c, _sp, _cp = sp.symbols("s_theta c_theta s_phi c_phi", real=True)
_TRIG = {sin(theta): _s, cos(theta): _c, sin(phi): _sp, cos(phi): _cp}
_R = sp.expand(r_paper**2).subs(_TRIG)
_BASIS = [_rho**2 - _R, _s**2 + _c**2 - 1, _sp**2 + _cp**2 - 1]
_GENS = (_rho, _s, _c, _sp, _cp)


def _remainder(expr) -> sp.Expr:
    """Normal form of expr's numerator modulo the basis (0 iff expr vanishes identically)."""
    expr = sp.sympify(expr)
    roots = {}
    for power in expr.atoms(sp.Pow):
        if power.exp.is_Rational and power.exp.q == 2:
            base = power.base
            assert _remainder(base - r_paper**2) == 0, f"unexpected radicand {base}"
            roots[power] = _rho ** int(2 * power.exp)
    expr = expr.xreplace(roots).subs(_TRIG)
    assert not expr.has(theta, phi), f"trigonometric atom left in {expr}"
    numerator = sp.expand(sp.numer(sp.together(expr)))
    if numerator == 0:
        return sp.S.Zero
    _, rem = sp.reduced(numerator, _BASIS, *_GENS, order="lex")
    return sp.expand(rem)


def test_every_comparison_is_run(comparisons):
    assert sorted(comparisons) == sorted(LABELS)


@pytest.mark.parametrize("label", LABELS)
def test_paper_form(label, comparisons, random_params, mp_compile):
    derived, paper = (_flat(x) for x in comparisons[label])
    assert len(derived) == len(paper), (len(derived), len(paper))

    # exact
    for i, (x, y) in enumerate(zip(derived, paper)):
        rem = _remainder(sp.sympify(x) - sp.sympify(y))
        assert rem == 0, f"{label}[{i}]: derived - paper reduces to {rem}"

    # numerical, 200 points at 50 digits
    _numerically_equal(label, derived, paper, random_params, mp_compile)


def _numerically_equal(label, derived, paper, random_params, mp_compile, count=200,
                       rel=mpmath.mpf("1e-30")):
    exprs = [sp.sympify(e) for e in derived + paper]
    symbols = sorted(set().union(*(e.free_symbols for e in exprs)), key=sp.default_sort_key)
    func = mp_compile(symbols, exprs, dps=50)
    rng = np.random.default_rng(zlib.crc32(label.encode()))
    params = random_params(rng, count)
    n = len(derived)
    for i in range(count):
        values = {P[name]: getattr(params[i], name) for name in api.PARAMETER_NAMES}
        for s in symbols:
            if s not in values:
                # angles in a wide range; other state values and tau of either sign and size
                values[s] = float(rng.uniform(-7.0, 7.0) * np.exp(rng.uniform(-2.0, 2.0)))
        result = func(*(values[s] for s in symbols))
        for j in range(n):
            x, y = result[j], result[n + j]
            with mpmath.workdps(50):
                assert abs(x - y) <= rel * max(abs(x), abs(y)), (
                    f"{label}[{j}]: derived {mpmath.nstr(x, 20)} paper {mpmath.nstr(y, 20)} "
                    f"at {values}")


# ----------------------------------------------------------------------------- not vacuous


@pytest.mark.parametrize("wrong", [
    "e3 with (L^2 - L a)", "K_EQ without the l_ND / rho^3 term", "M_EQ with m_C / 2"])
def test_a_misprint_is_caught(wrong, comparisons, random_params, mp_compile):
    """Typical misprints of the paper's forms fail both comparisons."""
    if wrong.startswith("e3"):
        derived = comparisons["(40)-(41) e3 sin, e4 cos: G's contributions"][0][0]
        paper = (k * (r_paper - l_ND) * (H * a + (L**2 - L * a) * cos(theta)) / r_paper
                 * sin(theta))
    elif wrong.startswith("K_EQ"):
        derived = comparisons["(52)-(53) K_EQ"][0][0]
        paper = ((F * L - g * L * (m_B + m_C / 2)) * sin(theta)
                 + k * (H * a * cos(theta) + C2 * (cos(theta)**2 - sin(theta)**2))
                 * (rho_E - l_ND) / rho_E)
    else:
        derived = comparisons["(50) M_EQ"][0][0]
        paper = L**2 / 2 * (m_A + m_B + m_C / 2 + (m_B - m_A) * (2 * cos(theta)**2 - 1))
    assert _remainder(derived - paper) != 0
    with pytest.raises(AssertionError):
        _numerically_equal(wrong, [derived], [paper], random_params, mp_compile, count=20)
