"""The runtime's certified isolation in n dimensions (runtime/codegen_boxes.c), on
its own (issue 31): every zero of G: R^n -> R^n in a box, each proven by Krawczyk's operator,
what cannot be decided reported, never dropped, never counted as a zero.

Driven through drivers/boxes_driver.c, whose problems are written by hand in interval
arithmetic. The references share nothing with the runtime: closed forms, and for the double
pendulum's statics (two bars on torsional springs: G = dV/dtheta) a reduction to one
equation in theta_2, scanned densely and refined by mpmath at 30 digits. Cases: the
textbook examples, hypothesis-drawn spring stiffnesses (weak springs: several equilibria),
sets 1e-6 relative either side of the upright's buckling threshold (the count changes by two
there, or a cluster is reported at the upright: never an odd miscount), a zero on the first
split plane (found once), a double zero (a cluster), a pole (a singular box), capacity,
misuse, float, and sanitizers.
"""
from __future__ import annotations

import math
import os

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

ROOT, CLUSTER, SINGULAR = 0, 1, 2
FULL, BAD_INPUT = -1, -3
SPLIT = 0.5078125   # where the runtime halves a box (codegen_boxes.c)


def h(x: float) -> str:
    return float(x).hex()


class Boxes:
    """tests/support/c/boxes_driver.c: solve commands, answers parsed."""

    def __init__(self, program):
        self.program = program

    def line(self, problem, n, p, lo, hi, capacity=64) -> str:
        p = list(p) + [0.0] * (6 - len(p))
        return (f"solve {problem} {n} {' '.join(map(h, p))} {' '.join(map(h, lo))} "
                f"{' '.join(map(h, hi))} {capacity}")

    def solve_many(self, requests):
        """[(status, [(kind, lo, hi, point)])] for [(problem, n, p, lo, hi[, capacity])]."""
        out = self.program([self.line(*r) for r in requests])
        results = []
        for request, words in zip(requests, out):
            n = request[1]
            status, count = int(words[0]), int(words[1])
            values = words[2:]
            boxes = []
            for r in range(count):
                f = values[r * (1 + 3 * n):(r + 1) * (1 + 3 * n)]
                nums = np.array([float.fromhex(x) for x in f[1:]])
                boxes.append((int(f[0]), nums[:n], nums[n:2 * n], nums[2 * n:]))
            results.append((status, boxes))
        return results

    def solve(self, *request):
        return self.solve_many([request])[0]


def _build(runtime_driver, tmp_path_factory, name, flags=None, defines=(), env=None):
    exe = tmp_path_factory.mktemp(name) / name
    runtime_driver.build(exe, "boxes_driver.c", ("codegen_boxes.c", "codegen_interval.c"),
                         flags=flags, defines=defines)
    return Boxes(runtime_driver.program(exe, env))


@pytest.fixture(scope="module")
def boxes(runtime_driver, tmp_path_factory):
    return _build(runtime_driver, tmp_path_factory, "boxes_driver")


def roots_of(result):
    status, found = result
    assert status == 0, status
    return [b for b in found if b[0] == ROOT]


def inside(point, lo, hi, slack=0.0) -> bool:
    return bool(np.all(point >= lo - slack) and np.all(point <= hi + slack))


# --------------------------------------------------------------------------- closed forms


def test_circle_and_line_two_roots_each_proven_once(boxes):
    r, b = 1.0, 0.5
    found = roots_of(boxes.solve("circle", 2, [r, b], [-2, -2], [2, 2]))
    y = r / math.sqrt(1 + b * b)
    exact = [np.array([b * y, y]), np.array([-b * y, -y])]
    assert len(found) == 2
    for e in exact:
        (box,) = [f for f in found if inside(e, f[1], f[2], 1e-15)]
        assert np.max(np.abs(box[3] - e)) <= 4e-16 and np.max(box[2] - box[1]) <= 1e-14


def test_three_coordinates(boxes):
    """x = y^2, y = z^2, z = x^2: the real zeros are (0, 0, 0) and (1, 1, 1)."""
    found = roots_of(boxes.solve("cyclic", 3, [], [-2] * 3, [2] * 3))
    points = sorted(tuple(np.round(f[3], 12)) for f in found)
    assert points == [(0.0, 0.0, 0.0), (1.0, 1.0, 1.0)]


def test_no_zero_no_result(boxes):
    assert boxes.solve("none", 2, [], [-2, -2], [2, 2]) == (0, [])


