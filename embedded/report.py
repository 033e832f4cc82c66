"""embedded/report.md and .json from what `make embedded` built and ran (embedded/embedded.mk).

For each build (double, float) and library: code size per group of objects
(arm-none-eabi-size), the worst-case stack of every public function (stack.py, from gcc's call
graphs) beside the high-water mark the firmware measured, the instructions QEMU counted for
each route of the example's analysis, and the firmware's output against the host's. Exits 1
when a double build's output differs from the host's for no cause it can name.

A library with n coordinates (codegen_multibody: one route, NAME_analyze_work, and modes,
receptance and box enclosures at a point) gets its own section after render.py's tables,
which are the one-coordinate libraries'.

Usage: report.py BUILD_DIR OUT_STEM CFLAGS   (writes OUT_STEM.md and OUT_STEM.json; CFLAGS: the
cross compiler's flags, for the record)
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import stack  # noqa: E402  (beside this file)
import render  # noqa: E402
from render import markdown  # noqa: E402

_VALUE = re.compile(r"^(\S+) = 0x([0-9a-f]{16}) ")


def sizes(objects: dict[str, Path]) -> dict[str, dict[str, int]]:
    """Group -> text (code and constants: flash), data, bss, from arm-none-eabi-size."""
    out = stack.tool("arm-none-eabi-size", *map(str, objects.values())).splitlines()[1:]
    return {group: dict(zip(("text", "data", "bss"), map(int, line.split()[:3])))
            for group, line in zip(objects, out)}


def object_groups(build: Path, lib: str) -> dict[str, Path]:
    """The library's objects by what they hold: its functions, its model (the descriptor and
    the public entries), and each part of the runtime (analysis, roots, interval, dd...:
    codegen_NAME.c)."""
    groups = {}
    for obj in sorted((build / lib).glob(f"{lib}*.o")):
        groups[obj.stem.removeprefix(lib).lstrip("_") or "functions"] = obj
    for obj in sorted((build / "runtime").glob("*.o")):
        groups[f"runtime {obj.stem.removeprefix('codegen_')}"] = obj
    return groups


def public_functions(objects: list[Path]) -> list[str]:
    """The functions the library's header declares: its global ones but the kernels."""
    names = []
    for obj in objects:
        for line in stack.tool("arm-none-eabi-nm", "-g", "--defined-only", str(obj)).splitlines():
            _, kind, name = line.split()
            if kind == "T" and not name.endswith(("_kernel", "_kernel_work")):
                names.append(name)
    return sorted(names)


def cycles_through(graph: stack.Graph, roots: list[str]) -> list[list[str]]:
    """The recursions reachable from roots, each once (as the functions on its cycle)."""
    found, seen = [], set()

    def visit(name: str, path: list[str]) -> None:
        for callee in sorted(graph.calls.get(name, ())):
            if callee in path:
                cycle = path[path.index(callee):]
                if frozenset(cycle) not in seen:
                    seen.add(frozenset(cycle))
                    found.append(cycle)
            elif callee not in done:
                visit(callee, path + [callee])
        done.add(name)

    done: set[str] = set()
    for root in roots:
        visit(root, [root])
    return found


def stack_report(build: Path, lib: str, library_objects: list[Path]) -> dict:
    graph = stack.Graph()
    stack.read_callgraphs(library_objects + sorted((build / "runtime").glob("*.o")), graph)
    stack.read_binary(build / lib / "firmware.elf", graph)
    functions = {}
    for name in public_functions(library_objects):
        result = stack.worst_stack(graph, name)
        functions[name] = {"bytes": result.bytes, "bounded": result.bounded,
                           "path": [[stack.short(f), frame] for f, frame in result.path]}
    cycles = cycles_through(graph, list(functions))
    return {"functions": functions,
            "recursion": [{"functions": [stack.short(f) for f in cycle],
                           "bytes_per_level": sum(graph.frames.get(f, 0) for f in cycle)}
                          for cycle in cycles],
            "calls_fma": _reaches(graph, functions, "fma")}


def _reaches(graph: stack.Graph, roots, target: str) -> bool:
    """Whether any of roots calls target, however indirectly."""
    todo, seen = list(roots), set()
    while todo:
        name = todo.pop()
        if name == target:
            return True
        if name not in seen:
            seen.add(name)
            todo.extend(graph.calls.get(name, ()))
    return False


def measured(target_output: str) -> dict:
    """The firmware's '# ' lines: per route its instructions and stack high-water mark."""
    result = {"fma_rounds_once": None, "calibration": None}
    for line in target_output.splitlines():
        route = re.match(r"# (\w+): instructions (\d+) stack (\d+)", line)
        if route:
            result[route.group(1)] = {"instructions": int(route.group(2)),
                                      "stack": int(route.group(3))}
        calibration = re.match(r"# calibration: 2001 instructions counted as (\d+)", line)
        if calibration:
            result["calibration"] = int(calibration.group(1))
        fma = re.match(r"# libm fma rounds once: (\d)", line)
        if fma:
            result["fma_rounds_once"] = fma.group(1) == "1"
    return result


