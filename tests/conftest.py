"""Shared fixtures for the test suite: the derivation and its emission plan, reproducible
random parameters and states, and high-precision reference evaluation.

Everything random here comes from ``numpy.random.default_rng`` with a fixed seed, so a run
is reproducible; hypothesis-driven tests draw integer seeds and call ``random_params``
themselves.

Helpers are handed to tests as session-scoped fixtures (``random_params``, ``mp_eval``, ...)
rather than imported from this file, so the suite works whatever the import mode.

Nothing compiled is loaded at import: the doughty library (``api``) loads on first use, so
that tests/runtime_c, which compiles the C runtime on its own and loads no mechanism's
library, runs in a clone where nothing is generated or built.
"""
from __future__ import annotations

import functools
import math
import os
import shutil
import subprocess
import zlib
from dataclasses import dataclass
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import settings

from codegen import resources


class _Doughty:
    """The doughty Library (codegen.api.load), loaded when first used."""

    def __getattr__(self, name):
        from codegen.api import load

        return getattr(load("doughty"), name)


api = _Doughty()


# Property tests are deterministic by default, so CI judges the same examples every run;
# HYPOTHESIS_PROFILE=explore searches fresh random examples (and remembers failures).
settings.register_profile("deterministic", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "deterministic"))

SEED = 20_240_611
#: Unit roundoff of IEEE double precision.
UNIT_ROUNDOFF = 2.0**-53
#: AddressSanitizer + UBSan, aborting on the first report (runtime/cflags.txt's sets).
SANITIZE = tuple(resources.cflags("base", "sanitize"))


# --------------------------------------------------------------------------- derivation


@functools.lru_cache(maxsize=None)
def _derivation():
    from codegen.compiler.derivation import derive
    from codegen.compiler.model import doughty

    # derive() caches per Mechanism *object* (identity hash), so build the model once.
    return derive(doughty.build())


@functools.lru_cache(maxsize=None)
def _plan():
    from codegen.compiler.emission.plan import build_plan

    return build_plan(_derivation())


def pytest_generate_tests(metafunc):
    """``plan_function_name``: every C function of the emission plan, by name."""
    if "plan_function_name" in metafunc.fixturenames:
        metafunc.parametrize("plan_function_name", [f.name for f in _plan().functions])


# --------------------------------------------------------------------------- tools


def _in_ci() -> bool:
    """CI is set (to anything but an explicit no: '', 0, false, no)."""
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def missing_tools_message(missing: list[str], packages: dict[str, str] | None = None) -> str:
    """What is missing and how to install it; a tool's Debian package is its own name unless
    ``packages`` maps it to others."""
    install = " ".join(dict.fromkeys((packages or {}).get(tool, tool) for tool in missing))
    return (f"{', '.join(missing)} {'is' if len(missing) == 1 else 'are'} not installed: "
            f"install with `apt-get install {install}` (Debian/Ubuntu; .ci/run does "
            f"this in CI)")


def _need_tools(*tools: str, packages: dict[str, str] | None = None) -> None:
    missing = [tool for tool in tools if shutil.which(tool) is None]
    if not missing:
        return
    message = missing_tools_message(missing, packages)
    if _in_ci():
        pytest.fail(f"{message} [CI is set, so this fails instead of skipping]", pytrace=False)
    pytest.skip(message)


@pytest.fixture(scope="session")
def need_tools():
    """need_tools(*tools, packages=None): skip the test (locally) or fail it (CI set, as .ci/run
    does, since it installs them) unless every tool is on PATH, naming the install command."""
    return _need_tools


@pytest.fixture(scope="session")
def derivation():
    return _derivation()


@pytest.fixture(scope="session")
def plan():
    return _plan()


@pytest.fixture(scope="session")
def param_symbols():
    """Parameter name -> the sympy Symbol the derivation uses for it."""
    return {n: sp.Symbol(n, real=True) for n in api.PARAMETER_NAMES}


@pytest.fixture
def rng(request):
    """A generator seeded from SEED and the test's name: reproducible, order-independent."""
    return np.random.default_rng([SEED, zlib.crc32(request.node.nodeid.encode())])


# --------------------------------------------------------------------------- parameters


def _log_uniform(rng, low, high):
    return float(math.exp(rng.uniform(math.log(low), math.log(high))))


