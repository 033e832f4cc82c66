"""Independent numerical references for the statics of four planar one-degree-of-freedom
mechanisms: ``slider_crank``, ``four_bar``, ``torsion_pendulum`` and ``doughty``.

Nothing here shares anything with the compiler's derivation: no SymPy, no import from
``codegen``, no formula for the generalised force G. Each mechanism is modelled from its
geometry only:

* positions are found by a *numerical* position analysis -- Newton's method on the
  loop-closure (constraint) equation, started from a geometric guess in the requested
  assembly mode, and the result checked to be in that mode;
* the potential energy V is summed from its physical contributions (gravity on every body's
  centre, springs from their lengths, constant forces, constant torque);
* G = dV/dtheta is a numerical derivative of V: ``mpmath.diff`` at >= 30 digits for the
  reference values, a complex step (Im V(theta + i h) / h, exact to rounding in double
  precision, no cancellation) for the vectorised scan;
* equilibria are the sign changes of G found by a dense scan and refined by ``brentq`` on the
  high-precision G, with jumps and blow-ups of G rejected.

The mechanisms' geometry, parameter names and example values follow ``MECHANISMS.md`` (and,
for Doughty's mechanism, the paper); they are typed in here so that nothing is read at run
time. Conventions: planar, X right, Y up, gravity g along -Y, angles counter-clockwise from
+X, uniform bars with their centre at mid-length. V = sum m g y_centre + sum 1/2 k
(length - free length)^2 (+ 1/2 k_t (theta - theta_0)^2) - sum F . x_point - T theta.

Interface: ``REFERENCES[name]`` is an object with

* ``EXAMPLE`` -- the example parameters (a fresh dict each time it is read);
* ``MODES`` -- the assembly modes: (+1, -1) for slider_crank and four_bar, (+1,) otherwise;
* ``theta_range(params)`` -- (lo, hi), the range being lo < theta <= hi;
* ``assembles(params, theta)`` -- the distance condition for the mechanism to exist;
* ``positions(params, theta, mode=+1)`` -- dict of named points (x, y) as mpf, or None;
* ``potential(params, theta, mode=+1)`` / ``potential_terms`` -- V (mpf) / its parts;
* ``generalized_force(params, theta, mode=+1)`` / ``generalized_force_terms`` -- G = dV/dtheta;
* ``generalized_force_array(params, thetas, mode=+1)`` -- the double-precision scan values;
* ``equilibria(params, mode=+1, samples=20000)`` -- sorted list of floats.

``params`` may be None (the example values); otherwise it must name every parameter (extra
names are an error, so a misspelt name cannot pass silently).

Known limitations of ``equilibria``: it finds sign changes of G. A double root (G touches zero
without changing sign) is not reported, nor is a pair of roots closer together than the scan's
step (2 pi / samples; 0.018 deg by default), since G does not change sign between two samples
there. A mechanism with G identically zero (no loads) has every theta as an equilibrium and
``equilibria`` returns []. A genuine root within ~1e-6 rad of a jump or blow-up of G may be
misjudged as part of the singularity. For the torsion pendulum a root exactly at the open end
theta_0 - pi is outside the range and dropped.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
from scipy.optimize import brentq

__all__ = ["REFERENCES", "WORK_DPS", "SliderCrank", "FourBar", "TorsionPendulum", "Doughty"]

#: Decimal digits of the high-precision evaluations (potential, generalised force).
WORK_DPS = 30

_mp = mpmath.mp
_H_COMPLEX_STEP = 1e-20


# --------------------------------------------------------------------------- arithmetic
# The geometry and energy are written once and evaluated by one of two back-ends: mpmath
# scalars at the working precision (the reference values), or numpy arrays of complex
# numbers (the complex-step scan). Only analytic operations are used on the state, so a
# complex step through the numpy back-end differentiates exactly.


class _MP:
    """Scalar mpmath back-end at the current ``mp`` precision."""

    vector = False
    sin = staticmethod(mpmath.sin)
    cos = staticmethod(mpmath.cos)
    sqrt = staticmethod(mpmath.sqrt)

    @staticmethod
    def num(x):
        return mpmath.mpf(x)

    @staticmethod
    def pi():
        return +_mp.pi

    @staticmethod
    def real_angle(dx, dy):
        return mpmath.atan2(dy, dx)

    @staticmethod
    def tol(scale):
        return 16 * _mp.eps * scale

    @staticmethod
    def maxiter():
        # Quadratic convergence needs ~10 steps; at a limit position (double root) Newton
        # only halves the error each step, so allow two per bit.
        return 40 + 2 * _mp.prec


class _NP:
    """Vectorised numpy back-end (complex arrays for the complex step)."""

    vector = True
    sin = staticmethod(np.sin)
    cos = staticmethod(np.cos)
    sqrt = staticmethod(np.sqrt)

    @staticmethod
    def num(x):
        return float(x)

    @staticmethod
    def pi():
        return math.pi

    @staticmethod
    def real_angle(dx, dy):
        return np.arctan2(np.real(dy), np.real(dx))

    @staticmethod
    def tol(scale):
        return 1e-14 * scale

    @staticmethod
    def maxiter():
        return 120


def _newton(xp, residual, x0, scale):
    """Newton's method on a scalar equation (elementwise for arrays).

    ``residual(x, idx)`` returns (f, df/dx) at x; ``idx`` selects the elements of the
    theta-dependent data that x belongs to (None for a scalar). Stops when the step is below
    the back-end's tolerance (then takes one more step: convergence is quadratic there) or
    after the back-end's iteration cap (reached only next to a limit position, where the
    root is double and its accuracy is limited to ~sqrt(eps) anyway).

    Arrays: only the elements not yet converged are iterated. mpmath above double
    precision: the iteration first runs at double precision from the geometric guess, then
    polishes at full precision from there (a few quadratic steps instead of many); if the
    double-precision pass does not converge (a double root: the two modes about to meet) the
    full-precision iteration starts from the geometric guess itself, so that it approaches
    the root from the requested mode's side."""
    tol = xp.tol(scale)
    if xp.vector:
        x = np.array(x0, dtype=complex)
        active = np.arange(x.size)
        for _ in range(xp.maxiter()):
            f, df = residual(x[active], active)
            step = f / df
            x[active] = x[active] - step
            # Converged (or hopeless: nan) elements take one last step and leave the set.
            done = ~(np.abs(step) > tol)
            if np.any(done):
                idx = active[done]
                f, df = residual(x[idx], idx)
                x[idx] = x[idx] - f / df
                active = active[~done]
            if active.size == 0:
                break
        return x
    if _mp.prec > 80:
        with mpmath.workprec(53):
            x, converged = _newton_scalar(xp, residual, x0, xp.tol(scale))
        if converged:  # else (next to a limit position) start again from the guess
            x0 = x
    return _newton_scalar(xp, residual, x0, tol)[0]


