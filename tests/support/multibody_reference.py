"""Independent high-precision reference for the multi-degree-of-freedom mechanisms.

Nothing here is shared with the compiler (no SymPy, no import from ``codegen``, nothing read
from ``MECHANISMS.md`` at run time). Each mechanism is typed in from its geometric definition:

* ``double_pendulum`` -- bars O-A (l_1, m_1) and A-B (l_2, m_2), tip mass m_t at B, torsional
  springs k_1 on theta_1 (free alpha_1) and k_2 on theta_2 - theta_1 (free alpha_2), dampers
  c_1, c_2 in parallel, force F_x at B along +X, gravity g along -Y.
* ``triple_pendulum`` -- the same chain with three bars (l_i, m_i), springs k_i / dampers c_i
  on the relative angles (k_1, c_1 on theta_1 itself), free angles alpha_i, no tip mass and
  no force (``m_t`` / ``F_x`` are honoured if a parameter set names them).
* ``flexible_doughty`` -- Doughty's two-slider mechanism with its bar made of two uniform
  halves (L/2, m_C/2 each) joined at J by a torsional spring k_t / damper c_t:
  B = (0, y_B), J = B + (L/2)(cos t1, -sin t1), A = J + (L/2)(cos t2, -sin t2),
  y_B = (L/2)(sin t1 + sin t2); slider masses m_A at A, m_B at B; spring k (free length l_ND)
  and damper b from (H, 0) to P = B + a (cos t1, -sin t1); force F on slider 2 along +Y.

Coordinates
-----------
Every mechanism uses the independent coordinates q = (theta_1, delta) with
delta = theta_2 - theta_1 (theta_2 absolute); the triple pendulum uses
q = (theta_1, delta_2, delta_3), delta_i = theta_i - theta_{i-1}. Ranges (the "box"):

* pendulums: theta_1 in (alpha_1 - pi, alpha_1 + pi], delta_i in (alpha_i - pi, alpha_i + pi]
  (the springs wind: states a turn apart are different);
* flexible_doughty: theta_1 in (-pi, pi] (periodic: reported values are mapped into it),
  delta in (-pi, pi) (open at both ends).

What is computed (all at 40 significant digits, ``mpmath.workdps(40)``; the caller's global
mpmath precision is left untouched)
-------------------------------------------------------------------------------------------
* ``potential`` V: springs' elastic energy + sum m g y_centre - F . x_point (own formulas).
* ``generalised_force`` G_i = dV/dq_i by ``mpmath.diff`` (the constant forces are inside V,
  so Q = 0 and G = dV/dq). ``stiffness`` K = dG/dq = the Hessian of V, by ``mpmath.diff``
  mixed partials.
* ``kinetic_matrices`` (M, B): M = sum_bodies m J_c^T J_c + I J_w^T J_w where J_c (centre) and
  J_w (rotation angle) are numerical Jacobians (``mpmath.diff``) of each body's centre and
  angle; B = sum_dampers c grad(e) grad(e)^T where e(q) is the length / angle difference the
  damper acts on (Rayleigh D = c edot^2 / 2).
* ``modes``: K phi = omega^2 M phi by Cholesky (M = L L^T, eigsy of L^-1 K L^-T, phi mass
  normalised, largest component positive); the 2n eigenvalues s of M s^2 + B s + K from the
  first-order state matrix; a damping ratio per mode (see ``_mode_zetas``).
* ``equilibria``: every zero of G in the box, each with its modal data.

How all the zeros are found (the method is this module's own)
--------------------------------------------------------------
Pendulum chains (double and triple): in absolute angles t_j the equilibrium equations are
``k_j (phi_j - alpha_j) + R_j = 0`` for j = n..1, where phi_j = t_j - t_{j-1} (t_0 = 0) and
``R_j = sum_{i >= j} f_i(t_i)``, f_i(t) = P_i cos t + Q_i sin t the load torque on bar i
(P_i = g l_i (m_i/2 + sum_{j>i} m_j + m_t), Q_i = F_x l_i). Walking down the chain from the
last angle s = t_n, each equation with k_j > 0 gives the next angle in closed form,
``t_{j-1} = t_j - alpha_j + R_j / k_j``; so all angles are explicit functions of s and the
zeros of G are exactly the zeros of ONE scalar residual ``k_1 (t_1 - alpha_1) + R_1(s)``
(a one-to-one correspondence). If a spring k_j is zero the equation at j becomes
``R_j(s) = 0`` (roots in s), and t_{j-1} starts a new, independent 1-D segment below it
(with R restarting from zero); solutions of the segments are combined. Each 1-D residual is
scanned in float64 on a uniform grid over the whole reachable range of its variable (the
sum of the relative angles' ranges, plus a margin), with the number of points raised until
no angle of the chain moves by more than 0.004 rad per step (so weak springs, which make the
angles swing wildly with s, get a finer grid); every sign change (and every grid extremum
whose parabola through three samples crosses zero, a near-miss net for close pairs) is
refined at 40 digits by a bracketing solver (``mpmath.findroot``, Anderson-Bjorck) on the
same residual evaluated in mpmath.

flexible_doughty: a 2-D scan. G_1 and G_2 are evaluated in float64 by the complex-step
derivative of V (exact to rounding) on a grid of about 700 x 700 points over
theta_1 in [-pi - margin, pi + margin] (the seam is overlapped), delta in [-pi, pi]. Every
grid cell where both G_1 and G_2 change sign among its corners is a candidate; Newton's
method (Jacobian by central differences of the complex-step G) is run from each candidate's
centre in float64 and kept if it converges within a few cells of its start.

Finally, for both methods, every candidate is polished by Newton's method on the full
40-digit G (``mpmath.diff`` G and K), accepted only if |G| is negligible (relative to the
forces' scale), snapped onto a box boundary if within 1e-25 of it (so the half-open rule
decides), filtered to the box, and deduplicated (max-norm distance < 1e-9, modulo 2 pi in
theta_1 for flexible_doughty). Double roots are not looked for (G does not change sign).

Damping ratio per mode (``zeta``): for each complex-conjugate pair s, zeta = -Re s / |s|;
real eigenvalues are paired into overdamped modes (the pairing whose products
s_a s_b best match the undamped omega^2), zeta = -(s_a + s_b) / (2 sqrt(s_a s_b)) (> 1) for a
pair with s_a s_b > 0 and NaN for a pair with s_a s_b <= 0 (an unstable, divergent mode).
Modes are sorted by |s| (complex) or sqrt|s_a s_b| (real pair), ascending (at an unstable
equilibrium this order need not match the order of ``omega``, which follows omega^2).

Checks made when this module was written (not run at import): against multistart Newton
(scipy fsolve from thousands of random points of the box) on ~50 parameter sets per
mechanism (springs 0.05x .. 1.3x the example, masses/lengths +-30 %, alpha shifted, F_x != 0,
zero springs, k_t from 20 to 1e10) no zero was missing; the counts were unchanged with an
8x finer 1-D grid and a 2400 x 2400 2-D grid on 120 random sets; with k_t -> infinity the
flexible_doughty equilibria, first omega and zeta converge like 1/k_t to the rigid
mechanism's (which reproduce the paper's Table 3: theta = 12.4726 deg, omega_n = 26.8338,
zeta = 3.3222, ...); ``hanging_frequencies`` agrees with ``modes`` to all digits.

Public interface
----------------
``EXAMPLES``, ``NAMES``, ``RANGES`` (text), ``box(name, params)``,
``potential(name, params, q)``, ``kinetic_matrices(name, params, q)``,
``generalised_force(name, params, q)``, ``stiffness(name, params, q)``,
``modes(name, params, q)``, ``equilibria(name, params)``,
``hanging_frequencies(params)`` (double pendulum), ``rigid_doughty_equilibria(params)``
(Doughty's own one-degree-of-freedom mechanism, delta forced to 0, for the k_t -> infinity
check).
"""
from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
from mpmath import mp