def near_table2(rng) -> api.Params:
    """Table 2 with every parameter scaled by a factor around 1 (sd ~10 %)."""
    table2 = api.example_params()
    base = {n: getattr(table2, n) for n in api.PARAMETER_NAMES}
    values = {n: v * math.exp(rng.normal(0.0, 0.1)) for n, v in base.items()}
    values["a"] = min(values["a"], values["L"])
    return api.Params(**values)


def far_from_table2(rng) -> api.Params:
    """Anywhere in the physically meaningful box, including exact edge values."""
    L = _log_uniform(rng, 0.05, 5.0)
    v = {
        "L": L,
        "a": float(rng.uniform(0.0, L)),
        "H": float(rng.uniform(-2.0, 2.0)),
        "m_A": _log_uniform(rng, 0.01, 50.0),
        "m_B": _log_uniform(rng, 0.01, 50.0),
        "m_C": _log_uniform(rng, 0.01, 50.0),
        "k": _log_uniform(rng, 1e-2, 1e5),
        "b": _log_uniform(rng, 1e-2, 1e4),
        "l_ND": float(rng.uniform(0.0, 2.0)),
        "F": float(rng.uniform(-500.0, 500.0)),
        "g": float(rng.uniform(0.0, 20.0)),
    }
    # Exact edge values of the admissible ranges, each now and then.
    edges = {"a": (0.0, L), "H": (0.0,), "k": (0.0,), "b": (0.0,), "l_ND": (0.0,),
             "F": (0.0,), "g": (0.0,)}
    for name, choices in edges.items():
        if rng.random() < 0.06:
            v[name] = float(choices[rng.integers(len(choices))])
    if v["a"] == 0.0 and v["H"] == 0.0:
        v["H"] = 0.5  # spring anchored at B's track and O' at the origin: r = L|sin| only
    return api.Params(**v)


def _random_params(rng, count: int, near_fraction: float = 0.5) -> list:
    """``count`` parameter sets: a fraction near Table 2, the rest anywhere in the box."""
    return [near_table2(rng) if rng.random() < near_fraction else far_from_table2(rng)
            for _ in range(count)]


@pytest.fixture(scope="session")
def random_params():
    return _random_params


def params_from_seed(seed: int, near_fraction: float = 0.5) -> api.Params:
    return _random_params(np.random.default_rng([SEED, seed]), 1, near_fraction)[0]


@pytest.fixture(scope="session")
def params_for_seed():
    """seed -> one parameter set (for hypothesis, which draws the seed)."""
    return params_from_seed


# --------------------------------------------------------------------------- states


@dataclass
class States:
    """Batches of states: theta, theta_d (count,), coords, rates, accels (count, 5),
    multipliers (count, 4)."""

    theta: np.ndarray
    theta_d: np.ndarray
    coords: np.ndarray
    rates: np.ndarray
    accels: np.ndarray
    multipliers: np.ndarray


def random_angles(rng, count: int, wide_fraction: float = 0.1) -> np.ndarray:
    """Mostly in [-pi, pi]; some far outside, to exercise the periodic functions."""
    theta = rng.uniform(-math.pi, math.pi, count)
    wide = rng.random(count) < wide_fraction
    theta[wide] = rng.uniform(-60.0, 60.0, wide.sum())
    return theta


def _random_states(rng, params_table: np.ndarray, consistent: bool = True) -> States:
    """One state per row of ``params_table`` (a ``api.params_array``).

    consistent=True: coordinates and rates on the mechanism (from the compiled
    ``dependent_state``); False: every coordinate, rate and acceleration drawn independently.
    Accelerations and multipliers are always arbitrary.
    """
    n = len(params_table)
    theta = random_angles(rng, n)
    theta_d = rng.normal(0.0, 5.0, n) * np.exp(rng.uniform(-3, 1, n))
    if consistent:
        coords, rates = api.dependent_state(params_table, theta, theta_d)
    else:
        L = params_table["L"]
        coords = np.column_stack([
            rng.uniform(-2, 2, n) * L, rng.uniform(-2, 2, n) * L,
            rng.uniform(0.01, 2.0, n) * L, theta, random_angles(rng, n)])
        rates = rng.normal(0.0, 5.0, (n, 5))
    accels = rng.normal(0.0, 50.0, (n, 5))
    multipliers = rng.normal(0.0, 1e3, (n, 4))
    return States(theta, theta_d, np.asarray(coords), np.asarray(rates), accels, multipliers)


