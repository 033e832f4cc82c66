"""A user's model file as a loaded Library, built once and reused.

The library of a model file is generated and built into a folder, and a stamp written last
records what it was built from: a hash of the model file's bytes, of the user's modules it
imports (each file's path and bytes; not Python's, installed packages' or this package's) and
of the package (generate.fingerprint: its sources, templates and the SymPy, Jinja2 and Python
versions).
While all are unchanged the folder is loaded as it is. Without a folder of the caller's the
build goes to the per-user cache, ``$XDG_CACHE_HOME/mechvib/`` (else ``~/.cache/mechvib/``),
one entry per stamp, built in a temporary folder beside it and renamed into place: another
run sees a complete entry or none. The compiled library's size and hash, recorded beside the
stamp when it is built, are checked before each load: a library truncated or damaged since
is built again, not loaded.
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from . import files
from .runtime.api import load_from
from .runtime.library import Library

STAMP = ".mechvib-build"
#: The compiled library's file name, size and SHA-256, written when it is built.
LIBRARY_RECORD = ".mechvib-library"


def cache_root() -> Path:
    """The per-user folder that holds the builds of model files."""
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "mechvib"


def _stamp(folder: Path) -> str | None:
    try:
        return (folder / STAMP).read_text()
    except OSError:
        return None


def _current(folder: Path, key: str | None) -> bool:
    """Whether ``folder`` holds an intact build of ``key`` (never for no key: a shipped
    mechanism named through --model is always built)."""
    return key is not None and _stamp(folder) == key and _intact(folder)


def _record_library(folder: Path, built: Path) -> None:
    """Record the compiled library's name, size and hash, to be checked before each load."""
    data = built.read_bytes()
    record = {"file": built.name, "size": len(data), "sha256": hashlib.sha256(data).hexdigest()}
    files.write_text(folder / LIBRARY_RECORD, json.dumps(record))


def _intact(folder: Path) -> bool:
    """Whether the compiled library is still what was built (a truncated or overwritten file
    would fail to load, or load wrong, on every later run)."""
    try:
        record = json.loads((folder / LIBRARY_RECORD).read_text())
        built = folder / Path(record["file"]).name
        if built.stat().st_size != record["size"]:
            return False
        return hashlib.sha256(built.read_bytes()).hexdigest() == record["sha256"]
    except (OSError, ValueError, KeyError, TypeError):
        return False


def library(model: str | os.PathLike[str], out: str | os.PathLike[str] | None = None,
            progress: Callable[[str], None] = lambda stage: None,
            rebuild: bool = False) -> Library:
    """The Library of a model file, built into ``out`` (default: the per-user cache) unless
    that folder already holds this model's build (``rebuild``: build it anyway). ``progress``
    is told each stage (deriving: STEP, emitting C, building)."""
    from .compiler import generate
    from .compiler.model import load_with_sources

    # checked: a ModelError names the problem before any build
    mechanism, sources = load_with_sources(str(model))
    key = _key(generate, Path(model), sources, mechanism.name)
    folder = Path(out) if out is not None else cache_root() / (key or mechanism.name)
    if rebuild or not _current(folder, key):
        # derived and checked against the model before anything is written
        plan = generate.verified_plan(mechanism, progress)
        if out is None:
            _build_beside(generate, mechanism, plan, folder, key, progress)
        else:
            with files.locked(folder):  # another run building here waits its turn
                if rebuild or not _current(folder, key):
                    _build_in_place(generate, mechanism, plan, folder, key, progress)
    return load_from(folder, mechanism.name)


def _key(generate, model: Path, sources: tuple[Path, ...], name: str) -> str | None:
    """What a build is made from: the model file's bytes, each module it imports of the
    user's (path and bytes: a changed helper is a changed model) and the package's
    fingerprint (None for a shipped mechanism named through --model: there is no file)."""
    if not model.is_file():
        return None
    digest = hashlib.sha256(model.read_bytes() + b"\0" + generate.fingerprint(name).encode())
    for source in sources:
        digest.update(b"\0" + str(source).encode() + b"\0" + source.read_bytes())
    return digest.hexdigest()[:32]


def _build_in_place(generate, mechanism, plan, folder: Path, key: str | None, progress
                    ) -> None:
    """Build into the caller's folder; the stamp goes first and comes back last, so a build
    interrupted half way is never taken for a finished one."""
    (folder / STAMP).unlink(missing_ok=True)
    _build(generate, mechanism, plan, folder, progress)
    if key:
        files.write_text(folder / STAMP, key)


def _build_beside(generate, mechanism, plan, folder: Path, key: str | None, progress
                  ) -> None:
    """Build in a temporary folder beside ``folder`` and rename it into place: another run
    sees the finished entry or none."""
    folder.parent.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=".building-", dir=folder.parent))
    try:
        _build(generate, mechanism, plan, work, progress)
        if key:
            (work / STAMP).write_text(key)
        _replace(work, folder)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _build(generate, mechanism, plan, folder: Path, progress: Callable[[str], None]) -> None:
    """Write the library of a verified plan, build it, and check the compiled library
    against the plan it came from."""
    from .compiler.build import build_into
    from .compiler.derivation import derive
    from .compiler.derivation.multibody import derive_multibody
    from .compiler.verification import verify_compiled
    from .compiler.verification_multibody import verify_compiled_multibody

    generate.write_folder(folder / generate.RUNTIME, generate.runtime())
    generate.write_folder(folder / mechanism.name, generate.files_of(plan))
    progress("building")
    _record_library(folder, build_into(folder, mechanism.name))
    progress("checking the compiled library")
    if mechanism.dof > 1:
        verify_compiled_multibody(derive_multibody(mechanism), load_from(folder, mechanism.name))
    else:
        verify_compiled(derive(mechanism).mechanism, plan,
                        load_from(folder, mechanism.name).rows, mechanism)


def _replace(work: Path, folder: Path) -> None:
    """Rename the finished build into place; where another run put one there first, or an
    old build of the same name (no stamp: a shipped name) is in the way, that one goes."""
    try:
        os.rename(work, folder)
    except OSError:
        key = _stamp(work)
        if key is not None and _current(folder, key):
            return  # another run built the same entry meanwhile: keep theirs
        shutil.rmtree(folder, ignore_errors=True)
        os.rename(work, folder)