__all__ = [
    "DPS", "NAMES", "EXAMPLES", "box", "potential", "kinetic_matrices", "generalised_force",
    "stiffness", "modes", "equilibria", "hanging_frequencies", "rigid_doughty_equilibria",
]

#: Decimal digits of every high-precision evaluation.
DPS = 40

NAMES = ("double_pendulum", "flexible_doughty", "triple_pendulum")

_HALF_PI = 1.5707963267948966

_EXAMPLES = {
    "flexible_doughty": dict(H=0.18, L=0.9, a=0.135, m_A=0.194, m_B=0.143, m_C=9.124,
                             k=3500.0, b=875.0, l_ND=0.15, F=110.0, g=9.81,
                             k_t=2000.0, c_t=2.0),
    "double_pendulum": dict(l_1=1.0, l_2=0.8, m_1=1.0, m_2=0.8, m_t=0.5, k_1=30.0, k_2=15.0,
                            alpha_1=_HALF_PI, alpha_2=0.0, c_1=0.3, c_2=0.2, F_x=0.0,
                            g=9.81),
    "triple_pendulum": dict(l_1=0.5, l_2=0.4, l_3=0.3, m_1=1.0, m_2=0.8, m_3=0.6,
                            k_1=40.0, k_2=20.0, k_3=10.0, alpha_1=_HALF_PI, alpha_2=0.0,
                            alpha_3=0.0, c_1=0.3, c_2=0.2, c_3=0.1, g=9.81),
}

#: name -> example parameters (plain floats). Copy before modifying.
EXAMPLES = {name: dict(values) for name, values in _EXAMPLES.items()}

RANGES = {
    "double_pendulum": "theta_1 in (alpha_1 - pi, alpha_1 + pi], delta in (alpha_2 - pi, alpha_2 + pi]",
    "flexible_doughty": "theta_1 in (-pi, pi] (periodic), delta in (-pi, pi)",
    "triple_pendulum": "theta_1 in (alpha_1 - pi, alpha_1 + pi], delta_i in (alpha_i - pi, alpha_i + pi]",
}


def _at_dps(func):
    """Run ``func`` at DPS digits without touching the caller's precision afterwards."""
    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with mp.workdps(DPS):
            return func(*args, **kwargs)
    return wrapper


def _check_name(name):
    if name not in NAMES:
        raise ValueError(f"unknown mechanism {name!r}; expected one of {NAMES}")


def _ndof(name):
    return 3 if name == "triple_pendulum" else 2


def _mpq(q):
    return [mp.mpf(x) for x in q]


# --------------------------------------------------------------------------------------------
# Model definitions (mpmath): bodies, dampers, potential
# --------------------------------------------------------------------------------------------

def _chain_data(name, p):
    """Bars' lengths / masses / springs / free angles / dampers of a pendulum chain."""
    n = _ndof(name)
    idx = range(1, n + 1)
    return dict(
        n=n,
        l=[p[f"l_{i}"] for i in idx], m=[p[f"m_{i}"] for i in idx],
        k=[p[f"k_{i}"] for i in idx], alpha=[p[f"alpha_{i}"] for i in idx],
        c=[p.get(f"c_{i}", 0.0) for i in idx],
        m_t=p.get("m_t", 0.0), F_x=p.get("F_x", 0.0), g=p["g"],
    )


