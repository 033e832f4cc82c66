"""`make embedded`: every library on a Cortex-M4F under QEMU, against the host.

The run (marked slow: ~1-2 min from nothing, seconds when build/embedded is current) needs
the cross toolchain and QEMU; locally their absence skips with the install command, under CI
it fails. The stack walker (embedded/stack.py) is also checked on graphs made up here.
"""
from __future__ import annotations

import json
import struct
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "embedded"))
import stack  # noqa: E402

LIBRARIES = sorted(p.name for p in (ROOT / "generated").iterdir() if (p / f"{p.name}.h").is_file())
#: The libraries with n > 1 coordinates: one analysis (no second route, no _work entry), and
#: their modes, receptance and box enclosure measured at a stable equilibrium.
MULTIBODY = sorted(lib for lib in LIBRARIES if json.loads(
    (ROOT / "generated" / lib / f"{lib}_api.json").read_text()).get("dof", 1) > 1)
MULTIBODY_CALLS = ("analyze", "modes", "receptance", "box_enclosure")
TOOLCHAIN = {"arm-none-eabi-gcc": "gcc-arm-none-eabi libnewlib-arm-none-eabi"}


@pytest.fixture(scope="module")
def report(need_tools, tmp_path_factory) -> dict:
    """`make embedded` with its report written to a temporary folder (embedded/report.md, the
    committed one, stays as it is)."""
    need_tools("arm-none-eabi-gcc", "qemu-system-arm", "make", "cc", packages=TOOLCHAIN)
    stem = tmp_path_factory.mktemp("embedded") / "report"
    done = subprocess.run(["make", "--no-print-directory", "embedded",
                           f"EMBEDDED_REPORT={stem}", f"PYTHON={sys.executable}"],
                          cwd=ROOT, capture_output=True, text=True, timeout=1200)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    result = json.loads(stem.with_suffix(".json").read_text())
    result["markdown"] = stem.with_suffix(".md").read_text()
    return result


def _entries(report: dict):
    for build, libs in report["builds"].items():
        for lib, entry in libs.items():
            yield build, lib, entry


@pytest.mark.slow
def test_every_library_runs_in_both_builds(report):
    assert set(report["builds"]) == {"double", "float"}
    for build in ("double", "float"):
        assert sorted(report["builds"][build]) == LIBRARIES
    for build, lib, entry in _entries(report):
        assert set(entry["measured"]) >= set(_routes(lib)), (build, lib)
        assert entry["multibody"] == (lib in MULTIBODY)
        assert entry["measured"]["analyze"]["instructions"] > 0
        assert entry["comparison"]["lines"] > 20  # the analysis was printed, not only a status
        assert f"| `{lib}` | {build} |" in report["markdown"]


@pytest.mark.slow
def test_instruction_counts_are_exact(report):
    """A loop of exactly 2001 instructions, measured as the analysis is."""
    assert {entry["measured"]["calibration"] for _, _, entry in _entries(report)} == {2001}


@pytest.mark.slow
def test_the_worst_case_stack_covers_what_the_firmware_used(report):
    """The call-graph bound is at least the painted stack's high-water mark, for both routes
    (a walker that missed a frame or a call would fall below it)."""
    for build, lib, entry in _entries(report):
        functions = entry["stack"]["functions"]
        for route in _routes(lib):
            bound = functions[f"{lib}_{route}"]
            assert bound["bytes"] >= entry["measured"][route]["stack"] > 0, (build, lib, route)


def _routes(lib: str) -> tuple[str, ...]:
    """What the firmware measures: both routes, or a multibody library's analysis and the
    calls at its stable equilibrium."""
    return MULTIBODY_CALLS if lib in MULTIBODY else ("analyze", "isolate")


@pytest.mark.slow
def test_code_size_is_reported_per_group(report):
    for _, lib, entry in _entries(report):
        assert ({"functions", "runtime multibody", "runtime boxes", "runtime modal",
                 "runtime interval"} if lib in MULTIBODY else
                {"functions", "model", "runtime analysis", "runtime simulation", "runtime roots",
                 "runtime interval", "runtime dd"}) <= set(entry["size"]), lib
        assert all(size["text"] > 0 for size in entry["size"].values())