#: Bits of a double's significand below a float's: a float build prints its values widened
#: to double (exactly), so its ulps are 2^29 of the double's.
WIDENING_BITS = {"double": 0, "float": 52 - 23}


def _ulps(a: str, b: str, real: str = "double") -> int:
    """Distance in units in the last place of ``real`` between two values printed as the
    bits of a double (a float's widened exactly)."""
    def ordered(bits: str) -> int:
        value = int(bits, 16)
        return value if value < 1 << 63 else (1 << 63) - value
    return abs(ordered(a) - ordered(b)) >> WIDENING_BITS[real]


_DECIMAL = re.compile(r"-?\d+\.\d+")


def _shape(line: str) -> str:
    """A line with its values masked: a value's name, or a summary line with its decimals
    (angles, K_EQ) as N; counts, kinds and statuses (integers) kept."""
    value = _VALUE.match(line)
    return value.group(1) if value else " ".join(_DECIMAL.sub("N", line).split())


def _set_apart_uncertain(lines: list[str]) -> tuple[list[str], list[str]]:
    """(the lines, the undecided intervals' lines)."""
    return ([x for x in lines if not x.startswith("uncertain")],
            [x for x in lines if x.startswith("uncertain")])


def comparison(host: str, target: str, real: str = "double") -> dict:
    """The firmware's output against the host's, the measurements ('# ') aside."""
    host_lines = [x for x in host.splitlines() if not x.startswith("#")]
    target_lines = [x for x in target.splitlines() if not x.startswith("#")]
    if host_lines == target_lines:
        return {"identical": True, "lines": len(host_lines)}
    # Undecided intervals may split differently where the libm's bounds differ: compared
    # apart from the rest
    (host_kept, host_uncertain), (target_kept, target_uncertain) = (
        _set_apart_uncertain(lines) for lines in (host_lines, target_lines))
    same_shape = [_shape(x) for x in host_kept] == [_shape(x) for x in target_kept]
    differing = [(h, t) for h, t in zip(host_kept, target_kept) if h != t]
    values = [(_VALUE.match(h), _VALUE.match(t)) for h, t in differing]
    return {"identical": False, "lines": len(host_lines),
            "differing_lines": len(differing) + abs(len(host_uncertain) - len(target_uncertain)),
            # every difference is in a value's bits, none in a count, kind or status
            "only_values_differ": same_shape,
            "uncertain_differ": host_uncertain != target_uncertain,
            # in the roots' angles (a residual, G at a root, is rounding noise: any ulps)
            "max_ulps_theta": max((_ulps(h.group(2), t.group(2), real) for h, t in values
                                   if h and t and h.group(1).startswith("theta[")),
                                  default=0) if same_shape else None,
            "first_difference": list(differing[0]) if differing else None}


def verdict(entry: dict) -> str:
    same = entry["comparison"]
    if same["identical"]:
        return "identical"
    if same["only_values_differ"]:
        # newlib's sin, cos, atan2 ... (and their float versions) are not glibc's: last bits
        # passed on; undecided intervals may split differently
        return "values differ (libm)" + (", uncertain intervals split differently"
                                         if same["uncertain_differ"] else "")
    return "DIFFERS"


def collect(out: Path, cflags: str) -> dict:
    report = {"builds": {}, "tools": {
        "gcc": stack.tool("arm-none-eabi-gcc", "-dumpversion").strip(),
        "qemu": stack.tool("qemu-system-arm", "--version").split()[3],
        "cflags": " ".join(cflags.split())}}
    for build in sorted(p for p in out.iterdir() if (p / "runtime").is_dir()):
        libs = {}
        for lib_dir in sorted(p for p in build.iterdir() if (p / "firmware.elf").is_file()):
            lib = lib_dir.name
            groups = object_groups(build, lib)
            library_objects = [obj for group, obj in groups.items()
                               if not group.startswith("runtime")]
            target = (lib_dir / "target.txt").read_text()
            entry = {"size": sizes(groups), "stack": stack_report(build, lib, library_objects),
                     "measured": measured(target),
                     "comparison": comparison((lib_dir / "host.txt").read_text(), target,
                                              build.name)}
            entry["verdict"] = verdict(entry)
            entry["multibody"] = is_multibody(entry)
            libs[lib] = entry
        report["builds"][build.name] = libs
    report["float_is_double"] = _same_objects(out / "double", out / "float")
    return report


def is_multibody(entry: dict) -> bool:
    """Whether the library is one with n coordinates: it has the ranges' centres
    (PREFIX_range_centres), which one coordinate's has not."""
    return any(name.endswith("_range_centres") for name in entry["stack"]["functions"])


def _only(report: dict, multibody: bool) -> dict:
    """The report with only the libraries of one kind."""
    return {**report, "builds": {build: {lib: entry for lib, entry in libs.items()
                                         if entry.get("multibody", False) == multibody}
                                 for build, libs in report["builds"].items()}}


