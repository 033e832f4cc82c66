"""The C runtime's codes as its headers declare them, read from the headers: never typed again.

runtime/'s headers are the one declaration of every code the runtime hands out (a root's
kind, an equilibrium's stability and damping, what an undecided interval is, ...): they must
compile without the generator. Everything else takes the codes from them:
- the generator writes each library's cffi declarations of the enums (``declaration``) and
  the header's ``NAME_STABLE``-style aliases from the enums' members (``Enum.names``);
- the Python side names the codes in words (``words``, ``named``) with the values read here.

Only what C99 headers of this runtime write is read: ``typedef enum NAME { A = 0, B, ... }
NAME;`` blocks (a member without a value is the one before it plus one) and ``#define NAME
INTEGER`` lines (``-1``, ``(-11)``); comments are dropped first. Standard library only.
"""
from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from pathlib import Path

from . import resources

_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_ENUM = re.compile(r"typedef\s+enum\s+(\w+)\s*\{([^}]*)\}\s*(\w+)\s*;")
_MEMBER = re.compile(r"(\w+)(?:\s*=\s*\(?\s*(-?\d+)\s*\)?)?")
_DEFINE = re.compile(r"^[ \t]*#[ \t]*define[ \t]+(\w+)[ \t]+"
                     r"\(?[ \t]*(-?\d+)[uUlL]*[ \t]*\)?[ \t]*$", re.M)
#: The prefix of every name of the runtime.
PREFIX = "CODEGEN_"


@dataclass(frozen=True)
class Enum:
    """One ``typedef enum``: its name and its members (name, value) in declaration order."""

    name: str
    members: tuple[tuple[str, int], ...]

    @property
    def names(self) -> tuple[str, ...]:
        """The members' names without the runtime's prefix (``STABLE`` for
        ``CODEGEN_STABLE``), in declaration order."""
        return tuple(n[len(PREFIX):] if n.startswith(PREFIX) else n for n, _ in self.members)


def parse(text: str) -> tuple[dict[str, Enum], dict[str, int]]:
    """The enums (by name) and the integer constants (every enum member and every integer
    ``#define``, by name) of a header's text."""
    code = _COMMENT.sub(" ", text)
    enums: dict[str, Enum] = {}
    for match in _ENUM.finditer(code):
        tag, body, name = match.groups()
        if tag != name:
            raise ValueError(f"typedef enum {tag} {{...}} {name}: the tag and the name differ")
        members, value = [], -1
        for item in filter(None, (part.strip() for part in body.split(","))):
            member = _MEMBER.fullmatch(item)
            if member is None:
                raise ValueError(f"enum {name}: cannot read the member {item!r}")
            value = int(member.group(2)) if member.group(2) is not None else value + 1
            members.append((member.group(1), value))
        enums[name] = Enum(name, tuple(members))
    constants = {n: v for enum in enums.values() for n, v in enum.members}
    for name, value in _DEFINE.findall(code):
        constants[name] = int(value)
    return enums, constants


@functools.lru_cache(maxsize=None)
def _read(folder: Path) -> tuple[dict[str, Enum], dict[str, int]]:
    enums: dict[str, Enum] = {}
    constants: dict[str, int] = {}
    for header in sorted(folder.glob("*.h")):
        found, values = parse(header.read_text())
        for name, value in values.items():
            if constants.setdefault(name, value) != value:
                raise ValueError(f"{header.name}: {name} = {value}, "
                                 f"another header of {folder} says {constants[name]}")
        enums.update(found)
    return enums, constants


def enums(folder: Path | None = None) -> dict[str, Enum]:
    """Every enum of the runtime's headers (resources.runtime() unless told), by name."""
    return _read(resources.runtime() if folder is None else folder)[0]


def constants(folder: Path | None = None) -> dict[str, int]:
    """Every integer constant of the runtime's headers: enum members and ``#define``s."""
    return _read(resources.runtime() if folder is None else folder)[1]


def words(enum: str, **renamed: str) -> tuple[str, ...]:
    """The word of each code of an enum whose codes are 0, 1, ..., n - 1, indexed by code:
    a member's name without the prefix, in lower case, spaces for underscores
    (``CODEGEN_MODE_UNDECIDED``: "mode undecided"), unless ``renamed`` gives another (by the
    name without the prefix: ``words("codegen_damping", NOT_OSCILLATORY="none")``)."""
    declared = enums()[enum]
    by_code = dict(zip((v for _, v in declared.members), declared.names))
    if sorted(by_code) != list(range(len(declared.members))):
        raise ValueError(f"{enum}: its codes are not 0 .. {len(declared.members) - 1}")
    unknown = set(renamed) - set(declared.names)
    if unknown:
        raise ValueError(f"{enum} has no member {', '.join(sorted(unknown))}")
    return tuple(renamed.get(by_code[code], by_code[code].lower().replace("_", " "))
                 for code in range(len(by_code)))


def named(words_of: dict[str, str]) -> dict[int, str]:
    """Code -> word, for constants named without the prefix (``{"MB_STABLE": "stable"}``),
    their values read from the headers."""
    values = constants()
    codes = {values[PREFIX + name]: word for name, word in words_of.items()}
    if len(codes) != len(words_of):
        raise ValueError(f"two of {sorted(words_of)} have the same value")
    return codes


def declaration(enum: Enum, width: int = 120, wrap: int = 100) -> str:
    """The enum as a C declaration (for cffi's cdef): on one line where that fits in
    ``width`` columns, else its members indented, as many to a line as fit in ``wrap``."""
    members = [f"{n} = {v}" for n, v in enum.members]
    line = f"typedef enum {enum.name} {{ {', '.join(members)} }} {enum.name};"
    if len(line) <= width:
        return line
    lines, current = [], ""
    for i, member in enumerate(members):
        piece = member + ("," if i < len(members) - 1 else "")
        if current and len(current) + 1 + len(piece) > wrap:
            lines.append(current)
            current = ""
        current = f"{current} {piece}" if current else f"    {piece}"
    lines.append(current)
    return "\n".join([f"typedef enum {enum.name} {{", *lines, f"}} {enum.name};"])


__all__ = ["Enum", "PREFIX", "constants", "declaration", "enums", "named", "parse", "words"]