@pytest.mark.slow
@pytest.mark.parametrize("build", ["double", "float"])
@pytest.mark.parametrize("lib", LIBRARIES)
def test_firmware_prints_what_the_host_prints_but_libm_bits(report, build, lib):
    """Every count, kind, status and line as on the host. Values may differ in their last
    bits where newlib's sin, cos, atan2 (or sinf ...) round otherwise than glibc's; sigma's
    double-double products do not (newlib 3.3's fma rounds twice: the firmware prints so,
    and the library takes exact products from Dekker's TwoProduct instead), nor does
    anything of a library whose example needs no such call."""
    entry = report["builds"][build][lib]
    assert entry["comparison"]["identical"] or entry["comparison"]["only_values_differ"], (
        entry["comparison"])
    assert entry["verdict"] != "DIFFERS"
    if build == "double":   # double-double: exact products on any libm
        assert _sigma_lines(build, lib, "target") == _sigma_lines(build, lib, "host")
    # the runtime's modal linear algebra calls only sqrt, fabs, copysign and fmax, which
    # round exactly on any libm: its self-test is the host's bit for bit in both builds
    modal = _modal_lines(build, lib, "target")
    assert modal[0] == "modes: status 0" and len(modal) == 1 + 12 + 1 + 12 + 1 + 18
    assert modal == _modal_lines(build, lib, "host")


#: Relative to the largest of its kind: how far a float build's modal values may lie from the
#: host's (newlib's sinf, cosf against glibc's in the equilibria and the matrices at them);
#: a double build's.
MODAL_RTOL = {"double": 1e-12, "float": 1e-5}


@pytest.mark.slow
@pytest.mark.parametrize("build", ["double", "float"])
@pytest.mark.parametrize("lib", MULTIBODY)
def test_multibody_firmware_finds_the_hosts_equilibria(report, build, lib):
    """A library with n coordinates: the firmware proves as many equilibria as the host, each
    inside the box the host proved (and the host's inside the firmware's), with the same
    stability; their modes, receptances and K's enclosure within rounding of the host's
    (newlib's sin and cos are not glibc's: last bits differ, in double too); PREFIX_modes
    repeats the analysis' modes bit for bit and the enclosure of G over a proven box holds 0."""
    target, host = (_values(build, lib, side) for side in ("target", "host"))
    lines = {side: _printed(build, lib, side) for side in ("target", "host")}
    summary = [[x for x in lines[side] if x.startswith(("analyze:", "equilibria ", "stability[",
                                                         "modal_status[", "uncertain_kind["))]
               for side in ("target", "host")]
    assert summary[0] == summary[1] and "analyze: status 0" in summary[0]
    count = int(next(x for x in summary[0] if x.startswith("equilibria ")).split()[1].rstrip(","))
    assert count >= 1
    n = sum(1 for name, _ in host if name == "theta") // count
    for r in range(count):
        for k in range(r * n, (r + 1) * n):
            for a, b in ((target, host), (host, target)):
                assert b["lo", k] <= a["theta", k] <= b["hi", k], (r, k)
    for name in ("omega_squared", "s_re", "s_im", "damping_ratio", "modal_damping", "shapes",
                 "H_re", "H_im", "K"):
        keys = [key for key in host if key[0] == name]
        scale = max(abs(host[key]) for key in keys if host[key] == host[key])
        for key in keys:
            if host[key] != host[key]:  # NaN where documented: a modal damping of omega^2 <= 0
                assert target[key] != target[key], key
            else:
                assert abs(target[key] - host[key]) <= MODAL_RTOL[build] * scale, key
    for side in ("target", "host"):
        assert "the same as the analysis' modes: 1" in lines[side]
        g = _values(build, lib, side)
        for i in range(n):
            assert g["G", 2 * i] <= 0 <= g["G", 2 * i + 1]


def _values(build: str, lib: str, side: str) -> dict[tuple[str, int], float]:
    """The values a firmware or the host printed (name[index] = 0xBITS decimal), by name and
    index; the modal self-test's (the last lines) left out."""
    lines = _printed(build, lib, side)
    values = {}
    for line in lines[:lines.index("modes: status 0")]:
        name, _, rest = line.partition("[")
        if " = 0x" in rest:
            index, bits = rest.split("] = 0x")
            values[name, int(index)] = struct.unpack(">d", bytes.fromhex(bits.split()[0]))[0]
    return values


def _printed(build: str, lib: str, side: str) -> list[str]:
    """What a firmware ('target') or the host printed, in make embedded's build folder."""
    return (ROOT / "build" / "embedded" / build / lib / f"{side}.txt").read_text().splitlines()


def _sigma_lines(build: str, lib: str, side: str) -> list[str]:
    return [line for line in _printed(build, lib, side) if line.startswith("sigma[")]


def _modal_lines(build: str, lib: str, side: str) -> list[str]:
    """The modal self-test's lines (codegen_modal.c on fixed 3 x 3 matrices): the last."""
    lines = _printed(build, lib, side)
    return lines[lines.index("modes: status 0"):]


