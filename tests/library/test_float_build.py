"""The float build (-DCODEGEN_FLOAT): strict C99 with -Wdouble-promotion, guarded against the
flags that break it, and never silently wrong against the double build.

A driver written from each library's API spec reads parameter sets (exact in float) and prints every root of
the analysis with its certified interval, and every uncertain interval. It is compiled twice
from the same sources, in double and in float. On thousands of sets around the example, every
certified equilibrium of the double build (its isolation route, complete by construction) must lie in a certified float interval of the same
kind, or in an interval the float build reports as uncertain; every certified float
equilibrium must hold a double one (none invented); and where both are sure of K's sign,
the stability agrees.
"""
from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from libraries import generated_libraries

from codegen.resources import cflags

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated"
STRICT = cflags("base", "strict", "promotion", "optimize")
MECHANISMS = generated_libraries(GENERATED, several=False)  # theirs: tests/runtime/test_multibody.py
#: Sets compared per mechanism (the isolation that the float build runs is the slow part).
SETS = {"default": 300}
EQUILIBRIUM, OTHER_ASSEMBLY, EXTRANEOUS, MODE_UNDECIDED = 0, 1, 2, 3


def _same_kind(double_kind: int, float_kind: int) -> bool:
    """A proven zero whose mode float cannot tell (its conditions within rounding) is a
    weaker claim than double's, not another one."""
    return float_kind == double_kind or (float_kind == MODE_UNDECIDED
                                         and double_kind in (EQUILIBRIUM, OTHER_ASSEMBLY))

DRIVER = r"""
#include <stdio.h>
#include <stdlib.h>
#include "%(prefix)s.h"

/* With an argument, the isolation route. One parameter set per line (the values in the header's order); per set prints
 * "set STATUS N_ROOTS N_UNCERTAIN", then "root KIND CERTIFIED THETA LO HI K", then
 * "uncertain MODE LO HI", all in double. */
int main(int argc, char **argv)
{
    const int isolate = argc > 1 && argv[1] != NULL; /* the isolation route instead of analyze */
    double values[%(n)d];
    for (;;) {
        %(prefix)s_params params;
        %(prefix)s_analysis result;
        %(prefix)s_status status;
        int i;
        for (i = 0; i < %(n)d; ++i) {
            if (scanf("%%lf", &values[i]) != 1) {
                return 0;
            }
        }
%(assign)s
        status = isolate ? %(prefix)s_isolate(&params, &result) : %(prefix)s_analyze(&params, &result);
        if (status != 0) {
            printf("set %%d 0 0\n", (int)status);
            continue;
        }
        printf("set 0 %%d %%d\n", result.n_roots, result.n_uncertain);
        for (i = 0; i < result.n_roots; ++i) {
            const %(prefix)s_equilibrium *e = &result.roots[i];
            printf("root %%d %%d %%.17g %%.17g %%.17g %%.17g\n", (int)e->kind, e->certified,
                   (double)e->theta, (double)e->theta_lo, (double)e->theta_hi, (double)e->K);
        }
        for (i = 0; i < result.n_uncertain; ++i) {
            printf("uncertain %%u %%.17g %%.17g\n", result.uncertain[i].mode,
                   (double)result.uncertain[i].lo, (double)result.uncertain[i].hi);
        }
    }
}
"""


def _spec(name: str) -> dict:
    return json.loads((GENERATED / name / f"{name}_api.json").read_text())


def _compile(name: str, tmp: Path, flags: list[str], source: str, out: str) -> Path:
    path = tmp / f"{out}.c"
    path.write_text(source)
    binary = tmp / out
    sources = sorted((GENERATED / name).glob("*.c")) + sorted((GENERATED / "runtime").glob("*.c"))
    subprocess.run(["gcc", *STRICT, *flags, f"-I{GENERATED / name}",
                    f"-I{GENERATED / 'runtime'}", str(path), *map(str, sources), "-lm",
                    "-o", str(binary)], check=True, capture_output=True, text=True)
    return binary


def _driver_source(spec: dict) -> str:
    names = [p["name"] for p in spec["parameters"]]
    assign = "\n".join(f"        params.{n} = (codegen_real)values[{i}];"
                       for i, n in enumerate(names))
    return DRIVER % {"prefix": spec["prefix"], "n": len(names), "assign": assign}


def _parse(text: str) -> list:
    sets = []
    for line in text.splitlines():
        word, *rest = line.split()
        if word == "set":
            sets.append({"status": int(rest[0]), "roots": [], "uncertain": []})
        elif word == "root":
            kind, certified = int(rest[0]), int(rest[1])
            sets[-1]["roots"].append((kind, certified, *map(float, rest[2:])))
        else:
            sets[-1]["uncertain"].append((int(rest[0]), float(rest[1]), float(rest[2])))
    return sets