def _chain_angles(q):
    """Absolute angles from (theta_1, delta_2, ...)."""
    t = []
    acc = mp.mpf(0)
    for x in q:
        acc = acc + x
        t.append(acc)
    return t


def _chain_joints(d, q):
    """Joint points O, A, B, ... of the chain (mpf pairs)."""
    t = _chain_angles(q)
    pts = [(mp.mpf(0), mp.mpf(0))]
    for li, ti in zip(d["l"], t):
        x, y = pts[-1]
        pts.append((x + li * mp.cos(ti), y + li * mp.sin(ti)))
    return pts, t


def _chain_bodies(d):
    """(mass, centroidal inertia, centre(q), angle(q)) for each body; angle None for a point."""
    bodies = []
    for i in range(d["n"]):
        def centre(q, i=i):
            pts, _ = _chain_joints(d, q)
            return ((pts[i][0] + pts[i + 1][0]) / 2, (pts[i][1] + pts[i + 1][1]) / 2)

        def angle(q, i=i):
            return _chain_angles(q)[i]

        li, mi = mp.mpf(d["l"][i]), mp.mpf(d["m"][i])
        bodies.append((mi, mi * li ** 2 / 12, centre, angle))
    if d["m_t"]:
        bodies.append((mp.mpf(d["m_t"]), mp.mpf(0), lambda q: _chain_joints(d, q)[0][-1], None))
    return bodies


def _chain_dampers(d):
    # c_i acts on the relative angle delta_i (theta_1 itself for i = 1), i.e. on q_i.
    return [(mp.mpf(d["c"][i]), (lambda q, i=i: q[i])) for i in range(d["n"])]


def _chain_potential(d, q):
    pts, _ = _chain_joints(d, q)
    g = mp.mpf(d["g"])
    V = mp.mpf(0)
    for i in range(d["n"]):
        V += mp.mpf(d["k"][i]) * (q[i] - mp.mpf(d["alpha"][i])) ** 2 / 2
        V += mp.mpf(d["m"][i]) * g * (pts[i][1] + pts[i + 1][1]) / 2
    V += mp.mpf(d["m_t"]) * g * pts[-1][1]
    V -= mp.mpf(d["F_x"]) * pts[-1][0]
    return V


def _fd_points(p, q):
    """Points of the flexible Doughty mechanism (mpf pairs)."""
    t1, t2 = q[0], q[0] + q[1]
    L, a, H = mp.mpf(p["L"]), mp.mpf(p["a"]), mp.mpf(p["H"])
    c1, s1, c2, s2 = mp.cos(t1), mp.sin(t1), mp.cos(t2), mp.sin(t2)
    B = (mp.mpf(0), L / 2 * (s1 + s2))
    J = (B[0] + L / 2 * c1, B[1] - L / 2 * s1)
    A = (J[0] + L / 2 * c2, J[1] - L / 2 * s2)
    P = (B[0] + a * c1, B[1] - a * s1)
    return dict(A=A, B=B, J=J, P=P, O=(H, mp.mpf(0)), t1=t1, t2=t2)


def _fd_spring_length(p, q):
    pt = _fd_points(p, q)
    return mp.sqrt((pt["P"][0] - pt["O"][0]) ** 2 + (pt["P"][1] - pt["O"][1]) ** 2)


def _fd_bodies(p):
    mC2 = mp.mpf(p["m_C"]) / 2
    Ih = mC2 * (mp.mpf(p["L"]) / 2) ** 2 / 12

    def mid(u, v):
        return ((u[0] + v[0]) / 2, (u[1] + v[1]) / 2)

    return [
        (mp.mpf(p["m_A"]), mp.mpf(0), lambda q: _fd_points(p, q)["A"], None),
        (mp.mpf(p["m_B"]), mp.mpf(0), lambda q: _fd_points(p, q)["B"], None),
        # the halves point along (cos t, -sin t): their rotation angle is -t
        (mC2, Ih, lambda q: mid(_fd_points(p, q)["B"], _fd_points(p, q)["J"]), lambda q: -q[0]),
        (mC2, Ih, lambda q: mid(_fd_points(p, q)["J"], _fd_points(p, q)["A"]),
         lambda q: -(q[0] + q[1])),
    ]


def _fd_dampers(p):
    return [(mp.mpf(p["b"]), lambda q: _fd_spring_length(p, q)),
            (mp.mpf(p["c_t"]), lambda q: q[1])]


def _fd_potential(p, q):
    pt = _fd_points(p, q)
    g = mp.mpf(p["g"])
    r = mp.sqrt((pt["P"][0] - pt["O"][0]) ** 2 + (pt["P"][1] - pt["O"][1]) ** 2)
    yc1 = (pt["B"][1] + pt["J"][1]) / 2
    yc2 = (pt["J"][1] + pt["A"][1]) / 2
    mC2 = mp.mpf(p["m_C"]) / 2
    V = mp.mpf(p["k_t"]) * q[1] ** 2 / 2
    V += mp.mpf(p["k"]) * (r - mp.mpf(p["l_ND"])) ** 2 / 2
    V += g * (mp.mpf(p["m_A"]) * pt["A"][1] + mp.mpf(p["m_B"]) * pt["B"][1]
              + mC2 * yc1 + mC2 * yc2)
    V -= mp.mpf(p["F"]) * pt["B"][1]
    return V