def _newton_scalar(xp, residual, x, tol):
    for _ in range(xp.maxiter()):
        f, df = residual(x, None)
        step = f / df
        x = x - step
        if abs(step) <= tol:
            f, df = residual(x, None)
            return x - f / df, True
    return x, False


def _at(value, idx):
    """The elements idx of a theta-dependent array (scalars and idx None pass through)."""
    if idx is None or np.ndim(value) == 0:
        return value
    return value[idx]


def _dist(xp, p, q):
    """Euclidean distance, the positive square root (analytic for a complex step)."""
    return xp.sqrt((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2)


def _mid(p, q):
    return ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)


def _wrong_side(xp, side):
    """Whether a (dimensionless) signed distance from the boundary between the assembly
    modes is negative beyond rounding. At a limit position the two modes meet and the
    double root is only accurate to ~sqrt(eps), hence the slack (eps^(1/3))."""
    if xp.vector:
        return bool(np.any(side < -1e-7))
    return side < -mpmath.mpf(2) ** (-_mp.prec // 3)


class ModeError(RuntimeError):
    """The numerical position analysis converged outside the requested assembly mode."""


# --------------------------------------------------------------------------- base class


class _Reference:
    name: str = ""
    PARAMS: tuple = ()
    _EXAMPLE: dict = {}
    MODES: tuple = (+1,)
    #: True when theta and theta + 2 pi are the same state (range (-pi, pi]).
    periodic = True

    # ---- to be provided by each mechanism (xp is _MP or _NP)
    def _margin_np(self, p, theta):
        """The distance condition as a margin: >= 0 exactly where the mechanism assembles
        (array over real angles)."""
        return np.ones(np.shape(theta))

    def _assembles_np(self, p, theta):
        return self._margin_np(p, theta) >= 0

    def _points(self, xp, p, theta, mode):  # dict name -> (x, y)
        raise NotImplementedError

    def _energy_terms(self, xp, p, theta, pts):  # dict name -> V part
        raise NotImplementedError

    # ---- parameters
    @property
    def EXAMPLE(self):
        return dict(self._EXAMPLE)

    def _params(self, params):
        if params is None:
            params = self._EXAMPLE
        unknown = set(params) - set(self.PARAMS)
        if unknown:
            raise ValueError(f"{self.name}: unknown parameters {sorted(unknown)}")
        missing = set(self.PARAMS) - set(params)
        if missing:
            raise ValueError(f"{self.name}: missing parameters {sorted(missing)}")
        return {k: params[k] for k in self.PARAMS}

    def _check_mode(self, mode):
        if mode not in self.MODES:
            raise ValueError(f"{self.name}: assembly mode {mode!r} not in {self.MODES}")

    def theta_range(self, params=None):
        """(lo, hi): theta's range is lo < theta <= hi."""
        return (-math.pi, math.pi)

    # ---- assemblability
    def assembles(self, params, theta):
        """Whether the mechanism can be assembled at theta (a distance condition, evaluated
        at >= WORK_DPS digits like ``positions``)."""
        p = self._params(params)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            return bool(self._assembles_mp(self._mp_params(p), mpmath.mpf(theta)))

    def _assembles_mp(self, p, theta):
        return True

    # ---- high-precision reference values
    def _mp_params(self, p):
        return {k: mpmath.mpf(v) for k, v in p.items()}

    def _solve_mp(self, p, theta, mode):
        if not self._assembles_mp(p, theta):
            return None
        return self._points(_MP, p, theta, mode)

    def positions(self, params, theta, mode=+1):
        """The points of the mechanism at theta in the given assembly mode, as a dict of
        (x, y) pairs of mpf at >= WORK_DPS digits; None where it cannot be assembled."""
        self._check_mode(mode)
        p = self._params(params)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            return self._solve_mp(self._mp_params(p), mpmath.mpf(theta), mode)

    def _terms_at(self, p, theta, mode):
        # p: mpf params; theta: mpf; at the current precision.
        pts = self._solve_mp(p, theta, mode)
        if pts is None:
            return None
        return self._energy_terms(_MP, p, theta, pts)

    def potential_terms(self, params, theta, mode=+1):
        """The parts of V (gravity, spring(s), force, torque) at theta; None if unassembled."""
        self._check_mode(mode)
        p = self._params(params)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            return self._terms_at(self._mp_params(p), mpmath.mpf(theta), mode)

    def potential(self, params, theta, mode=+1):
        """V at theta (mpf at >= WORK_DPS digits); None where the mechanism cannot be
        assembled."""
        self._check_mode(mode)
        p = self._params(params)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            terms = self._terms_at(self._mp_params(p), mpmath.mpf(theta), mode)
            return None if terms is None else mpmath.fsum(terms.values())

    def _diff(self, p, theta, mode, part):
        pm = self._mp_params(p)

        def f(t):
            terms = self._terms_at(pm, t, mode)
            if terms is None:
                raise _NotAssembled
            return mpmath.fsum(terms.values()) if part is None else terms[part]

        try:
            return mpmath.diff(f, mpmath.mpf(theta))
        except _NotAssembled:
            return None

    def generalized_force(self, params, theta, mode=+1):
        """G = dV/dtheta by mpmath.diff of the potential at >= WORK_DPS digits; None where
        the mechanism cannot be assembled at theta or infinitesimally beside it (a limit
        position, where G is infinite)."""
        self._check_mode(mode)
        p = self._params(params)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            return self._diff(p, theta, mode, None)

    def generalized_force_terms(self, params, theta, mode=+1):
        """d/dtheta of each part of V (same keys as ``potential_terms``); None if
        unassembled. Their sum is G; the sum of their magnitudes is the scale of G."""
        self._check_mode(mode)
        p = self._params(params)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            names = self._terms_at(self._mp_params(p), mpmath.mpf(theta), mode)
            if names is None:
                return None
            out = {}
            for name in names:
                d = self._diff(p, theta, mode, name)
                if d is None:
                    return None
                out[name] = d
            return out

    # ---- double-precision vectorised scan
    def potential_array(self, params, thetas, mode=+1):
        """V at an array of real angles in double precision (nan where unassembled)."""
        self._check_mode(mode)
        p = self._params(params)
        return self._potential_np(p, np.asarray(thetas, dtype=float), mode).real

    def _potential_np(self, p, thetas, mode, step=0.0):
        shape = np.shape(thetas)
        thetas = np.atleast_1d(thetas).ravel()
        margin = self._margin_np(p, thetas)
        ok = margin >= 0
        # Unassemblable angles are computed at the most comfortably assemblable one instead
        # (then discarded), so that the vectorised Newton has nothing to diverge on.
        if not np.all(ok):
            if not np.any(ok):
                return np.full(shape, complex(np.nan, np.nan))
            thetas = np.where(ok, thetas, thetas[np.argmax(margin)])
        z = thetas + 1j * step if step else thetas.astype(complex)
        with np.errstate(all="ignore"):
            pts = self._points(_NP, p, z, mode)
            terms = self._energy_terms(_NP, p, z, pts)
            v = sum(terms.values())
        v = np.asarray(v, dtype=complex) * np.ones(thetas.shape)
        v[~ok] = complex(np.nan, np.nan)
        return v.reshape(shape)

    def generalized_force_array(self, params, thetas, mode=+1):
        """G at an array of real angles by a complex step in double precision (accurate to
        rounding; nan where unassembled)."""
        self._check_mode(mode)
        p = self._params(params)
        thetas = np.asarray(thetas, dtype=float)
        return self._g_np(p, thetas, mode)

    def _g_np(self, p, thetas, mode):
        v = self._potential_np(p, thetas, mode, step=_H_COMPLEX_STEP)
        return v.imag / _H_COMPLEX_STEP

    # ---- equilibria
    def _boundary_points(self, p, grid, ok):
        """Extra samples next to each limit of the assemblable region, clustering
        geometrically towards it, so that a sign change of G between the last regular
        sample and the limit (where G blows up) is not missed."""
        extra = []
        for i in np.nonzero(ok[:-1] != ok[1:])[0]:
            good, bad = (grid[i], grid[i + 1]) if ok[i] else (grid[i + 1], grid[i])
            for _ in range(80):  # bisection of the distance condition
                mid = 0.5 * (good + bad)
                if mid in (good, bad):
                    break
                if self._assembles_np(p, np.asarray([mid]))[0]:
                    good = mid
                else:
                    bad = mid
            span = good - (grid[i] if ok[i] else grid[i + 1])
            for k in range(1, 21):
                t = good - span * 2.0**-k
                if t != good and self._assembles_np(p, np.asarray([t]))[0]:
                    extra.append(t)
        return extra

    def equilibria(self, params=None, mode=+1, samples=20000):
        """Every theta in the range where G changes sign (sorted floats), found by a dense
        double-precision scan restricted to where the mechanism assembles, each bracket
        refined by brentq on the high-precision G (to ~1e-15 rad) and kept only if G
        behaves like a simple root there (not a jump or blow-up). See the module docstring
        for what is not found."""
        self._check_mode(mode)
        p = self._params(params)
        lo, hi = self.theta_range(p)
        n = int(samples)
        step = (hi - lo) / n
        # One extra sample past each end: for a periodic mechanism the last interval
        # [hi, hi + step] is the first one again, but it also holds the wrap-around point
        # (float(pi) is below pi and float(-pi) above -pi, so a root at exactly +-pi lies
        # between the grid's two ends); for the torsion pendulum it catches a root at the
        # closed end hi. Roots outside the range are mapped back or dropped below.
        grid = lo + step * np.arange(-1, n + 2)
        grid[1], grid[n + 1] = lo, hi
        ok = self._assembles_np(p, grid)
        extra = self._boundary_points(p, grid, ok)
        if extra:
            grid = np.unique(np.concatenate([grid, extra]))
        g = self._g_np(p, grid, mode)

        brackets = []
        prev = None  # index of the last finite, nonzero sample of the current run
        finite = np.isfinite(g)
        for i in range(len(grid)):
            if not finite[i]:
                prev = None
                continue
            if g[i] == 0.0:
                continue
            if prev is not None and (g[prev] > 0) != (g[i] > 0):
                brackets.append((prev, i))
            prev = i

        def gmp(t):
            with mpmath.workdps(WORK_DPS):
                val = self._diff(p, t, mode, None)
            if val is None:
                raise _NotAssembled
            return val

        roots = []
        for ia, ib in brackets:
            try:
                x = self._refine(grid, finite, ia, ib, gmp)
            except _NotAssembled:  # the bracket touches an unassemblable point
                continue
            if x is None or not self._is_simple_root(x, gmp):
                continue
            # Within a few ulp of an end counts as at the end (the float ends are rounded).
            slack = 8 * np.spacing(max(abs(lo), abs(hi)))
            if self.periodic:
                if x > hi + slack:
                    x -= 2 * math.pi
                elif x <= lo + slack:
                    x += 2 * math.pi
            if not (lo + slack < x <= hi + slack):
                continue
            roots.append(min(x, hi))
        roots.sort()
        out = []
        for x in roots:
            if not out or abs(x - out[-1]) > 1e-9:
                out.append(x)
        if self.periodic and len(out) > 1 and out[0] + 2 * math.pi - out[-1] <= 1e-9:
            out.pop(0)
        return out

    @staticmethod
    def _refine(grid, finite, ia, ib, gmp):
        a, b = float(grid[ia]), float(grid[ib])
        ga, gb = gmp(a), gmp(b)
        if ga == 0:
            return a
        if gb == 0:
            return b
        if (ga > 0) == (gb > 0):
            # The double-precision sign at an end was rounding noise next to a root: widen
            # the bracket by one sample each side (still within the assembled run).
            if ia == 0 or ib + 1 >= len(grid) or not (finite[ia - 1] and finite[ib + 1]):
                return None
            a, b = float(grid[ia - 1]), float(grid[ib + 1])
            ga, gb = gmp(a), gmp(b)
            if (ga > 0) == (gb > 0):
                return None
        return brentq(lambda t: float(gmp(t)), a, b, xtol=1e-15, rtol=8.9e-16, maxiter=200)

    @staticmethod
    def _is_simple_root(x, gmp):
        """G changes sign at x and shrinks in proportion to the distance from x (a simple
        root) rather than keeping its size (a jump) or growing (a limit position)."""
        try:
            far = [abs(gmp(x - 1e-6)), abs(gmp(x + 1e-6))]
            gl, gr = gmp(x - 1e-9), gmp(x + 1e-9)
        except _NotAssembled:
            return False
        if gl == 0 or gr == 0 or (gl > 0) == (gr > 0):
            return False
        return max(abs(gl), abs(gr)) <= 0.05 * max(far)


class _NotAssembled(Exception):
    pass


# --------------------------------------------------------------------------- mechanisms


class SliderCrank(_Reference):
    """Offset slider-crank with a return spring anchored off the slide (MECHANISMS.md).

    Crank O-A (O at the origin, length R, angle theta, mass m_1), rod A-B (length l, mass
    m_2), slider B (mass m_3) on the line y = e. Mode +1: the slider is to the right of the
    crank pin (x_B >= x_A); mode -1: to its left. Spring k, free length l_0, from S = (x_S,
    y_S) to B; force F on the slider along +X; torque T on the crank (counter-clockwise)."""

    name = "slider_crank"
    PARAMS = ("R", "l", "e", "m_1", "m_2", "m_3", "k", "l_0", "x_S", "y_S", "b", "F", "T", "g")
    _EXAMPLE = dict(R=0.1, l=0.3, e=0.02, m_1=0.5, m_2=1.2, m_3=2.0, k=2000.0, l_0=0.25,
                    x_S=0.45, y_S=0.2, b=40.0, F=-30.0, T=0.0, g=9.81)
    MODES = (+1, -1)

    def _margin_np(self, p, theta):
        # The slide y = e must come within l of the crank pin: l^2 >= (e - R sin th)^2.
        dy = p["e"] - p["R"] * np.sin(np.real(theta))
        return p["l"] ** 2 - dy**2

    def _assembles_mp(self, p, theta):
        return p["l"] ** 2 >= (p["e"] - p["R"] * mpmath.sin(theta)) ** 2

    def _points(self, xp, p, theta, mode):
        R, l, e = p["R"], p["l"], p["e"]
        A = (R * xp.cos(theta), R * xp.sin(theta))
        # Loop closure O -> A -> B = (x_B, e): R cos th + l cos phi = x_B (linear in x_B),
        # R sin th + l sin phi = e, solved by Newton for the rod angle phi from the rod
        # horizontal and pointing right (mode +1) or left (mode -1). The residual is
        # increasing in phi on [-pi/2, pi/2], concave on the half where its root lies to the
        # right of 0 and convex on the other, so from 0 Newton converges monotonically to the
        # root with cos(phi) >= 0; from pi, by symmetry, to the one with cos(phi) <= 0;
        # whenever |e - R sin th| <= l.
        phi0 = (0.0 if mode > 0 else xp.pi()) + 0.0 * theta
        phi = _newton(xp, lambda ph, i: (_at(A[1], i) + l * xp.sin(ph) - e, l * xp.cos(ph)),
                      phi0, scale=4.0)
        B = (A[0] + l * xp.cos(phi), e)
        # Verify the mode: the rod points right (mode +1) / left (mode -1) of the pin.
        side = mode * np.real(xp.cos(phi))
        if _wrong_side(xp, side):
            raise ModeError(f"slider_crank: Newton left assembly mode {mode}")
        return {"O": (xp.num(0), xp.num(0)), "A": A, "B": B,
                "crank_centre": _mid((0, 0), A), "rod_centre": _mid(A, B), "phi": phi}

    def _energy_terms(self, xp, p, theta, pts):
        g = p["g"]
        S = (p["x_S"], p["y_S"])
        spring_len = _dist(xp, pts["B"], S)
        return {
            "gravity": g * (p["m_1"] * pts["crank_centre"][1] + p["m_2"] * pts["rod_centre"][1]
                            + p["m_3"] * pts["B"][1]),
            "spring": p["k"] / 2 * (spring_len - p["l_0"]) ** 2,
            "force": -p["F"] * pts["B"][0],
            "torque": -p["T"] * theta,
        }


class FourBar(_Reference):
    """Four-bar linkage with a spring on the coupler-rocker joint (MECHANISMS.md).

    Ground pivots O2 = (0, 0), O4 = (d, 0); crank O2-A (a_2, theta, m_2), coupler A-B (a_3,
    m_3), rocker O4-B (a_4, m_4). Mode +1: B left of the directed line A -> O4, i.e.
    (O4 - A) x (B - A) >= 0; mode -1: right of it. Spring k, free length l_0, from S = (x_S,
    y_S) to B; torque T on the crank."""

    name = "four_bar"
    PARAMS = ("d", "a_2", "a_3", "a_4", "m_2", "m_3", "m_4", "k", "l_0", "x_S", "y_S", "b",
              "T", "g")
    _EXAMPLE = dict(d=0.4, a_2=0.12, a_3=0.35, a_4=0.3, m_2=0.4, m_3=1.0, m_4=0.8, k=1500.0,
                    l_0=0.2, x_S=0.1, y_S=0.45, b=30.0, T=0.0, g=9.81)
    MODES = (+1, -1)

    def _margin_np(self, p, theta):
        # The circles about A (radius a_3) and O4 (radius a_4) must meet:
        # |a_3 - a_4| <= |A - O4| <= a_3 + a_4 (and A != O4, else B's direction is free).
        th = np.real(theta)
        D2 = (p["a_2"] * np.cos(th) - p["d"]) ** 2 + (p["a_2"] * np.sin(th)) ** 2
        margin = np.minimum(D2 - (p["a_3"] - p["a_4"]) ** 2, (p["a_3"] + p["a_4"]) ** 2 - D2)
        return np.where(D2 > 0, margin, -1.0)

    def _assembles_mp(self, p, theta):
        D2 = (p["a_2"] * mpmath.cos(theta) - p["d"]) ** 2 + (p["a_2"] * mpmath.sin(theta)) ** 2
        return (p["a_3"] - p["a_4"]) ** 2 <= D2 <= (p["a_3"] + p["a_4"]) ** 2 and D2 > 0

    def _points(self, xp, p, theta, mode):
        d, a2, a3, a4 = p["d"], p["a_2"], p["a_3"], p["a_4"]
        O4 = (d, 0 * d)
        A = (a2 * xp.cos(theta), a2 * xp.sin(theta))
        # Loop closure O2 -> A -> B = O4 -> B: B = O4 + a_4 (cos phi4, sin phi4) with
        # |B - A|^2 = a_3^2, solved by Newton for the rocker angle phi4. Measured from the
        # direction u of A - O4 the residual is const - 2 a_4 |A - O4| cos(psi); started at
        # psi = -pi/2 (mode +1: B left of A -> O4) or +pi/2 (mode -1), the first step lands
        # on the root's side of the inflection and Newton then converges monotonically to
        # the root with psi in [-pi, 0] (mode +1) or [0, pi] (mode -1).
        base = xp.real_angle(A[0] - O4[0], A[1] - O4[1])
        psi0 = -mode * xp.pi() / 2
        phi0 = base + psi0

        def residual(ph, i):
            bx = O4[0] + a4 * xp.cos(ph) - _at(A[0], i)
            by = O4[1] + a4 * xp.sin(ph) - _at(A[1], i)
            return bx * bx + by * by - a3 * a3, 2 * a4 * (-bx * xp.sin(ph) + by * xp.cos(ph))

        phi4 = _newton(xp, residual, phi0 + 0 * theta, scale=8.0)
        B = (O4[0] + a4 * xp.cos(phi4), O4[1] + a4 * xp.sin(phi4))
        # Verify the mode from the cross product (O4 - A) x (B - A).
        cross = (O4[0] - A[0]) * (B[1] - A[1]) - (O4[1] - A[1]) * (B[0] - A[0])
        side = mode * np.real(cross) if xp.vector else mode * cross
        if _wrong_side(xp, side / (a3 * (a2 + d))):
            raise ModeError(f"four_bar: Newton left assembly mode {mode}")
        return {"O2": (xp.num(0), xp.num(0)), "O4": O4, "A": A, "B": B,
                "crank_centre": _mid((0, 0), A), "coupler_centre": _mid(A, B),
                "rocker_centre": _mid(O4, B), "phi4": phi4}

    def _energy_terms(self, xp, p, theta, pts):
        g = p["g"]
        S = (p["x_S"], p["y_S"])
        spring_len = _dist(xp, pts["B"], S)
        return {
            "gravity": g * (p["m_2"] * pts["crank_centre"][1]
                            + p["m_3"] * pts["coupler_centre"][1]
                            + p["m_4"] * pts["rocker_centre"][1]),
            "spring": p["k"] / 2 * (spring_len - p["l_0"]) ** 2,
            "torque": -p["T"] * theta,
        }


class TorsionPendulum(_Reference):
    """A uniform bar O-P (length l, mass m) pivoted at the origin at angle theta, a point
    mass m_t at its tip P, a torsion spring k_t with free angle theta_0 at the pivot and a
    horizontal force F_x at the tip. Range (theta_0 - pi, theta_0 + pi]: the spring winds,
    theta and theta + 2 pi are different states."""

    name = "torsion_pendulum"
    PARAMS = ("l", "m", "m_t", "k_t", "theta_0", "c", "F_x", "g")
    _EXAMPLE = dict(l=1.0, m=1.0, m_t=2.0, k_t=20.0, theta_0=1.5707963267948966, c=0.5,
                    F_x=0.0, g=9.81)
    periodic = False

    def theta_range(self, params=None):
        p = self._params(params)
        return (p["theta_0"] - math.pi, p["theta_0"] + math.pi)

    def _points(self, xp, p, theta, mode):
        l = p["l"]
        P = (l * xp.cos(theta), l * xp.sin(theta))
        return {"O": (xp.num(0), xp.num(0)), "P": P, "bar_centre": _mid((0, 0), P)}

    def _energy_terms(self, xp, p, theta, pts):
        return {
            "gravity": p["g"] * (p["m"] * pts["bar_centre"][1] + p["m_t"] * pts["P"][1]),
            "spring": p["k_t"] / 2 * (theta - p["theta_0"]) ** 2,
            "force": -p["F_x"] * pts["P"][0],
        }


class Doughty(_Reference):
    """Doughty's two-slider mechanism: slider 1 (m_A) at A = (p, 0) on X, slider 2 (m_B) at
    B = (0, q) on Y, a uniform bar (L, m_C) from A to B at angle theta (p = L cos theta,
    q = L sin theta). Spring k (free length l_ND) with damper b from O' = (H, 0) to the point
    P of the bar at distance a from B. Force F on slider 2 along +Y. The spring length is a
    length (positive root); there is no assembly mode. G jumps where r = 0."""

    name = "doughty"
    PARAMS = ("H", "L", "a", "m_A", "m_B", "m_C", "k", "b", "l_ND", "F", "g")
    _EXAMPLE = dict(H=0.18, L=0.9, a=0.135, m_A=0.194, m_B=0.143, m_C=9.124, k=3500.0,
                    b=875.0, l_ND=0.15, F=110.0, g=9.81)

    def _points(self, xp, p, theta, mode):
        L, a, H = p["L"], p["a"], p["H"]
        A = (L * xp.cos(theta), 0 * L)
        B = (0 * L, L * xp.sin(theta))
        # P: at distance a from B along the bar towards A.
        P = (B[0] + a * (A[0] - B[0]) / L, B[1] + a * (A[1] - B[1]) / L)
        return {"A": A, "B": B, "C": _mid(A, B), "P": P, "O'": (H, 0 * H)}

    def _energy_terms(self, xp, p, theta, pts):
        r = _dist(xp, pts["P"], pts["O'"])
        return {
            "gravity": p["g"] * (p["m_A"] * pts["A"][1] + p["m_B"] * pts["B"][1]
                                 + p["m_C"] * pts["C"][1]),
            "spring": p["k"] / 2 * (r - p["l_ND"]) ** 2,
            "force": -p["F"] * pts["B"][1],
        }

    def spring_length(self, params, theta):
        """r = |P - O'| (mpf), the positive root."""
        pts = self.positions(params, theta)
        with mpmath.workdps(max(_mp.dps, WORK_DPS)):
            return _dist(_MP, pts["P"], pts["O'"])


REFERENCES = {
    ref.name: ref for ref in (SliderCrank(), FourBar(), TorsionPendulum(), Doughty())
}