# --------------------------------------------------------------- the walker, on made-up graphs


def test_worst_stack_adds_the_deepest_chain_and_flags_recursion():
    graph = stack.Graph(frames={"main": 16, "a": 100, "b": 40, "c": 8, "leaf": 24},
                        calls={"main": {"a", "b"}, "a": {"leaf"}, "b": {"c"}, "c": {"b"}})
    main = stack.worst_stack(graph, "main")
    assert main.bytes == 16 + 100 + 24
    assert [name for name, _ in main.path] == ["main", "a", "leaf"]
    assert not main.bounded                   # b -> c -> b: no bound from the graph
    assert stack.worst_stack(graph, "a").bounded and stack.worst_stack(graph, "a").bytes == 124


def test_indirect_calls_reach_what_the_entry_or_static_data_takes_the_address_of():
    # analyze passes isolate's callback `enclose` to `search`, which calls it indirectly;
    # simulate passes `rhs` to `step`; `handler` sits in a static table
    graph = stack.Graph(
        frames={"analyze": 8, "search": 16, "enclose": 100, "simulate": 8, "step": 16,
                "rhs": 900, "handler": 40},
        calls={"analyze": {"search"}, "search": {stack.INDIRECT},
               "simulate": {"step"}, "step": {stack.INDIRECT}},
        taken_by={"enclose": {"analyze"}, "rhs": {"simulate"}, "handler": {stack.STATIC_DATA}})
    assert stack.indirect_targets(graph, "analyze") == {"enclose", "handler"}
    assert stack.worst_stack(graph, "analyze").bytes == 8 + 16 + 100
    assert stack.worst_stack(graph, "simulate").bytes == 8 + 16 + 900
    # a function reached only indirectly takes another address: found to a fixed point
    graph.taken_by["rhs"].add("enclose")
    assert stack.indirect_targets(graph, "analyze") == {"enclose", "handler", "rhs"}
    assert stack.worst_stack(graph, "analyze").bytes == 8 + 16 + 900
    nowhere = stack.Graph(frames={"f": 8}, calls={"f": {stack.INDIRECT}})
    assert not stack.worst_stack(nowhere, "f").bounded   # a target we cannot see


def test_a_call_through_a_named_pointer_reaches_the_taken_functions_of_that_name(tmp_path):
    # the runtime calls model->equilibrium_state and its callback enclose; the library's
    # static table holds both kernels, and a third, heavier one nothing here calls by name
    source = tmp_path / "runtime.c"
    source.write_text("int f(void)\n{\n    return model->enclose(c);\n    s->f(x);\n}\n")
    assert stack._pointer_name(source, 3, 12) == "enclose"
    assert stack._pointer_name(source, 4, 5) == "f"
    assert stack._pointer_name(source, 9, 1) is None
    graph = stack.Graph(
        frames={"run": 8, "isolate": 16, "lib.c:enclose": 100, "lib.c:equilibrium_state": 900,
                "step": 16},
        calls={"run": {"isolate", "step"}, "isolate": {stack.indirect_call("enclose")},
               "step": {stack.indirect_call("rhs")}},
        taken_by={"lib.c:enclose": {stack.STATIC_DATA},
                  "lib.c:equilibrium_state": {stack.STATIC_DATA}})
    assert stack.worst_stack(graph, "isolate").bytes == 16 + 100
    # no taken function is named rhs: it may reach any of them
    assert stack.worst_stack(graph, "step").bytes == 16 + 900


def test_frames_and_calls_from_a_disassembly():
    listing = "\n".join([
        "00000100 <sin>:",
        "     100:\tpush\t{r4, r5, r6, lr}",
        "     102:\tvpush\t{d8-d9}",
        "     106:\tsub\tsp, #20",
        "     108:\tbl\t200 <__kernel_sin>",
        "     10c:\tbeq.n\t110 <sin+0x10>",
        "     10e:\tb.w\t300 <floor>",
        "00000200 <__kernel_sin>:",
        "     200:\tstmdb\tsp!, {r4, r5, r6, r7, r8, lr}",
        "     204:\tsub.w\tsp, sp, #256\t@ 0x100",
        "     208:\tblx\tr3",
    ])
    graph = stack.Graph()
    stack.read_disassembly(listing, graph)
    assert graph.frames == {"sin": 16 + 16 + 20, "__kernel_sin": 24 + 256}
    assert graph.calls == {"sin": {"__kernel_sin", "floor"}, "__kernel_sin": {stack.INDIRECT}}