def _model(name, params):
    """(potential(q), bodies, dampers) for a mechanism."""
    _check_name(name)
    if name == "flexible_doughty":
        return (lambda q: _fd_potential(params, q)), _fd_bodies(params), _fd_dampers(params)
    d = _chain_data(name, params)
    return (lambda q: _chain_potential(d, q)), _chain_bodies(d), _chain_dampers(d)


# --------------------------------------------------------------------------------------------
# Public pointwise quantities
# --------------------------------------------------------------------------------------------

def _partial(f, q, k, order=1):
    """d^order f / dq_k^order at q (f takes a list)."""
    q = list(q)

    def g(x):
        qq = list(q)
        qq[k] = x
        return f(qq)

    return mp.diff(g, q[k], order)


def _gradient(f, q):
    return [_partial(f, q, k) for k in range(len(q))]


def _hessian(f, q):
    n = len(q)
    H = mp.matrix(n, n)
    for i in range(n):
        H[i, i] = _partial(f, q, i, 2)
        for j in range(i + 1, n):
            orders = [0] * n
            orders[i] += 1
            orders[j] += 1
            H[i, j] = H[j, i] = mp.diff(lambda *x: f(list(x)), tuple(q), tuple(orders))
    return H


@_at_dps
def potential(name, params, q):
    """Potential energy V (mpf) at q."""
    V, _, _ = _model(name, params)
    return V(_mpq(q))


@_at_dps
def generalised_force(name, params, q):
    """G_i = dV/dq_i (list of mpf), by mpmath.diff at 40 digits (Q = 0: forces are in V)."""
    V, _, _ = _model(name, params)
    return _gradient(V, _mpq(q))


generalized_force = generalised_force


@_at_dps
def stiffness(name, params, q):
    """K = dG/dq (= Hessian of V), an n x n mpmath matrix, by mpmath.diff."""
    V, _, _ = _model(name, params)
    return _hessian(V, _mpq(q))


@_at_dps
def kinetic_matrices(name, params, q):
    """(M, B): mass matrix (T = qdot^T M qdot / 2) and damping matrix (D = qdot^T B qdot / 2),
    mpmath matrices built from numerical Jacobians of the bodies' centres and angles and of
    the dampers' lengths / angles."""
    _, bodies, dampers = _model(name, params)
    q = _mpq(q)
    n = len(q)
    M = mp.matrix(n, n)
    for mass, inertia, centre, angle in bodies:
        Jx = [_partial(lambda qq: centre(qq)[0], q, k) for k in range(n)]
        Jy = [_partial(lambda qq: centre(qq)[1], q, k) for k in range(n)]
        Jw = [_partial(angle, q, k) for k in range(n)] if angle is not None else [0] * n
        for i in range(n):
            for j in range(n):
                M[i, j] += mass * (Jx[i] * Jx[j] + Jy[i] * Jy[j]) + inertia * Jw[i] * Jw[j]
    Bm = mp.matrix(n, n)
    for c, ext in dampers:
        e = [_partial(ext, q, k) for k in range(n)]
        for i in range(n):
            for j in range(n):
                Bm[i, j] += c * e[i] * e[j]
    return M, Bm


def _pair_score(pairs, w2):
    score = 0
    for a, b in pairs:
        prod = abs(a * b)
        if prod == 0:
            return mp.inf
        score += min(abs(mp.log(prod / abs(x))) if x != 0 else mp.inf for x in w2)
    return score


def _matchings(items):
    if not items:
        yield []
        return
    first = items[0]
    for k in range(1, len(items)):
        rest = items[1:k] + items[k + 1:]
        for m in _matchings(rest):
            yield [(first, items[k])] + m


def _mode_zetas(s_list, w2):
    """[(natural frequency, zeta)] per mode from the 2n damped eigenvalues (see module doc)."""
    modes_ = []
    reals = []
    for s in s_list:
        if abs(mp.im(s)) > mp.mpf(10) ** (-25) * max(abs(s), 1):
            if mp.im(s) > 0:
                modes_.append((abs(s), -mp.re(s) / abs(s)))
        else:
            reals.append(mp.re(s))
    if reals:
        best = min(_matchings(reals), key=lambda m: _pair_score(m, w2))
        for a, b in best:
            prod = a * b
            if prod > 0:
                wn = mp.sqrt(prod)
                modes_.append((wn, -(a + b) / (2 * wn)))
            else:
                modes_.append((mp.sqrt(abs(prod)), mp.nan))
    modes_.sort(key=lambda t: t[0])
    return modes_