def test_a_zero_on_the_first_split_plane_is_found_once(boxes):
    """The box is first halved at 0.5078125 of its widest side: a zero exactly there lies on
    both halves' faces, where neither half can prove it; the inflated box does, once."""
    for n in (1, 2, 3):
        lo, hi = -1.0, 1.0
        cut = (1 - SPLIT) * lo + SPLIT * hi
        found = roots_of(boxes.solve("shift", n, [cut, 0.125], [lo] * n, [hi] * n))
        assert len(found) == 1
        expected = np.array([cut + i * 0.125 for i in range(n)])
        assert inside(expected, found[0][1], found[0][2])


def test_a_double_zero_is_a_cluster_never_a_root(boxes):
    status, found = boxes.solve("double", 2, [0.0, 0.3], [-1, -1], [1, 1])
    assert status == 0 and found and all(f[0] == CLUSTER for f in found)
    assert any(inside(np.array([0.0, 0.3]), f[1], f[2]) for f in found)
    # split apart by more than rounding: two proven roots
    found = roots_of(boxes.solve("double", 2, [1e-6, 0.3], [-1, -1], [1, 1]))
    assert sorted(round(f[3][0], 12) for f in found) == [-0.001, 0.001]


def test_a_pole_is_a_singular_box_and_the_root_beside_it_proven(boxes):
    status, found = boxes.solve("pole", 2, [1.0], [-2, -2], [2, 2])
    assert status == 0
    kinds = sorted(f[0] for f in found)
    assert kinds == [ROOT, SINGULAR]
    root = next(f for f in found if f[0] == ROOT)
    assert np.allclose(root[3], [1.0, 0.0], atol=1e-15)
    singular = next(f for f in found if f[0] == SINGULAR)
    assert inside(np.array([0.0, 0.0]), singular[1], singular[2])


def test_capacity_and_misuse(boxes):
    status, found = boxes.solve("circle", 2, [1.0, 0.5], [-2, -2], [2, 2], 1)
    assert status == FULL and len(found) == 1
    assert boxes.program(["misuse"])[0] == [str(BAD_INPUT)] * 3


# --------------------------------------------------------------------------- double pendulum

#: The example of ../shared/MECHANISMS.md's double_pendulum, as the statics' constants:
#: k1, k2, alpha1, alpha2, c1 = g l1 (m1/2 + m2 + m_t), c2 = g l2 (m2/2 + m_t).
G_ACC, L1, L2, M1, M2, MT = 9.81, 1.0, 0.8, 1.0, 0.8, 0.5
C1, C2 = G_ACC * L1 * (M1 / 2 + M2 + MT), G_ACC * L2 * (M2 / 2 + MT)
ALPHA1, ALPHA2 = math.pi / 2, 0.0


def pendulum_box(a1=ALPHA1, a2=ALPHA2):
    """theta_1 in (a1 - pi, a1 + pi], theta_2 - theta_1 in (a2 - pi, a2 + pi]: the runtime
    searches the box theta_1, theta_2 in [a1 - pi, a1 + pi] x [a1 + a2 - 2 pi, a1 + a2 + 2 pi]
    (a superset; the reference filters the same box)."""
    return [a1 - math.pi, a1 + a2 - 2 * math.pi], [a1 + math.pi, a1 + a2 + 2 * math.pi]


def pendulum_reference(k1, k2, a1=ALPHA1, a2=ALPHA2, c1=C1, c2=C2, samples=200001):
    """Every zero of G in the box, independently: G_2 = 0 gives theta_1 as a function of
    theta_2, t1 = t2 - a2 + (c2 / k2) cos t2; G_1 along it, scanned densely in theta_2 and
    refined at 30 digits. Returns the zeros (theta_1, theta_2) inside the box."""
    lo, hi = pendulum_box(a1, a2)
    t2 = np.linspace(lo[1], hi[1], samples)
    t1 = t2 - a2 + c2 / k2 * np.cos(t2)

    def g1(t1, t2, lib=np):
        return k1 * (t1 - a1) - k2 * (t2 - t1 - a2) + c1 * lib.cos(t1)

    values = g1(t1, t2)
    zeros = []
    with mpmath.workdps(30):
        def f(t):
            t = mpmath.mpf(t)
            s1 = t - a2 + mpmath.mpf(c2) / k2 * mpmath.cos(t)
            return g1(s1, t, mpmath)
        for i in np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]:
            root = mpmath.findroot(f, (t2[i], t2[i + 1]), solver="anderson")
            r1 = float(root - a2 + mpmath.mpf(c2) / k2 * mpmath.cos(root))
            zeros.append((r1, float(root)))
    return [z for z in zeros if lo[0] <= z[0] <= hi[0] and lo[1] <= z[1] <= hi[1]]