@pytest.fixture(scope="session")
def random_states():
    return _random_states


# --------------------------------------------------------------------------- high precision


def mp_lambdify(symbols, exprs, dps: int = 40):
    """Compile ``exprs`` (one expression or a sequence) once for mpmath.

    The returned function takes one float (or mpf) per symbol; floats are converted
    exactly (mpmath.mpf of a double is exact), evaluation runs at ``dps`` digits, and the
    result is an mpf or a list of mpf. Rational constants are printed as mpf quotients and
    evaluated inside the working precision, so nothing is rounded to double on the way.
    """
    single = isinstance(exprs, sp.Basic)
    exprs = [exprs] if single else list(exprs)
    func = sp.lambdify(list(symbols), exprs, modules="mpmath")

    def call(*values):
        with mpmath.workdps(dps):
            out = func(*(mpmath.mpf(v) for v in values))
            out = [mpmath.mpf(o) if not isinstance(o, mpmath.mpf) else +o for o in out]
        return out[0] if single else out

    return call


@functools.lru_cache(maxsize=256)
def _cached_mp_lambdify(symbols, expr, dps):
    return mp_lambdify(symbols, expr, dps)


def _mp_eval(expr, values: dict, dps: int = 40):
    """expr evaluated at ``values`` (Symbol -> float, converted exactly) with ``dps`` digits."""
    symbols = tuple(sorted(values, key=sp.default_sort_key))
    func = _cached_mp_lambdify(symbols, sp.sympify(expr), dps)
    return func(*(values[s] for s in symbols))


@pytest.fixture(scope="session")
def mp_eval():
    return _mp_eval


@pytest.fixture(scope="session")
def mp_compile():
    return mp_lambdify


# --------------------------------------------------------------------------- error bounds