@_at_dps
def modes(name, params, q):
    """Modal data at q (normally an equilibrium): dict with
    omega_squared (ascending, mpf), omega (sqrt, NaN where omega^2 < 0), shapes (mpmath matrix,
    mass-normalised columns, largest component of each positive), s (the 2n eigenvalues of
    M s^2 + B s + K sorted by |s| then Im s), zeta (one per mode, sorted by mode frequency,
    see module doc), M, B, K."""
    q = _mpq(q)
    n = len(q)
    M, Bm = kinetic_matrices(name, params, q)
    K = stiffness(name, params, q)
    Lc = mp.cholesky(M)
    Li = mp.inverse(Lc)
    A = Li * K * Li.T
    A = (A + A.T) / 2
    E, Qv = mp.eigsy(A)
    order = sorted(range(n), key=lambda i: E[i])
    w2 = [E[i] for i in order]
    shapes = mp.matrix(n, n)
    Phi = Li.T * Qv
    for col, i in enumerate(order):
        v = [Phi[r, i] for r in range(n)]
        big = max(range(n), key=lambda r: abs(v[r]))
        sign = 1 if v[big] >= 0 else -1
        for r in range(n):
            shapes[r, col] = sign * v[r]
    omega = [mp.sqrt(x) if x >= 0 else mp.nan for x in w2]
    Minv = mp.inverse(M)
    S = mp.matrix(2 * n, 2 * n)
    MK = -Minv * K
    MB = -Minv * Bm
    for i in range(n):
        S[i, n + i] = 1
        for j in range(n):
            S[n + i, j] = MK[i, j]
            S[n + i, n + j] = MB[i, j]
    ev = mp.eig(S, left=False, right=False)
    s = sorted(list(ev), key=lambda z: (abs(z), mp.im(z)))
    per_mode = _mode_zetas(s, w2)
    return dict(omega_squared=w2, omega=omega, shapes=shapes, s=s,
                zeta=[z for _, z in per_mode], M=M, B=Bm, K=K)


# --------------------------------------------------------------------------------------------
# Box (ranges) and bookkeeping
# --------------------------------------------------------------------------------------------

def box(name, params):
    """[(lo, hi, lo_open, hi_open)] per coordinate (floats)."""
    _check_name(name)
    if name == "flexible_doughty":
        return [(-math.pi, math.pi, True, False), (-math.pi, math.pi, True, True)]
    d = _chain_data(name, params)
    return [(a - math.pi, a + math.pi, True, False) for a in d["alpha"]]


def _mp_box(name, params):
    if name == "flexible_doughty":
        return [(-mp.pi, mp.pi, True, False), (-mp.pi, mp.pi, True, True)]
    d = _chain_data(name, params)
    return [(mp.mpf(a) - mp.pi, mp.mpf(a) + mp.pi, True, False) for a in d["alpha"]]


def _wrap_pi(x):
    """Map an angle into (-pi, pi] (mpf)."""
    two_pi = 2 * mp.pi
    y = x - two_pi * mp.floor((x + mp.pi) / two_pi)  # [-pi, pi)
    if y <= -mp.pi + mp.mpf(10) ** (-25):
        y += two_pi
    return y


def _in_box(name, params, q):
    """Snap q onto nearby box boundaries, then test the half-open box. Returns q or None."""
    q = list(q)
    if name == "flexible_doughty":
        q[0] = _wrap_pi(q[0])
    tol = mp.mpf(10) ** (-25)
    for i, (lo, hi, lo_open, hi_open) in enumerate(_mp_box(name, params)):
        if abs(q[i] - lo) < tol:
            q[i] = lo
        if abs(q[i] - hi) < tol:
            q[i] = hi
        if q[i] < lo or (lo_open and q[i] == lo):
            return None
        if q[i] > hi or (hi_open and q[i] == hi):
            return None
    return q


def _distance(name, q1, q2):
    diffs = [abs(a - b) for a, b in zip(q1, q2)]
    if name == "flexible_doughty":
        diffs[0] = min(diffs[0], abs(2 * mp.pi - diffs[0]))
    return max(diffs)


def _newton_polish(name, params, q0, max_iter=25):
    """Newton on the 40-digit G; returns (q, |G|, scale) or None when it fails."""
    V, _, _ = _model(name, params)
    q = _mpq(q0)
    n = len(q)
    for _ in range(max_iter):
        G = _gradient(V, q)
        K = _hessian(V, q)
        try:
            dq = mp.lu_solve(K, mp.matrix([-x for x in G]))
        except ZeroDivisionError:
            return None
        q = [q[i] + dq[i] for i in range(n)]
        step = max(abs(dq[i]) for i in range(n))
        if step > 1:
            return None  # wandered off: not the root this candidate stood for
        if step < mp.mpf(10) ** (-(DPS - 6)):
            break
    G = _gradient(V, q)
    K = _hessian(V, q)
    scale = 1 + mp.mnorm(K, 1)
    return q, max(abs(x) for x in G), scale


# --------------------------------------------------------------------------------------------
# Pendulum chains: 1-D reduction by walking down the chain
# --------------------------------------------------------------------------------------------

def _chain_loads(d):
    n = d["n"]
    P, Q = [], []
    for j in range(n):
        below = sum(d["m"][j + 1:]) + d["m_t"]
        P.append(d["g"] * d["l"][j] * (d["m"][j] / 2 + below))
        Q.append(d["F_x"] * d["l"][j])
    return P, Q


def _chain_walk(lib, d, P, Q, top, s):
    """Walk down from t_top = s (0-based index ``top``) with R restarting at 0.
    Returns (angles {j: t_j}, stop index, residual). ``lib`` is numpy or mpmath."""
    k, a = d["k"], d["alpha"]
    t = {top: s}
    R = 0
    for j in range(top, -1, -1):
        R = R + P[j] * lib.cos(t[j]) + Q[j] * lib.sin(t[j])
        if j == 0:
            return t, 0, k[0] * (t[0] - a[0]) + R
        if k[j] == 0:
            return t, j, R
        t[j - 1] = t[j] - a[j] + R / k[j]
    raise AssertionError("unreachable")


