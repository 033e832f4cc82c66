"""Worst-case stack of each function of a cross-compiled library, from its call graph.

The library's own functions come from gcc's -fcallgraph-info=su files (NAME.ci: a node per
function with its frame from -fstack-usage, an edge per call); the C library's and libgcc's
(sin, fma, __aeabi_dmul, ...: compiled without those flags) from the linked firmware's
disassembly, each frame the sum of its prologue's pushes and stack adjustments.
worst(f) = frame(f) + the largest worst(callee); a cycle (recursion) or a dynamic frame makes
it unbounded, and the report says so.

An indirect call made while an entry runs may reach a function whose address is taken by code
that entry runs, or held in static data: with no function pointer among its arguments or in
the memory they point to (the generated headers declare none), a pointer the call goes through
can come from nowhere else. The functions an entry runs are found to a fixed point: its direct
callees, and, where one of them calls indirectly, the functions so reachable. Of those, a call
through a pointer named X (read at the call's source position: `model->X(...)`, `s->X(...)`,
`X(...)`) reaches the ones named X where there are any: the runtime names each callback and
each codegen_model field after the function a library gives it (`.enclosure = enclosure`);
where none is named X, it may reach any of them.
"""
from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

INDIRECT = "__indirect_call"
STATIC_DATA = ""   # a taker that is no function: an initialised table, reachable from anywhere
_NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
_EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
_INDIRECT_EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "__indirect_call" '
                            r'label: "([^"]+):(\d+):(\d+)"')
_CALLEE = re.compile(r"^(?:[A-Za-z_]\w*\s*(?:->|\.)\s*)*([A-Za-z_]\w*)\s*\(")
_FRAME = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)")
_CALLS = {"R_ARM_THM_CALL", "R_ARM_THM_JUMP24", "R_ARM_THM_JUMP19", "R_ARM_CALL",
          "R_ARM_JUMP24", "R_ARM_THM_JUMP11", "R_ARM_THM_JUMP8"}


def tool(*command: str) -> str:
    """What a command prints (it must succeed)."""
    return subprocess.run(command, check=True, capture_output=True, text=True).stdout


@dataclass
class Graph:
    frames: dict[str, int] = field(default_factory=dict)      # function -> its frame [B]
    dynamic: set[str] = field(default_factory=set)            # frames of unbounded size
    calls: dict[str, set[str]] = field(default_factory=dict)  # function -> callees
    # function -> the functions whose code takes its address (STATIC_DATA: a table holds it)
    taken_by: dict[str, set[str]] = field(default_factory=dict)

    def add_call(self, caller: str, callee: str) -> None:
        self.calls.setdefault(caller, set()).add(callee)


@dataclass(frozen=True)
class Worst:
    bytes: int
    path: tuple[tuple[str, int], ...]   # the deepest chain: (function, its frame)
    bounded: bool                        # no recursion, no dynamic frame on the way


def short(name: str) -> str:
    """A function's name without the file gcc puts before a static one."""
    return name.rsplit(":", 1)[-1]


def read_callgraphs(objects: list[Path], graph: Graph) -> None:
    """The .ci beside each object, and which functions each object takes the address of."""
    for obj in objects:
        text = obj.with_suffix(".ci").read_text()
        source = re.search(r'graph: \{ title: "([^"]+)"', text).group(1)
        for title, label in _NODE.findall(text):
            frame = _FRAME.search(label)
            if frame:
                graph.frames[title] = int(frame.group(1))
                if frame.group(2).startswith("dynamic") and "bounded" not in frame.group(2):
                    graph.dynamic.add(title)
        for edge in text.splitlines():
            call = _EDGE.search(edge)
            if call is None:
                continue
            caller, callee = call.groups()
            site = _INDIRECT_EDGE.search(edge) if callee == INDIRECT else None
            graph.add_call(caller, indirect_call(_pointer_name(Path(site[2]), int(site[3]),
                                                               int(site[4])))
                           if site else callee)
        for target, takers in _address_taken(obj, source, set(graph.frames)).items():
            graph.taken_by.setdefault(target, set()).update(takers)


def indirect_call(pointer: str | None) -> str:
    """The call graph's name of an indirect call through a pointer so named (None: unknown)."""
    return f"{INDIRECT}:{pointer}" if pointer else INDIRECT


def _pointer_name(source: Path, line: int, column: int) -> str | None:
    """The name of the pointer an indirect call at source:line:column goes through."""
    try:
        text = source.read_text().splitlines()[line - 1][column - 1:]
    except (OSError, IndexError):
        return None
    match = _CALLEE.match(text)
    return match.group(1) if match else None


def _address_taken(obj: Path, source: str, known: set[str]) -> dict[str, set[str]]:
    """Functions of obj referred to other than by a call (the targets of indirect calls), each
    with the functions that refer to it: -ffunction-sections gives each function its section,
    .text.NAME, whose relocations `objdump -r` lists under its name; any other section is data.
    gcc names a static function in the .ci by its file and name; a global one by its name."""
    def ours(symbol: str) -> list[str]:
        return [name for name in (f"{source}:{symbol}", symbol) if name in known]

    taken: dict[str, set[str]] = {}
    taker = STATIC_DATA
    for line in tool("arm-none-eabi-objdump", "-r", str(obj)).splitlines():
        section = re.match(r"RELOCATION RECORDS FOR \[\.text\.([^\]]+)\]|RELOCATION RECORDS", line)
        if section:   # a function's code, or data (.rodata, .data, ...)
            taker = next(iter(ours(section.group(1))), STATIC_DATA) if section.group(1) else STATIC_DATA
            continue
        parts = line.split()
        if len(parts) == 3 and parts[1].startswith("R_ARM") and parts[1] not in _CALLS:
            for name in ours(parts[2].removeprefix(".text.")):
                taken.setdefault(name, set()).add(taker)
    return taken


