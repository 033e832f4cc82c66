"""An independent numerical reference for the statics and reduced coefficients of any
``Mechanism``: G = dV/dtheta, K = dG/dtheta, M (generalised mass), B (damping) and the
equilibria, from the model's own data only.

Nothing is shared with the derivation (no closed-form elimination, no import from
``codegen.compiler.derivation`` or ``codegen.compiler.emission``). The model's expressions are
only evaluated:

* positions: the constraints are solved *numerically* for the dependent coordinates, by
  Newton's method from many fixed pseudo-random starts (vectorised in double), keeping a
  solution in the declared assembly mode (every ``assembly_modes`` expression positive, every
  polar length positive), then polished by Newton in mpmath at high precision;
* V = sum m g y_centre + sum k/2 (length - l_0)^2 - sum F . point - sum T angle, each length
  evaluated as the model writes it;
* G, K: central first and second differences of V along the solved path, at WORK_DPS digits
  with a tiny step (about REPORT_DPS correct digits);
* M = sum m |dc/dtheta|^2 + I (dangle/dtheta)^2 and B = sum c (dl/dtheta)^2, with the same
  central differences of the centres, angles and damper lengths;
* equilibria: a dense scan of G (double) over the coordinate's range (range_centre - pi,
  range_centre + pi], with extra samples clustering towards each limit position, every sign
  change between two assembled samples refined by brentq on the high-precision G, and kept
  only if G is small there (not a pole or a jump).

Limitations: a double root (no sign change) or two roots closer than the scan's step are not
found; angles where Newton finds no solution from any start are taken as unassembled; where
the modes do not pin a single solution, the one with the largest smallest mode is taken.
Dependent angles are reported in (-pi, pi], so a potential that depends on their 2 pi
representative (a torsion spring on a dependent angle) is outside its scope.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp
from scipy.optimize import brentq

#: Digits the reference values are good to, and the working precision that delivers them:
#: a central difference with step 10^-STEP_DIGITS loses STEP_DIGITS (first) or twice that
#: (second difference) of WORK_DPS, and is off by ~10^(-2 STEP_DIGITS) by truncation.
REPORT_DPS = 30
WORK_DPS = 75
STEP_DIGITS = 20

_STARTS = 16          # Newton starts per angle in double
#: where none of them reaches the declared mode, this many per dependent coordinate's
#: doubling, up to 1024 (a chain of three dyads has 8 solutions, some reached by few starts)
_RETRY_STARTS = 16
#: (asked for a few angles at a time; a scan follows its solutions from neighbour to neighbour)
_RETRY_ANGLES = 4
_NEWTON_STEPS = 40


@dataclass(frozen=True)
class Values:
    """The reference at one angle (mpf, about REPORT_DPS digits)."""

    theta: float
    q: tuple            # the dependent coordinates, in the model's order
    V: mpmath.mpf
    G: mpmath.mpf
    K: mpmath.mpf
    M: mpmath.mpf
    B: mpmath.mpf


class Reference:
    """One mechanism with one parameter set (parameter name -> float)."""

    def __init__(self, mechanism, params: Mapping[str, float], seed: int = 0):
        self.mechanism = mechanism
        names = {p.symbol.name for p in mechanism.parameters}
        if set(params) != names:
            raise ValueError(f"parameters differ from the model's: {set(params) ^ names}")
        self.params = tuple(float(params[p.symbol.name]) for p in mechanism.parameters)
        frozen = mechanism.freezer()
        coords = [frozen[c.function] for c in mechanism.coordinates]
        self.theta = frozen[mechanism.coordinate(mechanism.independent)]
        self.dependent = [s for s in coords if s != self.theta]
        self.angle_like = np.array([c.unit == "rad" for c in mechanism.coordinates
                                    if frozen[c.function] != self.theta], dtype=bool)
        # Newton's tolerances and the spread of its starts: the model's largest length.
        self.length_scale = max([abs(v) for v in self.params_by_unit("m")] + [1e-3])
        self._compile(frozen)
        self._mp_params = [mpmath.mpf(v) for v in self.params]   # exact at any precision
        values = dict(zip(mechanism.symbols, self.params))
        #: The range's centre (an expression of the parameters) and the range (centre -+ pi).
        self.centre = float(sp.sympify(mechanism.range_centre).xreplace(values))
        self.range = (self.centre - math.pi, self.centre + math.pi)
        rng = np.random.default_rng(seed)
        self._starts = self._random_starts(rng, _STARTS)
        self._retry_starts = self._random_starts(
            rng, min(1024, _RETRY_STARTS * 2 ** len(self.dependent)))

    def params_by_unit(self, unit: str) -> list[float]:
        return [v for p, v in zip(self.mechanism.parameters, self.params) if p.unit == unit]

    # ------------------------------------------------------------------ compilation

    def _compile(self, frozen) -> None:
        m = self.mechanism
        freeze = lambda e: sp.sympify(e).xreplace(frozen)  # noqa: E731
        args = [self.theta, *self.dependent, *m.symbols]
        constraints = [freeze(c) for c in m.constraints]
        jacobian = sp.Matrix(constraints).jacobian(self.dependent) if constraints else None
        # What must be positive in the declared mode: the modes and every polar length.
        polar = [frozen[m.coordinate(length)] for length, _ in m.polar_pairs]
        positive = [freeze(e) for e in m.assembly_modes] + polar
        track = self._tracked(freeze)
        coefficients = ([b.mass for b in m.bodies] + [b.inertia for b in m.bodies]
                        + [d.coefficient for d in m.dampers])
        self.n_bodies, self.n_dampers = len(m.bodies), len(m.dampers)
        self._np = {name: sp.lambdify(args, exprs, modules="numpy") for name, exprs in (
            ("C", constraints), ("J", jacobian.tolist() if jacobian is not None else []),
            ("positive", positive), ("track", track))}
        self._mp = {name: sp.lambdify(args, exprs, modules="mpmath") for name, exprs in (
            ("C", constraints), ("J", jacobian.tolist() if jacobian is not None else []),
            ("positive", positive), ("track", track),
            ("coefficients", [sp.sympify(c) for c in coefficients]))}

    def _tracked(self, freeze) -> list:
        """[V, then x, y, angle of each body's centre, then each damper's length]: what is
        differentiated along the path."""
        m = self.mechanism
        V = sum((b.mass * m.gravity * b.centre[1] for b in m.bodies), sp.S.Zero)
        V += sum((s.stiffness / 2 * (s.length - s.free_length) ** 2 for s in m.springs), sp.S.Zero)
        V -= sum((f.force[0] * f.point[0] + f.force[1] * f.point[1] for f in m.forces), sp.S.Zero)
        V -= sum((t.torque * t.angle for t in m.torques), sp.S.Zero)
        out = [V]
        for b in m.bodies:
            out += [b.centre[0], b.centre[1], b.angle]
        out += [d.length for d in m.dampers]
        return [freeze(e) for e in out]

    def _random_starts(self, rng, count: int) -> np.ndarray:
        """(count, D): angles anywhere on the circle, other coordinates within a few
        lengths of the origin."""
        D = len(self.dependent)
        spread = np.where(self.angle_like, math.pi, 3.0 * self.length_scale)
        return rng.uniform(-1.0, 1.0, (count, D)) * spread

    # ------------------------------------------------------------------ positions in double

    def _call_np(self, name, theta, q) -> np.ndarray:
        """A compiled list of expressions on arrays: shape (len, *theta.shape)."""
        out = _flat(self._np[name](theta, *np.moveaxis(q, -1, 0), *self.params))
        if not out:
            return np.zeros((0, *np.shape(theta)))
        return np.array(np.broadcast_arrays(*out, theta)[:-1])   # constants to full arrays

    def _newton_np(self, theta, q, steps=_NEWTON_STEPS, wrap=True) -> np.ndarray:
        """Newton on the constraints for arrays theta (...), q (..., D); NaN where it fails.
        wrap: dependent angles into (-pi, pi] (off when following a path, so that a
        potential holding an angle, -T psi, stays continuous)."""
        D = q.shape[-1]
        with np.errstate(all="ignore"):
            for _ in range(steps):
                C = np.moveaxis(self._call_np("C", theta, q), 0, -1)
                J = np.moveaxis(self._call_np("J", theta, q), 0, -1).reshape(*q.shape, D)
                det = np.linalg.det(J)
                bad = ~np.isfinite(det) | (np.abs(det) < 1e-300) | ~np.all(np.isfinite(C), -1)
                J[bad] = np.eye(D)
                step = np.linalg.solve(J, C[..., None])[..., 0]
                step[bad] = np.nan
                q = q - step
            C = np.moveaxis(self._call_np("C", theta, q), 0, -1)
            ok = np.all(np.abs(C) <= 1e-9 * self.length_scale, axis=-1)
        q = np.where(ok[..., None], q, np.nan)
        if wrap:
            q[..., self.angle_like] = _wrap(q[..., self.angle_like])
        return q

    def _declared(self, theta, q) -> tuple[np.ndarray, np.ndarray]:
        """For each candidate, the smallest of the expressions positive in the declared mode
        (+inf if there are none) and whether it is a solution in that mode."""
        pos = self._call_np("positive", theta, q)
        least = np.min(pos, axis=0) if len(pos) else np.full(np.shape(theta), np.inf)
        least = np.where(np.all(np.isfinite(q), -1), least, -np.inf)
        return least, least > 0

    def assemble(self, thetas) -> np.ndarray:
        """Dependent coordinates (n, D) in the declared mode at each angle (double; a row of
        NaN where the mechanism cannot be assembled in that mode)."""
        thetas = np.atleast_1d(np.asarray(thetas, dtype=float))
        if not self.dependent:
            return np.zeros((len(thetas), 0))
        chosen = self._assemble_from(thetas, self._starts)
        if len(thetas) > 1:
            self._continue(thetas, chosen)
        missing = ~np.all(np.isfinite(chosen), axis=1)
        if missing.any() and len(thetas) <= _RETRY_ANGLES:
            chosen[missing] = self._assemble_from(thetas[missing], self._retry_starts)
        return chosen

    def _continue(self, thetas, chosen) -> None:
        """Where no start reached the declared mode at an angle, Newton from its neighbours'
        solutions (in the order given: a scan's), until that finds no more."""
        for _ in range(len(thetas)):
            missing = ~np.all(np.isfinite(chosen), axis=1)
            found = False
            for shift in (1, -1):
                neighbour = np.roll(chosen, shift, axis=0)
                index = np.nonzero(missing & np.all(np.isfinite(neighbour), axis=1))[0]
                index = index[(index - shift >= 0) & (index - shift < len(thetas))]
                if len(index) == 0:
                    continue
                q = self._assemble_from(thetas[index], neighbour[index][:, None, :])
                ok = np.all(np.isfinite(q), axis=1)
                chosen[index[ok]] = q[ok]
                missing[index[ok]] = False
                found = found or bool(ok.any())
            if not found:
                return

    def _assemble_from(self, thetas, starts) -> np.ndarray:
        """assemble, by Newton from each of starts at each angle: (k, D) for every angle, or
        (n, k, D), each angle its own."""
        k = starts.shape[-2]
        t = np.repeat(thetas[:, None], k, axis=1)
        q = self._newton_np(t, np.broadcast_to(starts, (*t.shape, len(self.dependent))).copy())
        least, ok = self._declared(t, q)
        best = np.argmax(np.where(ok, least, -np.inf), axis=1)
        chosen = q[np.arange(len(thetas)), best]
        chosen[~ok[np.arange(len(thetas)), best]] = np.nan
        return chosen

    def assembles(self, theta: float) -> bool:
        return bool(np.all(np.isfinite(self.assemble([theta])[0])))

    # ------------------------------------------------------------------ high precision

    def _solve_mp(self, theta, q0):
        """Newton in mpmath at the working precision from q0 (close to the solution)."""
        q = [mpmath.mpf(float(v)) for v in q0]
        if not q:
            return q
        tol = mpmath.mpf(10) ** (-WORK_DPS + 8) * self.length_scale
        for _ in range(60):
            C = mpmath.matrix(_flat(self._mp["C"](theta, *q, *self._mp_params)))
            J = mpmath.matrix(self._mp["J"](theta, *q, *self._mp_params))
            step = mpmath.lu_solve(J, C)
            q = [a - b for a, b in zip(q, step)]
            if mpmath.norm(step, mpmath.inf) <= tol:
                return q
        raise RuntimeError(f"Newton did not converge at theta = {float(theta)!r}")

    def values(self, theta: float, q0=None) -> Values | None:
        """G, K, M, B at theta (None where the mechanism cannot be assembled). q0: a
        solution near theta in the declared mode (found afresh when omitted)."""
        if q0 is None:
            q0 = self.assemble([theta])[0]
        if not np.all(np.isfinite(q0)):
            return None
        with mpmath.workdps(WORK_DPS):
            t0, h = mpmath.mpf(theta), mpmath.mpf(10) ** -STEP_DIGITS
            q = self._solve_mp(t0, q0)
            least = min(_flat(self._mp["positive"](t0, *q, *self._mp_params)), default=1)
            if least <= 0:
                raise RuntimeError(f"left the declared mode at theta = {theta!r}")
            rows = [_flat(self._mp["track"](t, *self._solve_mp(t, q), *self._mp_params))
                    for t in (t0 - h, t0, t0 + h)]
            lo, mid, hi = rows
            d = [(b - a) / (2 * h) for a, b in zip(lo, hi)]
            coef = _flat(self._mp["coefficients"](t0, *q, *self._mp_params))
            n, nd = self.n_bodies, self.n_dampers
            mass, inertia, damping = coef[:n], coef[n:2 * n], coef[2 * n:]
            M = sum((mass[i] * (d[1 + 3 * i] ** 2 + d[2 + 3 * i] ** 2)
                     + inertia[i] * d[3 + 3 * i] ** 2 for i in range(n)), mpmath.mpf(0))
            B = sum((damping[j] * d[1 + 3 * n + j] ** 2 for j in range(nd)), mpmath.mpf(0))
            K = (hi[0] - 2 * mid[0] + lo[0]) / h**2
            return Values(theta, tuple(q), +mid[0], +d[0], +K, +M, +B)

    # ------------------------------------------------------------------ equilibria

    def scan(self, samples: int = 2001):
        """(thetas, q, G) on a uniform grid over the closed range, with extra samples
        clustering towards each limit of the assembled region (G blows up there, so a zero
        may lie between the grid's last assembled sample and the limit); G in double
        (central difference, step 1e-6), NaN where the mechanism cannot be assembled."""
        thetas = np.linspace(*self.range, samples)
        q = self.assemble(thetas)
        extra = self._towards_limits(thetas, np.all(np.isfinite(q), axis=1))
        if extra:
            thetas = np.unique(np.concatenate([thetas, extra]))
            q = self.assemble(thetas)
        h = 1e-6
        V = [self._call_np("track", thetas + s, self._newton_np(thetas + s, q.copy(), 8, wrap=False)
                           if self.dependent else q)[0] for s in (-h, h)]
        return thetas, q, (V[1] - V[0]) / (2 * h)

    def _towards_limits(self, thetas, ok) -> list[float]:
        """Samples at 2^-k of the way from each limit (found by bisection) back to the last
        assembled grid point, k = 1..20."""
        extra = []
        for i in np.nonzero(ok[:-1] != ok[1:])[0]:
            good, bad = (thetas[i], thetas[i + 1]) if ok[i] else (thetas[i + 1], thetas[i])
            last = good
            for _ in range(60):
                mid = 0.5 * (good + bad)
                if mid in (good, bad):
                    break
                good, bad = (mid, bad) if self.assembles(mid) else (good, mid)
            extra += [good - (good - last) * 2.0**-k for k in range(1, 21)]
        return extra

    def equilibria(self, samples: int = 2001) -> list[float]:
        """Every zero of G in the range found by the scan, refined to ~1e-15 rad, sorted."""
        thetas, q, G = self.scan(samples)
        finite = np.isfinite(G)
        scale = float(np.median(np.abs(G[finite]))) if finite.any() else 1.0
        roots = []
        for i in range(len(thetas) - 1):
            if not (finite[i] and finite[i + 1]) or np.sign(G[i]) == np.sign(G[i + 1]) != 0:
                continue
            if G[i + 1] == 0:
                continue   # counted with the next interval, whose left end it is
            root = self._refine(thetas[i], thetas[i + 1], q[i], scale)
            if root is not None:
                roots.append(root)
        lo, hi = self.range
        return sorted(r for r in roots if lo < r <= hi)

    def _refine(self, a: float, b: float, q0, scale: float) -> float | None:
        """The zero of G in [a, b] (G changes sign there), or None where the sign change is
        a pole or a jump of G (G is not small at the limit brentq converges to)."""
        def G(t):
            return float(self.values(t, q0).G)
        try:
            root = brentq(G, a, b, xtol=1e-15, rtol=1e-15)
            return root if abs(G(root)) <= 1e-6 * scale else None
        except RuntimeError:   # Newton fails at the limit: the mechanism breaks there
            return None
        except ValueError:     # no sign change at high precision: a pole sampled in double
            return None


def _flat(out) -> list:
    """A lambdified result as a flat list (a matrix-shaped list of lists too)."""
    if isinstance(out, (list, tuple)):
        return [x for o in out for x in (_flat(o) if isinstance(o, (list, tuple)) else [o])]
    return [out]


def _wrap(angle):
    """Angles into (-pi, pi]."""
    return np.pi - np.mod(np.pi - angle, 2 * np.pi)


def angle_gap(a: float, b: float) -> float:
    """|a - b| modulo a full turn."""
    return abs(math.remainder(a - b, 2 * math.pi))