def _roots_1d(f_np, f_mp, lo, hi, angles_np=None):
    """All sign changes (and parabola near-misses) of f on [lo, hi], refined at 40 digits."""
    N = 4096
    for _ in range(6):
        s = np.linspace(lo, hi, N)
        r = f_np(s)
        if angles_np is None:
            break
        moves = angles_np(s)
        worst = max(np.max(np.abs(np.diff(x))) for x in moves)
        if worst <= 0.004 or N >= 2_000_000:
            break
        N = min(2_000_000, int(N * worst / 0.003) + 1)
    h = s[1] - s[0]
    brackets = []
    zero_idx = np.nonzero(r == 0)[0]
    roots = [mp.mpf(float(s[i])) for i in zero_idx]
    change = np.nonzero(r[:-1] * r[1:] < 0)[0]
    for i in change:
        brackets.append((float(s[i]), float(s[i + 1])))
    # near-miss net: an interior extremum whose interpolating parabola crosses zero
    ext = np.nonzero((np.diff(np.sign(np.diff(r))) != 0))[0] + 1
    for i in ext:
        if i <= 0 or i >= len(s) - 1:
            continue
        y0, y1, y2 = r[i - 1], r[i], r[i + 1]
        if y0 * y1 <= 0 or y1 * y2 <= 0:
            continue
        c2 = (y0 - 2 * y1 + y2) / 2
        c1 = (y2 - y0) / 2
        if c2 == 0:
            continue
        u = -c1 / (2 * c2)
        vert = y1 - c1 * c1 / (4 * c2)
        if vert * y1 < 0 and abs(u) <= 1.5:
            disc = math.sqrt(c1 * c1 - 4 * c2 * y1)
            for x in ((-c1 - disc) / (2 * c2), (-c1 + disc) / (2 * c2)):
                roots.append(("guess", float(s[i] + x * h)))
    out = []
    for a_, b_ in brackets:
        try:
            x = mp.findroot(f_mp, (mp.mpf(a_), mp.mpf(b_)), solver="anderson", verify=False)
        except (ZeroDivisionError, ValueError):
            x = None
        if x is None or not (a_ - h <= x <= b_ + h):
            x = mp.findroot(f_mp, (mp.mpf(a_), mp.mpf(b_)), solver="bisect", verify=False)
        out.append(x)
    for x in roots:
        if isinstance(x, tuple):
            try:
                y = mp.findroot(f_mp, mp.mpf(x[1]), solver="secant", verify=False)
            except (ZeroDivisionError, ValueError):
                continue
            if abs(y - x[1]) < 2 * h and abs(f_mp(y)) < mp.mpf(10) ** (-20) * (1 + abs(f_mp(mp.mpf(x[1])))):
                out.append(y)
        else:
            out.append(x)
    return out


def _chain_candidates(name, params):
    d = _chain_data(name, params)
    P, Q = _chain_loads(d)
    n = d["n"]
    margin = 0.05
    memo = {}

    def segment(top):
        """List of dicts {j: t_j (mpf)} for j = 0..top solving the segment below top."""
        if top in memo:
            return memo[top]
        centre = sum(d["alpha"][: top + 1])
        half = (top + 1) * math.pi + margin

        def f_np(s):
            return _chain_walk(np, d, P, Q, top, s)[2]

        def f_mp(s):
            return _chain_walk(mp, d, P, Q, top, s)[2]

        def angles_np(s):
            t, _, _ = _chain_walk(np, d, P, Q, top, s)
            return list(t.values())

        s_roots = _roots_1d(f_np, f_mp, centre - half, centre + half, angles_np)
        sols = []
        for s in s_roots:
            t, stop, _ = _chain_walk(mp, d, P, Q, top, s)
            if stop == 0:
                sols.append(t)
            else:
                for below in segment(stop - 1):
                    tt = dict(below)
                    tt.update(t)
                    sols.append(tt)
        memo[top] = sols
        return sols

    cands = []
    for t in segment(n - 1):
        q = [t[0]] + [t[j] - t[j - 1] for j in range(1, n)]
        cands.append(q)
    return cands


# --------------------------------------------------------------------------------------------
# flexible_doughty: 2-D scan with the complex-step G
# --------------------------------------------------------------------------------------------

def _fd_potential_np(p, t1, dl):
    """V in numpy (float or complex arrays), same formulas as _fd_potential."""
    L, a, H, g = p["L"], p["a"], p["H"], p["g"]
    t2 = t1 + dl
    c1, s1, s2 = np.cos(t1), np.sin(t1), np.sin(t2)
    yB = L / 2 * (s1 + s2)
    yJ = yB - L / 2 * s1
    yA = yJ - L / 2 * s2
    r = np.sqrt((a * c1 - H) ** 2 + (yB - a * s1) ** 2)
    mC2 = p["m_C"] / 2
    return (p["k_t"] * dl ** 2 / 2 + p["k"] * (r - p["l_ND"]) ** 2 / 2
            + g * (p["m_A"] * yA + p["m_B"] * yB + mC2 * (yB + yJ) / 2 + mC2 * (yJ + yA) / 2)
            - p["F"] * yB)


def _fd_G_np(p, t1, dl):
    h = 1e-30
    g1 = np.imag(_fd_potential_np(p, t1 + 1j * h, dl + 0j)) / h
    g2 = np.imag(_fd_potential_np(p, t1 + 0j, dl + 1j * h)) / h
    return g1, g2