#: What the firmware of a library with n coordinates measures besides its analysis (at the
#: example's first stable equilibrium).
MULTIBODY_CALLS = ("modes", "receptance", "box_enclosure")


def multibody_markdown(report: dict) -> list[str]:
    """The section of the libraries with n coordinates: their analysis against the issue's
    targets (in the caller's working memory, and with its own on its stack), the other calls'
    instructions and stack, code size, the deepest stack chain, the firmware against the host."""
    entries = list(render._entries(report))
    if not entries:
        return []
    targets, calls = [], []
    for lib, build, entry in entries:
        prefix = render._prefix(entry)
        functions, measured = entry["stack"]["functions"], entry["measured"]
        worst = functions[f"{prefix}_analyze_work"]
        limit, budget = render.STACK_TARGET[build], render.INSTRUCTIONS_TARGET[build]
        instructions = measured.get("analyze", {}).get("instructions")
        others = {n: f for n, f in functions.items()
                  if not n.endswith(("_analyze", "_analyze_work", "_batch"))}
        largest = max(others, key=lambda n: others[n]["bytes"])
        targets.append([
            f"`{lib}`", build, render._stack_cell(entry, f"{prefix}_analyze_work"),
            render._stack_cell(entry, f"{prefix}_analyze"), render._n(limit),
            f"{worst['bytes'] / limit:.1f}x over" if worst["bytes"] > limit else "met",
            render._n(measured.get("analyze", {}).get("stack")), render._n(instructions),
            "-" if not instructions else "met" if instructions <= budget
            else f"{instructions / budget:.1f}x over",
            f"`{largest.removeprefix(prefix + '_')}` {render._n(others[largest]['bytes'])}"])
        calls.append([f"`{lib}`", build] + [
            f"{render._n(measured.get(call, {}).get('instructions'))} / "
            f"{render._n(measured.get(call, {}).get('stack'))} / "
            f"{render._stack_cell(entry, f'{prefix}_{call}')}" for call in MULTIBODY_CALLS])
    paths = []
    for lib, entry in report["builds"].get("double", {}).items():
        prefix = render._prefix(entry)
        found = entry["stack"]["functions"][f"{prefix}_analyze_work"]
        frames = ", ".join(f"{name} {render._n(frame)}" for name, frame in found["path"] if frame)
        paths.append(f"- `{prefix}_analyze_work` {render._n(found['bytes'])} B: {frames}")
    return [
        "## The libraries with n coordinates",
        "",
        "Their analysis (every equilibrium in the box of the coordinates' ranges, each "
        "proven, with its modes; the runtime's `codegen_multibody`) runs in the caller's "
        "working memory (`NAME_analyze_work`, a static `NAME_workspace` here: the isolation's "
        "boxes and working memory), or keeps one on its stack (`NAME_analyze`). The firmware "
        "measures `NAME_analyze_work` on the example's parameters, then `NAME_modes`, "
        "`NAME_receptance` and `NAME_box_enclosure` at the example's first stable "
        "equilibrium.",
        "",
        *render._table(["mechanism", "build", "analyze_work: stack, worst case [B]",
                        "analyze (its own workspace) [B]", "target [B]",
                        "stack target", "measured high-water [B]", "analyze [instructions]",
                        "instructions target (double < 3 M, float < 500 k)",
                        "largest other public function [B]"], targets),
        *render._table(["mechanism", "build",
                        *(f"{call}: instructions / measured / worst-case stack [B]"
                          for call in MULTIBODY_CALLS)], calls),
        "Code size per group [B of flash]:",
        "",
        *render.size_table(report),
        "Where the double build's stack goes (the deepest chain, frames in bytes):",
        "",
        *paths,
        "",
        "The firmware against the host:",
        "",
        *render.comparison_table(report),
    ]


def full_markdown(report: dict) -> str:
    """render.py's report of the one-coordinate libraries, then the section of those with n."""
    multibody = multibody_markdown(_only(report, True))
    text = markdown(_only(report, False))
    return text + ("\n" + "\n".join(multibody) if multibody else "")


def _same_objects(a: Path, b: Path) -> bool:
    """Whether CODEGEN_FLOAT changed no object: the float build is the double code."""
    objects = sorted(p.relative_to(a) for p in a.rglob("*.o") if "firmware" not in p.parts)
    return bool(objects) and all((b / o).is_file() and (a / o).read_bytes() == (b / o).read_bytes()
                                 for o in objects)


def main() -> int:
    out, stem = Path(sys.argv[1]), Path(sys.argv[2])
    report = collect(out, sys.argv[3])
    stem.with_suffix(".json").write_text(json.dumps(report, indent=1, sort_keys=True) + "\n")
    text = full_markdown(report)
    stem.with_suffix(".md").write_text(text)
    print(text)
    failures = [f"{build}/{lib}" for build, libs in report["builds"].items()
                for lib, entry in libs.items()
                if entry["verdict"] == "DIFFERS"]
    if failures:
        print(f"report.py: the firmware's output differs from the host's: {', '.join(failures)}",
              file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