_REGISTERS = re.compile(r"\{([^}]*)\}")
_BRANCH = re.compile(r"bl?(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?(\.w|\.n)?$")


def _registers(operands: str) -> int:
    """How many registers a push/vpush list names ({r4, r5, lr}, {d8-d15})."""
    count = 0
    for item in _REGISTERS.search(operands).group(1).split(","):
        ends = re.findall(r"\d+", item)
        count += int(ends[1]) - int(ends[0]) + 1 if "-" in item else 1
    return count


def read_binary(elf: Path, graph: Graph) -> None:
    """Frames and calls of the functions the call graphs only name (libm, libgcc, libc),
    from the linked firmware's disassembly; a function's other names (__aeabi_dadd for
    __adddf3) share them."""
    read_disassembly(tool("arm-none-eabi-objdump", "-d", "--no-show-raw-insn", str(elf)),
                      graph)
    by_address: dict[int, list[str]] = {}
    absolute: set[str] = set()
    for line in tool("arm-none-eabi-nm", str(elf)).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TtWw":
            address, _, name = parts
            by_address.setdefault(int(address, 16) & ~1, []).append(name)
        elif len(parts) == 3 and parts[1] in "Aa":
            absolute.add(parts[2])
    # objdump names a branch target after the nearest symbol, and an absolute one (the linker
    # script's STACK_SIZE = 0x40000) may be nearest to code at that address: not a call
    for callees in graph.calls.values():
        callees -= absolute
    for names in by_address.values():
        labelled = [name for name in names if name in graph.frames]
        for name in names:
            if labelled and name not in graph.frames:
                graph.frames[name] = graph.frames[labelled[0]]
                graph.calls[name] = graph.calls.get(labelled[0], set())


def read_disassembly(listing: str, graph: Graph) -> None:
    function = None
    for line in listing.splitlines():
        start = re.match(r"^[0-9a-f]+ <([^>]+)>:$", line)
        if start:
            function = start.group(1)
            if function in graph.frames:   # ours: the .ci said it already
                function = None
            else:
                graph.frames[function] = 0
            continue
        instruction = re.match(r"^\s+[0-9a-f]+:\s+(\S+)\s*(.*)$", line)
        if function is None or instruction is None:
            continue
        mnemonic, operands = instruction.groups()
        if mnemonic in ("push", "push.w") or (mnemonic == "stmdb" and operands.startswith("sp!")):
            graph.frames[function] += 4 * _registers(operands)
        elif mnemonic == "vpush":
            graph.frames[function] += (8 if "d" in operands else 4) * _registers(operands)
        elif mnemonic in ("sub", "sub.w", "subw") and re.match(r"sp, (sp, )?#\d+", operands):
            graph.frames[function] += int(re.search(r"#(\d+)", operands).group(1))
        elif mnemonic.startswith("blx") and not operands.startswith("0"):
            graph.add_call(function, INDIRECT)
        elif _BRANCH.match(mnemonic):
            target = re.search(r"<([^>+]+)>", operands)
            if target and target.group(1) != function:
                graph.add_call(function, target.group(1))


def _taken_in(graph: Graph, running: set[str]) -> set[str]:
    """The functions whose address the running functions take, or a static table holds."""
    return {target for target, takers in graph.taken_by.items()
            if takers & (running | {STATIC_DATA})}


def runs(graph: Graph, entry: str) -> set[str]:
    """The functions entry may run, and (as INDIRECT's callees) the targets of its indirect
    calls: a fixed point, since a target reached may take further addresses."""
    seen: set[str] = set()
    todo = [entry]
    while todo:
        seen.update(todo)
        todo = [callee for name in todo for callee in graph.calls.get(name, ())
                if callee not in seen]
        if any(name.startswith(INDIRECT) for name in seen):
            todo += sorted(_taken_in(graph, seen) - seen)
    return seen


def indirect_targets(graph: Graph, entry: str) -> set[str]:
    """What an indirect call may reach while entry runs (see the module's docstring)."""
    return _taken_in(graph, runs(graph, entry))


def worst_stack(graph: Graph, entry: str) -> Worst:
    """The deepest chain from entry (depth first, each function once; a call back into a
    function still being explored is recursion: unbounded)."""
    known: dict[str, Worst] = {}
    exploring: set[str] = set()
    targets = indirect_targets(graph, entry)

    def worst(name: str) -> Worst:
        if name in known:
            return known[name]
        exploring.add(name)
        if name.startswith(INDIRECT):
            pointer = name[len(INDIRECT) + 1:]
            reached = {t for t in targets if short(t) == pointer} or targets
            deepest = max((worst(t) for t in sorted(reached)), key=lambda w: w.bytes,
                          default=Worst(0, (), False))
            result = Worst(deepest.bytes, deepest.path, deepest.bounded and bool(reached))
        else:
            frame = graph.frames.get(name)
            bounded = frame is not None and name not in graph.dynamic
            deepest = Worst(0, (), True)
            for callee in sorted(graph.calls.get(name, ())):
                if callee in exploring:
                    bounded = False
                    continue
                below = worst(callee)
                bounded &= below.bounded
                if below.bytes > deepest.bytes:
                    deepest = below
            result = Worst((frame or 0) + deepest.bytes, ((name, frame or 0),) + deepest.path,
                           bounded)
        exploring.discard(name)
        known[name] = result
        return result
    return worst(entry)