def _fd_candidates(params, n1=720, n2=720):
    margin_cells = 4
    h1 = 2 * math.pi / n1
    t1 = np.linspace(-math.pi - margin_cells * h1, math.pi + margin_cells * h1,
                     n1 + 2 * margin_cells + 1)
    dl = np.linspace(-math.pi, math.pi, n2 + 1)
    T, D = np.meshgrid(t1, dl, indexing="ij")
    g1, g2 = _fd_G_np(params, T, D)

    def changes(g):
        c = np.stack([g[:-1, :-1], g[1:, :-1], g[:-1, 1:], g[1:, 1:]])
        return (c.min(axis=0) <= 0) & (c.max(axis=0) >= 0)

    cells = np.argwhere(changes(g1) & changes(g2))
    if len(cells) == 0:
        return []
    x = (t1[cells[:, 0]] + t1[cells[:, 0] + 1]) / 2
    y = (dl[cells[:, 1]] + dl[cells[:, 1] + 1]) / 2
    x0, y0 = x.copy(), y.copy()
    hstep = 1e-6
    ok = np.zeros(len(x), dtype=bool)
    for _ in range(40):
        G1, G2 = _fd_G_np(params, x, y)
        a1, a2 = _fd_G_np(params, x + hstep, y)
        b1, b2 = _fd_G_np(params, x - hstep, y)
        c1, c2 = _fd_G_np(params, x, y + hstep)
        e1, e2 = _fd_G_np(params, x, y - hstep)
        J11, J21 = (a1 - b1) / (2 * hstep), (a2 - b2) / (2 * hstep)
        J12, J22 = (c1 - e1) / (2 * hstep), (c2 - e2) / (2 * hstep)
        det = J11 * J22 - J12 * J21
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = -(J22 * G1 - J12 * G2) / det
            dy = -(-J21 * G1 + J11 * G2) / det
        dx = np.where(np.isfinite(dx), dx, 0.0)
        dy = np.where(np.isfinite(dy), dy, 0.0)
        # limit steps so that a candidate cannot jump across the map
        lim = 4 * h1
        big = np.maximum(np.abs(dx), np.abs(dy))
        fac = np.where(big > lim, lim / np.maximum(big, 1e-300), 1.0)
        x = x + fac * dx
        y = y + fac * dy
        ok = big < 1e-13
        if ok.all():
            break
    G1, G2 = _fd_G_np(params, x, y)
    near = (np.abs(x - x0) < 6 * h1) & (np.abs(y - y0) < 6 * (2 * math.pi / n2))
    keep = near & np.isfinite(G1) & np.isfinite(G2)
    pts = np.stack([x[keep], y[keep]], axis=1)
    # cheap float dedupe before the 40-digit polish
    uniq = []
    for xy in pts:
        xy0 = np.array([(xy[0] + math.pi) % (2 * math.pi) - math.pi, xy[1]])
        if all(max(min(abs(xy0[0] - u[0]), 2 * math.pi - abs(xy0[0] - u[0])),
                   abs(xy0[1] - u[1])) > 1e-7 for u in uniq):
            uniq.append(xy0)
    return [list(u) for u in uniq]


# --------------------------------------------------------------------------------------------
# Equilibria
# --------------------------------------------------------------------------------------------

@_at_dps
def equilibria(name, params):
    """Every zero of G in the box, sorted by q. Each is a dict:
    q (tuple of floats), q_mp (tuple of mpf), stable (K positive definite),
    asymptotically_stable (every damped eigenvalue has Re s < 0), omega_squared, omega,
    zeta (floats; NaN where undefined), s (complex), residual (max |G|, float)."""
    _check_name(name)
    if name == "flexible_doughty":
        cands = _fd_candidates(params)
    else:
        cands = _chain_candidates(name, params)
    found = []
    for q0 in cands:
        pre = _in_box(name, params, _mpq(q0))
        # a candidate far outside the box cannot polish into it
        if pre is None and not _near_box(name, params, _mpq(q0)):
            continue
        res = _newton_polish(name, params, q0)
        if res is None:
            continue
        q, gmax, scale = res
        if gmax > mp.mpf(10) ** (-(DPS - 12)) * scale:
            continue
        q = _in_box(name, params, q)
        if q is None:
            continue
        if any(_distance(name, q, other) < 1e-9 for other in found):
            continue
        found.append(q)
    found.sort(key=lambda q: [float(x) for x in q])
    out = []
    for q in found:
        md = modes(name, params, q)
        w2 = md["omega_squared"]
        out.append(dict(
            q=tuple(float(x) for x in q),
            q_mp=tuple(q),
            stable=bool(min(w2) > 0),
            asymptotically_stable=bool(all(mp.re(z) < 0 for z in md["s"])),
            omega_squared=[float(x) for x in w2],
            omega=[float(x) for x in md["omega"]],
            zeta=[float(z) for z in md["zeta"]],
            s=[complex(z) for z in md["s"]],
            residual=float(max(abs(x) for x in generalised_force(name, params, q))),
        ))
    return out


def _near_box(name, params, q, slack=0.1):
    if name == "flexible_doughty":
        return abs(q[1]) < mp.pi + slack
    return all(lo - slack <= x <= hi + slack
               for x, (lo, hi, _, _) in zip(q, _mp_box(name, params)))


# --------------------------------------------------------------------------------------------
# Closed forms and one-degree-of-freedom checks
# --------------------------------------------------------------------------------------------