class RoundingBound:
    """First-order bound on the rounding error of evaluating expressions in double.

    The expression tree is walked node by node (shared subtrees once), vectorised over
    points with numpy. Every node carries its double value v and a bound e on the absolute
    error accumulated below it, propagated by the usual first-order rules (u = 2^-53):

        inputs (exact doubles) and integers   e = 0;  other constants  e = u |v|
        sum of n terms          e = sum e_i + (n - 1) u sum |v_i|
        product of n factors    e = sum_i e_i prod_{j != i} |v_j| + (n - 1) u |v|
        b**n                    e = |n| |v / b| e_b + (|n| + 1) u |v|
        sin, cos (libm, < 1 ulp) e = |derivative| e_x + 2 u |v|
        atan2(y, x)             e = (|x| e_y + |y| e_x) / (x^2 + y^2) + 2 u |v|
        |x|                     e = e_x (exact)

    This is the condition number of the expression *as written*, times u: the accuracy
    any straightforward double evaluation of it (in any association order, with common
    subexpressions shared) can promise. Where an expression cancels (an exact value near
    zero next to large terms), the bound is large compared with |value| and a comparison
    must allow for it; elsewhere it is a few hundred u |v| at most.
    """

    def __init__(self, symbols, exprs):
        self.symbols = tuple(symbols)
        self.nodes: list[tuple] = []
        self.index: dict = {}
        self.roots = [self._visit(sp.sympify(e)) for e in exprs]

    def _visit(self, e):
        if e in self.index:
            return self.index[e]
        if e.is_Symbol:
            if e not in self.symbols:
                raise ValueError(f"free symbol {e} is not an input")
            node = ("sym", self.symbols.index(e))
        elif e.is_Number or e.is_NumberSymbol:
            exact = e.is_Integer and abs(int(e)) < 2**53
            node = ("const", float(e), 0.0 if exact else UNIT_ROUNDOFF * abs(float(e)))
        else:
            kids = tuple(self._visit(a) for a in e.args)
            if e.is_Add:
                node = ("add", kids)
            elif e.is_Mul:
                node = ("mul", kids)
            elif e.is_Pow:
                if not e.exp.is_Number:
                    raise NotImplementedError(f"symbolic exponent in {e}")
                node = ("pow", kids[0], float(e.exp), sp.Rational(e.exp).q)
            elif isinstance(e, (sp.sin, sp.cos)):
                node = (type(e).__name__, kids[0])
            elif isinstance(e, sp.atan2):
                node = ("atan2", kids[0], kids[1])
            elif isinstance(e, sp.Abs):
                node = ("abs", kids[0])
            else:
                raise NotImplementedError(f"no rounding rule for {type(e).__name__}")
        self.nodes.append(node)
        self.index[e] = len(self.nodes) - 1
        return self.index[e]

    def __call__(self, *columns, input_rel: float = 0.0):
        """columns: one array per symbol. Returns (values, bounds), each (n_exprs, n).

        input_rel: a relative error already present in every input (0: exact doubles).
        """
        u = UNIT_ROUNDOFF
        cols = [np.asarray(c, dtype=np.float64) for c in columns]
        n = max((c.size for c in cols), default=1)
        val, err = [], []
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            for node in self.nodes:
                kind = node[0]
                if kind == "sym":
                    v = np.broadcast_to(cols[node[1]], (n,)).astype(np.float64)
                    e = input_rel * np.abs(v)
                elif kind == "const":
                    v, e = np.full(n, node[1]), np.full(n, node[2])
                elif kind == "add":
                    vs = [val[k] for k in node[1]]
                    v = np.sum(vs, axis=0)
                    e = (np.sum([err[k] for k in node[1]], axis=0)
                         + (len(vs) - 1) * u * np.sum(np.abs(vs), axis=0))
                elif kind == "mul":
                    vs = [val[k] for k in node[1]]
                    v = np.prod(vs, axis=0)
                    e = (len(vs) - 1) * u * np.abs(v)
                    for i, k in enumerate(node[1]):
                        others = [np.abs(vs[j]) for j in range(len(vs)) if j != i]
                        e = e + err[k] * (np.prod(others, axis=0) if others else 1.0)
                elif kind == "pow":
                    b, be = val[node[1]], err[node[1]]
                    expo, q = node[2], node[3]
                    v = np.power(b, expo) if q == 1 else np.power(np.abs(b), expo)
                    roundings = abs(expo) + (1 if q != 1 else 0) + 1
                    # |d(b**n)/db| = |n| |b|**(n-1); no division, so b = 0 stays finite
                    inherited = np.where(be == 0, 0.0,
                                         abs(expo) * np.power(np.abs(b), expo - 1) * be)
                    e = inherited + roundings * u * np.abs(v)
                elif kind == "sin":
                    x = val[node[1]]
                    v = np.sin(x)
                    e = np.abs(np.cos(x)) * err[node[1]] + 2 * u * np.abs(v)
                elif kind == "cos":
                    x = val[node[1]]
                    v = np.cos(x)
                    e = np.abs(np.sin(x)) * err[node[1]] + 2 * u * np.abs(v)
                elif kind == "atan2":
                    y, x = val[node[1]], val[node[2]]
                    v = np.arctan2(y, x)
                    e = ((np.abs(x) * err[node[1]] + np.abs(y) * err[node[2]]) / (x * x + y * y)
                         + 2 * u * np.abs(v))
                elif kind == "abs":
                    v, e = np.abs(val[node[1]]), err[node[1]]
                else:  # pragma: no cover
                    raise AssertionError(kind)
                val.append(v)
                err.append(e)
        return (np.array([val[r] for r in self.roots]), np.array([err[r] for r in self.roots]))


@pytest.fixture(scope="session")
def rounding_bound():
    return RoundingBound


@dataclass(frozen=True)
class Sanitizer:
    cc: str
    flags: tuple[str, ...] = SANITIZE


@pytest.fixture
def sanitizer(tmp_path) -> Sanitizer:
    """A C compiler that links SANITIZE programs (a probe is built), with those flags; skips
    where none does."""
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler")
    probe = tmp_path / "probe.c"
    probe.write_text("int main(void) { return 0; }\n")
    r = subprocess.run([cc, *SANITIZE, str(probe), "-o", str(tmp_path / "probe")],
                       capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"{cc} cannot link AddressSanitizer/UBSan: {r.stderr.strip()[:200]}")
    return Sanitizer(cc)


# --------------------------------------------------------------------------- paths

#: The checkout (tests/runtime_c/conftest.py holds the C runtime's drivers).
ROOT = Path(__file__).resolve().parents[1]
