"""Worst-case stack of each function of a cross-compiled library, from its call graph.

The library's own functions come from gcc's -fcallgraph-info=su files (NAME.ci: a node per
function with its frame from -fstack-usage, an edge per call); the C library's and libgcc's
(sin, fma, __aeabi_dmul, ...: compiled without those flags) from the linked firmware's
disassembly, each frame the sum of its prologue's pushes and stack adjustments. An indirect
call may reach every function whose address the objects take (their relocations other than
calls). worst(f) = frame(f) + the largest worst(callee); a cycle (recursion) or a dynamic
frame makes it unbounded, and the report says so.
"""
from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

INDIRECT = "__indirect_call"
_NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
_EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
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
    address_taken: set[str] = field(default_factory=set)

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
        for caller, callee in _EDGE.findall(text):
            graph.add_call(caller, callee)
        graph.address_taken |= _address_taken(obj, source, set(graph.frames))


def _address_taken(obj: Path, source: str, known: set[str]) -> set[str]:
    """Functions of obj referred to other than by a call: the targets of indirect calls.
    gcc names a static function in the .ci by its file and name; a global one by its name."""
    relocations = tool("arm-none-eabi-objdump", "-r", str(obj))
    taken = set()
    for line in relocations.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1].startswith("R_ARM") and parts[1] not in _CALLS:
            symbol = parts[2].removeprefix(".text.")
            taken |= {name for name in (f"{source}:{symbol}", symbol) if name in known}
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
    for line in tool("arm-none-eabi-nm", str(elf)).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TtWw":
            address, _, name = parts
            by_address.setdefault(int(address, 16) & ~1, []).append(name)
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


def worst_stack(graph: Graph):
    """worst(name) -> Worst, for any function of the graph (depth first, each function once;
    a call back into a function still being explored is recursion: unbounded)."""
    known: dict[str, Worst] = {}
    exploring: set[str] = set()

    def worst(name: str) -> Worst:
        if name in known:
            return known[name]
        exploring.add(name)
        if name == INDIRECT:
            targets = graph.address_taken
            deepest = max((worst(t) for t in sorted(targets)), key=lambda w: w.bytes,
                          default=Worst(0, (), False))
            result = Worst(deepest.bytes, deepest.path, deepest.bounded and bool(targets))
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
    return worst