@_at_dps
def hanging_frequencies(params):
    """Natural frequencies (ascending, mpf) of the double pendulum hanging straight down
    (theta_1 = theta_2 = -pi/2), in ABSOLUTE angles (theta_1, theta_2) -- the frequencies do
    not depend on the coordinates. Textbook two-uniform-bar form
        M = [[(m1/3 + m2) l1^2, m2 l1 l2 / 2], [m2 l1 l2 / 2, m2 l2^2 / 3]],
        K = g diag((m1/2 + m2) l1, m2 l2 / 2),
    extended to a tip mass m_t (m2 -> m2 + m_t in the coupling terms, + m_t l^2 terms) and to
    torsional springs (K += [[k1 + k2, -k2], [-k2, k2]]); with m_t = k_1 = k_2 = 0 it is exactly
    the textbook form. det(K - w^2 M) = 0 is solved as a quadratic in w^2. Raises ValueError
    if hanging is not an equilibrium (springs loaded there, or F_x != 0)."""
    d = _chain_data("double_pendulum", params)
    l1, l2 = (mp.mpf(x) for x in d["l"])
    m1, m2 = (mp.mpf(x) for x in d["m"])
    k1, k2 = (mp.mpf(x) for x in d["k"])
    mt, g = mp.mpf(d["m_t"]), mp.mpf(d["g"])
    a1, a2 = (mp.mpf(x) for x in d["alpha"])
    if d["F_x"] != 0 or (k1 != 0 and abs(a1 + mp.pi / 2) > 1e-12) or (k2 != 0 and abs(a2) > 1e-12):
        raise ValueError("hanging straight down is not an equilibrium for these parameters")
    M11 = (m1 / 3 + m2 + mt) * l1 ** 2
    M12 = (m2 / 2 + mt) * l1 * l2
    M22 = (m2 / 3 + mt) * l2 ** 2
    K11 = g * (m1 / 2 + m2 + mt) * l1 + k1 + k2
    K12 = -k2
    K22 = g * (m2 / 2 + mt) * l2 + k2
    A = M11 * M22 - M12 ** 2
    Bq = K11 * M22 + K22 * M11 - 2 * K12 * M12
    C = K11 * K22 - K12 ** 2
    disc = mp.sqrt(Bq ** 2 - 4 * A * C)
    w2 = sorted([(Bq - disc) / (2 * A), (Bq + disc) / (2 * A)])
    return [mp.sqrt(x) for x in w2]


@_at_dps
def rigid_doughty_equilibria(params):
    """Doughty's own 1-DOF mechanism (the flexible one with delta forced to 0, so k_t and c_t
    play no part): list of dicts theta, M, B, K (= dG/dtheta), omega_n = sqrt(K/M),
    zeta = B / (2 sqrt(K M)) (NaN when K <= 0), stable. theta in (-pi, pi]."""
    p = dict(params)

    def V(t):
        return _fd_potential(p, [t, mp.mpf(0)])

    def f_np(t):
        h = 1e-30
        return np.imag(_fd_potential_np(p, t + 1j * h, 0j * t)) / h

    def f_mp(t):
        return mp.diff(V, t)

    roots = _roots_1d(f_np, f_mp, -math.pi - 0.01, math.pi + 0.01)
    out = []
    for t in roots:
        for _ in range(5):
            t = t - mp.diff(V, t) / mp.diff(V, t, 2)
        t = _wrap_pi(t)
        if any(min(abs(t - u["theta_mp"]), 2 * mp.pi - abs(t - u["theta_mp"])) < 1e-9
               for u in out):
            continue
        Mq, Bq = kinetic_matrices("flexible_doughty", p, [t, 0])
        Kt = mp.diff(V, t, 2)
        M, Bv = Mq[0, 0], Bq[0, 0]
        out.append(dict(theta_mp=t, theta=float(t), M=float(M), B=float(Bv), K=float(Kt),
                        omega_n=float(mp.sqrt(Kt / M)) if Kt > 0 else float("nan"),
                        zeta=float(Bv / (2 * mp.sqrt(Kt * M))) if Kt > 0 else float("nan"),
                        stable=bool(Kt > 0)))
    out.sort(key=lambda u: u["theta"])
    return out


# --------------------------------------------------------------------------------------------
# Demo / self-check
# --------------------------------------------------------------------------------------------

def _demo():
    import time

    for name in NAMES:
        t0 = time.perf_counter()
        eqs = equilibria(name, EXAMPLES[name])
        dt = time.perf_counter() - t0
        print(f"{name}: {len(eqs)} equilibria ({dt:.2f} s)")
        for e in eqs:
            print("  q =", tuple(f"{x:.12f}" for x in e["q"]), "stable" if e["stable"] else "unstable",
                  "omega =", [f"{x:.6f}" for x in e["omega"]],
                  "zeta =", [f"{x:.6f}" for x in e["zeta"]], f"|G| = {e['residual']:.1e}")

    p = dict(EXAMPLES["flexible_doughty"], k_t=1e6)
    rigid = rigid_doughty_equilibria(p)
    flex = equilibria("flexible_doughty", p)
    print("Doughty rigid (delta = 0):")
    for u in rigid:
        print(f"  theta = {u['theta']:.12f} omega_n = {u['omega_n']:.6f} zeta = {u['zeta']:.6f}")
    print("flexible_doughty, k_t = 1e6:")
    for e in flex:
        print("  q =", e["q"], "omega =", e["omega"], "zeta =", e["zeta"])

    ph = dict(EXAMPLES["double_pendulum"], k_1=0.0, k_2=0.0, m_t=0.0, alpha_1=-_HALF_PI)
    print("hanging closed form:", [float(w) for w in hanging_frequencies(ph)])
    print("modes at hanging:   ", [float(w) for w in modes("double_pendulum", ph, [-mp.pi / 2, 0])["omega"]])


if __name__ == "__main__":
    _demo()