@pytest.fixture(scope="module")
def builds(tmp_path_factory):
    if shutil.which("gcc") is None:
        pytest.skip("needs gcc")
    tmp = tmp_path_factory.mktemp("float_build")
    made = {}
    for name in MECHANISMS:
        source = _driver_source(_spec(name))
        made[name] = (_compile(name, tmp, [], source, f"{name}_double"),
                      _compile(name, tmp, ["-DCODEGEN_FLOAT"], source, f"{name}_float"))
    return made


def _sets(spec: dict, count: int, spread: float, seed: int) -> np.ndarray:
    example = np.array([float(p["example"]) for p in spec["parameters"]])
    rng = np.random.default_rng(seed)
    factors = 1 + spread * rng.uniform(-1, 1, size=(count, example.size))
    # Rounded to float first, so that both builds analyse the very same parameters: the
    # float build's intervals are proofs about the parameters it holds.
    return np.vstack([example, example * factors]).astype(np.float32).astype(np.float64)


def _wide_sets(spec: dict, count: int, decades: float, seed: int) -> np.ndarray:
    """Sets drawn as the example times 10^u, u uniform in +-decades for each parameter (the
    search that found float losing equilibria near 0 and pi at aspect ratios of 200 and
    more), rounded to float as _sets does."""
    example = np.array([float(p["example"]) for p in spec["parameters"]])
    rng = np.random.default_rng(seed)
    factors = 10.0 ** rng.uniform(-decades, decades, size=(count, example.size))
    return (example * factors).astype(np.float32).astype(np.float64)


def _run(binary: Path, sets: np.ndarray, *route: str) -> list:
    text = "\n".join(" ".join(repr(float(v)) for v in row) for row in sets) + "\n"
    done = subprocess.run([str(binary), *route], input=text, capture_output=True, text=True,
                          check=True, timeout=600)
    return _parse(done.stdout)


def _inside(theta: float, lo: float, hi: float) -> bool:
    """theta in [lo, hi] as angles: an interval may be written across pi (lo or hi beyond it),
    and one 2 pi wide or more holds every angle."""
    margin = 4e-15 * max(abs(theta), 1.0)  # the double root's own rounding
    if hi - lo >= 2 * np.pi:
        return True
    turned = lo - margin + (theta - (lo - margin)) % (2 * np.pi)  # theta's turn from lo on
    return turned <= hi + margin


def _overlap(lo: float, hi: float, other_lo: float, other_hi: float) -> bool:
    """Whether two angle intervals meet, as _inside takes them."""
    return _inside(lo, other_lo, other_hi) or _inside(other_lo, lo, hi)


def silent_disagreements(double: dict, single: dict) -> list[str]:
    """What the float analysis of one set gets wrong without saying so."""
    if single["status"] != 0:
        return []  # a status is not silent
    problems = []
    sure = [r for r in single["roots"] if r[0] != EXTRANEOUS and r[1]]
    for kind, certified, theta, lo, hi, k in double["roots"]:
        if kind == EXTRANEOUS or not certified:
            continue
        matches = [r for r in sure if _same_kind(kind, r[0]) and _inside(theta, r[3], r[4])]
        covered = any(_inside(theta, u[1], u[2]) for u in single["uncertain"])
        if not matches and not covered:
            problems.append(f"equilibrium {theta!r} (kind {kind}) missing")
        for match in matches:
            scale = max(abs(r[5]) for r in double["roots"])
            if abs(k) > 1e-3 * scale and np.sign(k) != np.sign(match[5]):
                problems.append(f"equilibrium {theta!r}: K {k} in double, {match[5]} in float")
    for kind, certified, theta, lo, hi, k in sure:
        held = any(_inside(r[2], lo, hi) for r in double["roots"] if _same_kind(r[0], kind))
        covered = any(_overlap(lo, hi, u[1], u[2]) for u in double["uncertain"])
        uncertified = any(lo - 1e-6 <= r[2] <= hi + 1e-6 and not r[1] for r in double["roots"])
        if not (held or covered or uncertified):
            problems.append(f"float equilibrium in [{lo!r}, {hi!r}] (kind {kind}) invented")
    return problems


@pytest.mark.parametrize("name", MECHANISMS)
def test_float_never_silently_disagrees_with_double(builds, name):
    _compare(builds, name, SETS.get(name, SETS["default"]), seed=2026)


@pytest.mark.slow
@pytest.mark.parametrize("name", MECHANISMS)
def test_float_never_silently_disagrees_on_thousands_of_sets(builds, name):
    _compare(builds, name, 2000, seed=11)


