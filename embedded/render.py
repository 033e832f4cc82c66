"""embedded/report.md from the report report.py collects (the same data as report.json)."""
from __future__ import annotations

STACK_TARGET = {"double": 4096, "float": 2048}   # the issue's, for the whole analysis
#: The entries the targets are for: the analysis in the caller's working memory (which the
#: issue allows); the firmware measures these.
ROUTES = ("analyze_work", "isolate_work")
#: Instructions of the default analysis of the example (issue 29 sets them for Table 2, the
#: paper's mechanism; every library is held to them here).
INSTRUCTIONS_TARGET = {"double": 3_000_000, "float": 500_000}


def _n(value) -> str:
    return "-" if value is None else f"{value:,}".replace(",", " ")


def _table(header: list[str], rows: list[list]) -> list[str]:
    return (["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            + ["| " + " | ".join(map(str, row)) + " |" for row in rows] + [""])


def _entries(report: dict):
    for build, libs in report["builds"].items():
        for lib, entry in libs.items():
            yield lib, build, entry


def _analysis_stack(entry: dict) -> tuple[int, bool, str]:
    """The worst of the two routes: bytes, bounded, which route."""
    routes = {route: entry["stack"]["functions"].get(f"{prefix}_{route}")
              for prefix in [_prefix(entry)] for route in ROUTES}
    route, worst = max(((r, w) for r, w in routes.items() if w), key=lambda rw: rw[1]["bytes"])
    return worst["bytes"], worst["bounded"], route


def _prefix(entry: dict) -> str:
    return next(name for name in entry["stack"]["functions"]
                if name.endswith("_analyze")).removesuffix("_analyze")


def _stack_cell(entry: dict, function: str) -> str:
    found = entry["stack"]["functions"].get(function)
    if not found:
        return "-"
    return _n(found["bytes"]) + ("" if found["bounded"] else " + recursion")


def targets(report: dict) -> list[str]:
    rows = []
    for lib, build, entry in _entries(report):
        worst, bounded, route = _analysis_stack(entry)
        limit = STACK_TARGET[build]
        over = f"{worst / limit:.1f}x over" if worst > limit else "met"
        measured = max(entry["measured"].get(r, {}).get("stack", 0) for r in ("analyze", "isolate"))
        instructions = entry["measured"].get("analyze", {}).get("instructions")
        budget = INSTRUCTIONS_TARGET[build]
        goal = ("-" if not instructions else "met" if instructions <= budget
                else f"{instructions / budget:.1f}x over")
        rows.append([f"`{lib}`", build, f"{_n(worst)}{'' if bounded else ' + recursion'} "
                     f"({route})", _n(limit), over, _n(measured), _n(instructions), goal])
    return _table(["mechanism", "build", "analysis stack in the caller's working memory, worst case [B]", "target [B]",
                   "stack target", "measured high-water [B]", "analyze [instructions]",
                   "instructions target (double < 3 M, float < 500 k)"], rows)


def size_table(report: dict) -> list[str]:
    groups = sorted({g for _, _, e in _entries(report) for g in e["size"]})
    rows = []
    for lib, build, entry in _entries(report):
        size = entry["size"]
        cells = [_n(size[g]["text"] + size[g]["data"]) if g in size else "-" for g in groups]
        flash = sum(s["text"] + s["data"] for s in size.values())
        ram = sum(s["data"] + s["bss"] for s in size.values())
        rows.append([f"`{lib}`", build, *cells, _n(flash), _n(ram)])
    return _table(["mechanism", "build", *groups, "flash [B]", "static RAM [B]"], rows)


def stack_table(report: dict) -> list[str]:
    rows = []
    for lib, build, entry in _entries(report):
        prefix = _prefix(entry)
        others = {n: f for n, f in entry["stack"]["functions"].items()
                  if not n.endswith(("_analyze", "_isolate", "_work", "_batch"))}
        largest = max(others, key=lambda n: others[n]["bytes"])
        rows.append([f"`{lib}`", build, _stack_cell(entry, f"{prefix}_analyze_work"),
                     _n(entry["measured"].get("analyze", {}).get("stack")),
                     _stack_cell(entry, f"{prefix}_isolate_work"),
                     _n(entry["measured"].get("isolate", {}).get("stack")),
                     _stack_cell(entry, f"{prefix}_analyze"), _stack_cell(entry, f"{prefix}_isolate"),
                     f"`{largest.removeprefix(prefix + '_')}` {_n(others[largest]['bytes'])}"])
    return _table(["mechanism", "build", "analyze_work: worst case [B]", "measured [B]",
                   "isolate_work: worst case [B]", "measured [B]",
                   "analyze (its own workspace) [B]", "isolate (its own workspace) [B]",
                   "largest other public function [B]"], rows)


def deepest_paths(report: dict) -> list[str]:
    lines = []
    for lib, entry in report["builds"].get("double", {}).items():
        prefix = _prefix(entry)
        for route in ROUTES:
            found = entry["stack"]["functions"].get(f"{prefix}_{route}")
            if found:
                frames = ", ".join(f"{name} {_n(frame)}" for name, frame in found["path"]
                                   if frame)
                lines.append(f"- `{prefix}_{route}` {_n(found['bytes'])} B: {frames}")
        for cycle in entry["stack"]["recursion"]:
            lines.append(f"- recursion in `{lib}`: {' -> '.join(cycle['functions'])} -> "
                         f"{cycle['functions'][0]} ({_n(cycle['bytes_per_level'])} B a level; "
                         "counted once above)")
    return lines + [""]


def instruction_table(report: dict) -> list[str]:
    rows = [[f"`{lib}`", build, *(_n(entry["measured"].get(r, {}).get("instructions"))
                                   for r in ("analyze", "isolate"))]
            for lib, build, entry in _entries(report)]
    return _table(["mechanism", "build", "analyze [instructions]", "isolate [instructions]"],
                  rows)


def comparison_table(report: dict) -> list[str]:
    rows = []
    for lib, build, entry in _entries(report):
        same = entry["comparison"]
        rows.append([f"`{lib}`", build, entry["verdict"],
                     f"{same.get('differing_lines', 0)} of {same['lines']}",
                     _n(same.get("max_ulps_theta")),
                     {True: "yes", False: "no", None: "-"}[entry["measured"]["fma_rounds_once"]],
                     "yes" if entry["stack"]["calls_fma"] else "no"])
    return _table(["mechanism", "build", "firmware vs host", "lines differing",
                   "largest difference in a root's angle [ulp of its real]", "libm fma rounds once",
                   "library calls fma"],
                  rows)


def _calibrations(report: dict) -> str:
    counts = sorted({e["measured"]["calibration"] for _, _, e in _entries(report)},
                    key=lambda c: (c is None, c))
    return " or ".join(_n(c) for c in counts)


def markdown(report: dict) -> str:
    tools = report["tools"]
    float_note = ("**The float build is the double code for now**: no source selects on "
                  "`CODEGEN_FLOAT` yet, so its objects are byte for byte the double build's."
                  if report["float_is_double"] else
                  "The float build compiles the same sources with `-DCODEGEN_FLOAT`.")
    return "\n".join([
        "# The libraries on a Cortex-M4F",
        "",
        "Written by `make embedded` (`embedded/report.py`; the numbers of its last run). Every "
        "library of `generated/` is cross-compiled by arm-none-eabi-gcc "
        f"{tools['gcc']} (`{tools['cflags']}`) with the test firmware of `embedded/` (its own "
        "start-up and linker script, newlib's semihosting for output) and run under "
        f"`qemu-system-arm -M mps2-an386` (QEMU {tools['qemu']}, `-icount shift=6`: every "
        "instruction advances virtual time by 64 ns, read from the board's 25 MHz timer, so the "
        "counts are exact: a loop of 2001 instructions is counted as "
        f"{_calibrations(report)}). The firmware's main, written per library from its API spec by "
        "`tests/support/c/make_driver.py --firmware`, runs both routes on the library's example "
        "parameters (the paper's Table 2 for its mechanism) and prints every result's bits; the same main built "
        "for the host (`gcc -O0 -ffp-contract=off`) is the reference. " + float_note,
        "",
        "- *Worst-case stack*: gcc's `-fstack-usage` frames along its `-fcallgraph-info=su` "
        "call graph, walked by `embedded/stack.py`; the C library's and libgcc's functions "
        "(libm, soft double) from the firmware's disassembly; an indirect call may reach any "
        "function whose address the code the entry runs takes (the isolation's `enclose`, not "
        "the time response's right-hand side: no function pointer enters through the API), or "
        "a static table holds. From the caller's stack pointer, the result "
        "structure (the caller's memory) not included.",
        "- *Measured high-water*: the stack painted before the call and searched after it.",
        "- *Size*: `arm-none-eabi-size` of each object (text + data: flash); a program links "
        "only the objects it uses.",
        "",
        "## The issue's targets",
        "",
        *targets(report),
        "## Code size per group [B of flash]",
        "",
        *size_table(report),
        "## Stack per public function",
        "",
        *stack_table(report),
        "Where the double build's stack goes (the deepest chain, frames in bytes):",
        "",
        *deepest_paths(report),
        "## Instructions of the example's analysis",
        "",
        *instruction_table(report),
        "## The firmware against the host",
        "",
        *comparison_table(report),
    ])
