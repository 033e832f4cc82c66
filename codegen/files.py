"""Files written whole or not at all.

Every file the tool writes is first written to a temporary file unique to the process and
the call, in the target's folder (so that the final rename is atomic), and replaces the target
only once complete. An exception (KeyboardInterrupt included) removes the temporary file and
leaves the old target as it was; so does SIGTERM or SIGHUP in the command line, which turns
them into SystemExit (``exit_on_signals``). A temporary file left by a process that no longer
exists (killed with SIGKILL) is removed the next time the same target is written.
"""
from __future__ import annotations

import os
import secrets
import signal
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

#: The temporary files' names: .NAME.PID.TOKEN.SUFFIX beside NAME.
_MARK = ".part"


def temporary(path: Path, suffix: str = _MARK) -> Path:
    """A new name beside ``path`` that no other process or call uses."""
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}{suffix}")


def remove_orphans(path: Path) -> None:
    """Remove the temporary files of ``path`` whose process has ended."""
    if not path.parent.is_dir():
        return
    for candidate in path.parent.glob(f".{path.name}.*.*"):
        pid = candidate.name[len(path.name) + 2:].split(".", 1)[0]
        if pid.isdigit() and not _alive(int(pid)):
            candidate.unlink(missing_ok=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
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