@pytest.mark.slow
@pytest.mark.parametrize("name", MECHANISMS)
def test_float_never_silently_disagrees_across_six_decades(builds, name):
    """Every parameter drawn over 10^-3..10^3 times its example value."""
    spec = _spec(name)
    _compare(builds, name, 2000, seed=48, sets=_wide_sets(spec, 2000, 3.0, seed=48),
             analysed=0.5, roots_per_set=0.1)  # most wide four-bars close nowhere: no roots


# Issue 48's float reproducers, doughty's parameters in the header's order: an equilibrium
# 8.17e-8 deg from 0 (K = -7.1e7) between two stable ones 0.55 deg away, and L = 29491.2 with
# the rest at the example (four equilibria within 3e-4 deg of 0 and pi).
FLOAT_REPRODUCERS = [
    [0.0144452117, 3.28437495, 0.0146263279, 0.0178282652, 0.0168065038, 28.6438274,
     38779.4727, 49.9317284, 0.0313780978, 8.05679131, 0.564052999],
    [0.18, 29491.2, 0.135, 0.194, 0.143, 9.124, 3500.0, 875.0, 0.15, 110.0, 9.81],
]


def test_float_reproducers_lose_no_equilibrium(builds):
    sets = np.array(FLOAT_REPRODUCERS, dtype=np.float32).astype(np.float64)
    double_build, float_build = builds["doughty"]
    doubles, singles = _run(double_build, sets, "isolate"), _run(float_build, sets)
    for double, single in zip(doubles, singles):
        assert double["status"] == single["status"] == 0
        assert silent_disagreements(double, single) == []
    near_zero = [r for r in doubles[0]["roots"] if abs(r[2]) < 1e-8]
    assert len(near_zero) == 1 and near_zero[0][1]
    assert any(r[1] and r[3] <= near_zero[0][2] <= r[4] for r in singles[0]["roots"])


def _compare(builds, name: str, count: int, seed: int, sets: np.ndarray | None = None,
             analysed: float = 0.9, roots_per_set: float = 1.0) -> None:
    spec = _spec(name)
    sets = _sets(spec, count, 0.5, seed=seed) if sets is None else sets
    double_build, float_build = builds[name]
    # The reference is the double build's isolation route: complete and certified (its
    # polynomial route can miss an other-mode equilibrium beside a limit position).
    doubles, singles = _run(double_build, sets, "isolate"), _run(float_build, sets)
    assert len(doubles) == len(singles) == len(sets)
    problems = [f"set {i}: {p}" for i, (d, s) in enumerate(zip(doubles, singles))
                if d["status"] == 0 for p in silent_disagreements(d, s)]
    assert problems == []
    # The comparison compared something: most sets analysed in both, equilibria matched.
    both = sum(d["status"] == 0 and s["status"] == 0 for d, s in zip(doubles, singles))
    assert both >= analysed * len(sets)
    assert sum(len(s["roots"]) for s in singles) > roots_per_set * len(sets)


def test_float_table2_finds_every_root_and_classifies_it(builds):
    """The paper's example in float: its six equilibria proven, and all ten roots of the
    polynomial of the same kinds as in double, at angles within float's resolution."""
    spec = _spec(MECHANISMS[MECHANISMS.index("doughty")])
    example = _sets(spec, 0, 0.0, seed=0)
    double, single = (_run(b, example)[0] for b in builds["doughty"])
    assert single["status"] == 0 and single["uncertain"] == []
    assert [r[0] for r in single["roots"]] == [r[0] for r in double["roots"]]
    assert len(single["roots"]) == 10
    genuine = [r for r in single["roots"] if r[0] == EQUILIBRIUM]
    assert len(genuine) == 6 and all(r[1] for r in genuine)
    for d, s in zip(double["roots"], single["roots"]):
        assert abs(d[2] - s[2]) <= 1e-5
        if s[1]:
            assert s[3] <= d[2] <= s[4]  # the float interval is a proof


@pytest.mark.parametrize("flag, message", [
    ("-ffast-math", "-ffast-math"),
    ("-fsingle-precision-constant", "fsingle_precision_constant"),
])
def test_flags_that_break_the_library_are_refused(tmp_path, flag, message):
    if shutil.which("gcc") is None:
        pytest.skip("needs gcc")
    for real in ([], ["-DCODEGEN_FLOAT"]):
        done = subprocess.run(
            ["gcc", *cflags("base"), flag, *real, f"-I{GENERATED / 'runtime'}", "-c",
             str(GENERATED / "runtime" / "codegen_roots.c"), "-o", str(tmp_path / "x.o")],
            capture_output=True, text=True)
        assert done.returncode != 0 and message in done.stderr