def check_pendulum(boxes, k1, k2):
    lo, hi = pendulum_box()
    status, found = boxes.solve("pendulum", 2, [k1, k2, ALPHA1, ALPHA2, C1, C2], lo, hi)
    assert status == 0
    expected = pendulum_reference(k1, k2)
    roots = [f for f in found if f[0] == ROOT]
    undecided = [f for f in found if f[0] != ROOT]
    # every reference zero in a proven box or an undecided one; every proven box one of them
    for z in expected:
        assert any(inside(np.array(z), f[1], f[2], 1e-9) for f in found), (k1, k2, z)
    for f in roots:
        assert sum(inside(np.array(z), f[1], f[2], 1e-9) for z in expected) == 1, (k1, k2, f)
    if not undecided:
        assert len(roots) == len(expected), (k1, k2)
    return roots, undecided, expected


def test_double_pendulum_example(boxes):
    """The example: the upright (unstable) and two buckled equilibria."""
    roots, undecided, expected = check_pendulum(boxes, 30.0, 15.0)
    assert len(roots) == len(expected) == 3 and not undecided


@settings(max_examples=40, deadline=None)
@given(st.floats(0.5, 80.0), st.floats(0.5, 40.0))
def test_double_pendulum_drawn_springs(boxes, k1, k2):
    """Springs weak enough for many equilibria (up to a dozen over the box) or strong enough
    for one: every zero found, each proven root one zero."""
    check_pendulum(boxes, k1, k2)


def buckling_k1(k2, c1=C1, c2=C2):
    """k1 where the upright's stiffness matrix is singular (a pitchfork):
    det [[k1 + k2 - c1, -k2], [-k2, k2 - c2]] = 0."""
    return c1 - k2 + k2 * k2 / (k2 - c2)


@pytest.mark.parametrize("k2", [15.0, 25.0])
@pytest.mark.parametrize("side", [-1, 1])
def test_either_side_of_the_buckling_threshold(boxes, k2, side):
    """1e-6 relative either side of the pitchfork: the two buckled equilibria near the upright
    are proven (a pair, about 1e-3 rad from it) or the upright's neighbourhood is one
    cluster; the count never changes by one."""
    k1 = buckling_k1(k2) * (1 + side * 1e-6)
    roots, undecided, expected = check_pendulum(boxes, k1, k2)
    near = [f for f in roots if np.max(np.abs(f[3] - [ALPHA1, ALPHA1])) < 0.05]
    assert len(near) in (1, 3) or undecided
    assert (len(roots) - len(expected)) % 2 == 0 or undecided


# --------------------------------------------------------------------------- float, sanitizers


def test_float_build_finds_the_same_zeros(runtime_driver, tmp_path_factory):
    single = _build(runtime_driver, tmp_path_factory, "boxes_float", defines=("-DCODEGEN_FLOAT",))
    found = roots_of(single.solve("circle", 2, [1.0, 0.5], [-2, -2], [2, 2]))
    assert sorted(round(f[3][1], 5) for f in found) == [-0.89443, 0.89443]
    lo, hi = pendulum_box()
    status, found = single.solve("pendulum", 2, [30.0, 15.0, ALPHA1, ALPHA2, C1, C2], lo, hi)
    expected = pendulum_reference(30.0, 15.0)
    assert status == 0 and len([f for f in found if f[0] == ROOT]) == len(expected)


def test_sanitized_driver_gives_the_same_answers(boxes, sanitizer, runtime_driver,
                                                 tmp_path_factory):
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0", UBSAN_OPTIONS="print_stacktrace=1")
    sanitized = _build(runtime_driver, tmp_path_factory, "boxes_san",
                       flags=[*sanitizer.flags, *runtime_driver.warnings], env=env)
    lo, hi = pendulum_box()
    lines = ["misuse",
             boxes.line("circle", 2, [1.0, 0.5], [-2, -2], [2, 2]),
             boxes.line("pendulum", 2, [3.0, 2.0, ALPHA1, ALPHA2, C1, C2], lo, hi),
             boxes.line("pole", 2, [1.0], [-2, -2], [2, 2]),
             boxes.line("cyclic", 3, [], [-2] * 3, [2] * 3),
             boxes.line("shift", 6, [0.1, 0.2], [-1] * 6, [1] * 6)]
    assert sanitized.program.raw(lines) == boxes.program.raw(lines)
