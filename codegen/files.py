"""Files written whole or not at all.

Every file the tool writes is first written to a temporary file unique to the process and
the call, in the target's folder (so that the final rename is atomic), and replaces the target
only once complete. An exception (KeyboardInterrupt included) removes the temporary file and
leaves the old target as it was; so does SIGTERM or SIGHUP in the command line, which turns
them into SystemExit (``exit_on_signals``). A temporary file left by a process that no longer
exists (killed with SIGKILL) is removed the next time the same target is written, when its
name has the exact shape of ours and carries this machine's id (the folder may be shared with
another container or host, whose process ids mean nothing here); nothing else is touched.
"""
from __future__ import annotations

import hashlib
import os
import re
import secrets
import signal
import socket
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import cache
from pathlib import Path
from typing import Any

#: The temporary files' names: .NAME.PID.MACHINE.TOKEN.SUFFIX beside NAME (MACHINE: machine_id).
_MARK = ".part"
#: The suffixes the tool's temporary files end in (besides the target's own extension).
_SUFFIXES = (_MARK, ".partial")


@cache
def machine_id() -> str:
    """8 hex digits naming this boot of this host and its process-id namespace: only a
    process of the same can be looked up by the pid in a temporary file's name."""
    facts = [socket.gethostname()]
    try:   # Linux: a reboot or another container (pid namespace) is another machine
        facts.append(Path("/proc/sys/kernel/random/boot_id").read_text().strip())
        facts.append(os.readlink("/proc/self/ns/pid"))
    except OSError:   # elsewhere: the host name alone
        pass
    return hashlib.sha256("\n".join(facts).encode()).hexdigest()[:8]


def temporary(path: Path, suffix: str = _MARK) -> Path:
    """A new name beside ``path`` that no other process or call uses."""
    return path.with_name(f".{path.name}.{os.getpid()}.{machine_id()}."
                          f"{secrets.token_hex(4)}{suffix}")


def _temporary_shape(path: Path) -> re.Pattern[str]:
    """The names ``temporary`` gives beside ``path``: (pid, machine) as groups."""
    suffixes = "|".join(re.escape(s) for s in {*_SUFFIXES, path.suffix} if s)
    return re.compile(rf"\.{re.escape(path.name)}\.([0-9]{{1,10}})\.([0-9a-f]{{8}})\.[0-9a-f]{{8}}"
                      rf"(?:{suffixes})")


def remove_orphans(path: Path) -> None:
    """Remove the temporary files of ``path`` that a process of this machine left and that
    has ended; another machine's, and any file not named by ``temporary``, stay."""
    if not path.parent.is_dir():
        return
    shape = _temporary_shape(path)
    for candidate in path.parent.iterdir():
        match = shape.fullmatch(candidate.name)
        if match and match[2] == machine_id() and not _alive(int(match[1])):
            candidate.unlink(missing_ok=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    except OverflowError:  # no pid of this machine: keep the file
        return True
    return True


@contextmanager
def replacing(path: str | os.PathLike[str], suffix: str = _MARK) -> Iterator[Path]:
    """The temporary path to write; ``path`` is replaced by it when the block ends without
    an exception, and it is removed otherwise. ``suffix`` ends the temporary name (a writer
    that chooses its format by extension needs the target's)."""
    path = Path(path)
    remove_orphans(path)
    scratch = temporary(path, suffix)
    try:
        yield scratch
        os.replace(scratch, path)
    finally:
        scratch.unlink(missing_ok=True)


def write_text(path: str | os.PathLike[str], text: str) -> None:
    """``path``'s text, replaced whole."""
    with replacing(path) as scratch:
        scratch.write_text(text)


def exit_on_signals() -> None:
    """Turn SIGTERM and SIGHUP into SystemExit(128 + signal), so that what is being written
    is cleaned up as after an error (for a command-line process: a library leaves its
    host's signals alone)."""
    for number in (signal.SIGTERM, getattr(signal, "SIGHUP", None)):
        if number is not None and signal.getsignal(number) == signal.SIG_DFL:
            signal.signal(number, _raise_exit)


def _raise_exit(number: int, frame: object) -> None:
    raise SystemExit(128 + number)


@contextmanager
def locked(folder: Path) -> Iterator[None]:
    """Hold the folder's lock (a lock file in it) for the block: concurrent runs that build
    into the same folder take turns instead of mixing their files."""
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / ".mechvib-lock", "a") as lock:
        try:
            import fcntl
        except ImportError:  # not POSIX: no lock to take
            yield
            return
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def write_table(path: str | os.PathLike[str], what: str, as_json: Callable[[], dict],
                as_csv: Callable[[Any], None]) -> Path:
    """A result table written to path by its suffix: .json (``as_json()``, indented) or .csv
    (``as_csv(stream)``), atomically; ValueError for another suffix (``what`` names the
    result in the message). The path."""
    import json

    path = Path(path)
    if path.suffix.lower() not in (".csv", ".json"):
        raise ValueError(f"{path}: {what} is written as .csv or .json")
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".json":
        write_text(path, json.dumps(as_json(), indent=1) + "\n")
        return path
    with replacing(path) as scratch, scratch.open("w", newline="") as stream:
        as_csv(stream)
    return path
