"""Model -> derivation -> plan -> rendered files, written to (or compared with) a folder.

Each mechanism's library goes to its own folder (generated/NAME/); the hand-written C runtime's
sources (runtime/*.c, *.h) are copied once, unchanged, to generated/runtime/, shared by all.
That copy is produced, never edited: it makes generated/ whole, one folder to drop into a
firmware or any C project with nothing else of the repository, and `generate --check` holds
it equal to runtime/ (the runtime itself is edited, compiled and tested in runtime/).

The templates and the runtime are the checkout's templates/ and runtime/, or the copies inside
an installed package (codegen.resources). The default output folder, ``default_output()``, is
the checkout's generated/ in a checkout, else ./generated of the current directory: an
installed package never writes into its own folder.
"""
from __future__ import annotations

import difflib
import hashlib
import json
import sys
import warnings
from collections.abc import Callable
from pathlib import Path

import sympy

from .. import resources
from ..files import write_text
from .derivation import derive
from .derivation.multibody import derive_multibody
from .emission.multibody import MultibodyPlan, build_multibody_plan
from .emission.plan import Plan, build_plan
from .emission.render import render, render_multibody
from .model import SHIPPED, SHIPPED_MULTIBODY, Mechanism, load
from .verification import verify
from .verification_multibody import verify_multibody

#: Every library make generate writes: one coordinate's, then several coordinates'.
EVERY = SHIPPED + SHIPPED_MULTIBODY

TEMPLATES = resources.templates()
RUNTIME = resources.RUNTIME
#: The runtime's files that generated/runtime/ carries: its C sources (not the FMI glue in
#: runtime/fmi/, which FMUs take, nor cflags.txt).
RUNTIME_SOURCES = (".c", ".h")
BUILD_BYPRODUCTS = (".o",)  # objects a compiler may leave beside the sources

#: The SymPy release the committed generated/ was produced and tested with (pyproject pins it);
#: common-subexpression elimination and printing may differ between releases.
TESTED_SYMPY = "1.14.0"


def default_output() -> Path:
    """Where generate writes unless told: the checkout's generated/, or ./generated (the
    current directory's, at the time of the call) when the package is installed."""
    return resources.generated() if resources.in_checkout() else Path.cwd() / "generated"


def default_cache() -> Path | None:
    """Where the command line keeps what it derived (a checkout's build/), None installed."""
    return resources.ROOT / "build" / "generate-cache" if resources.in_checkout() else None


def fingerprint(name: str, templates: Path = TEMPLATES) -> str:
    """A digest of everything a shipped mechanism's files are made from: every source file of
    the package (its model included), the templates, the runtime (whose headers declare the
    codes the cffi declarations repeat), and the SymPy, Jinja2 and Python versions. Equal
    digests give byte-identical files, so a cached result can stand in."""
    import jinja2

    digest = hashlib.sha256(f"{name} {sympy.__version__} {jinja2.__version__} "
                            f"{sys.version_info[:2]}".encode())
    sources = sorted(resources.PACKAGE.rglob("*.py")) + [
        p for folder in (templates, resources.runtime()) for p in sorted(folder.rglob("*"))
        if p.is_file()]
    for path in sources:
        digest.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def _emit_shipped(name: str, templates: Path, cache: Path | None) -> dict[str, str]:
    """emit(load(name)), or its files from the cache when nothing they are made from changed
    and the entry is intact (its checksum holds: a truncated or edited entry is rebuilt)."""
    entry = cache / f"{name}-{fingerprint(name, templates)}.json" if cache else None
    cached = _read_entry(entry) if entry is not None else None
    if cached is not None:
        return cached
    files = emit(load(name), templates)
    if entry is not None:
        entry.parent.mkdir(parents=True, exist_ok=True)
        for old in entry.parent.glob(f"{name}-*.json"):
            old.unlink(missing_ok=True)
        text = json.dumps(files, sort_keys=True)
        write_text(entry, json.dumps({"sha256": _digest(text), "files": text}))
    return files


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def _read_entry(entry: Path) -> dict[str, str] | None:
    """A cache entry's files, or None when it is missing or damaged."""
    try:
        stored = json.loads(entry.read_text())
        if _digest(stored["files"]) == stored["sha256"]:
            return json.loads(stored["files"])
    except (OSError, ValueError, KeyError, TypeError):
        pass
    return None


def _present(out: Path) -> set[str]:
    if not out.is_dir():
        return set()
    return {p.name for p in out.iterdir() if p.is_file() and p.suffix not in BUILD_BYPRODUCTS
            and not p.name.startswith(".")}  # the manifest, a write in progress


def emit(mechanism: Mechanism, templates: Path = TEMPLATES,
         progress: Callable[[str], None] = lambda stage: None) -> dict[str, str]:
    """File name -> text of one mechanism's library, once its expressions have been checked
    against the model (verification.VerificationError, a ValueError, if they disagree);
    ``progress`` is told each stage ("deriving: STEP", "verifying", "emitting C") as it
    starts."""
    return files_of(verified_plan(mechanism, progress), templates)


def files_of(plan: Plan, templates: Path = TEMPLATES) -> dict[str, str]:
    """File name -> text of the library of a (verified) plan."""
    return (render_multibody if isinstance(plan, MultibodyPlan) else render)(plan, templates)


def verified_plan(mechanism: Mechanism, progress: Callable[[str], None] = lambda stage: None
                  ) -> Plan:
    """The emission plan of a mechanism, checked against the model before anything is
    written (see emit)."""
    if sympy.__version__ != TESTED_SYMPY:
        warnings.warn(f"SymPy {sympy.__version__} is not the tested {TESTED_SYMPY}: the "
                      f"generated files may differ from the committed ones", stacklevel=3)
    if mechanism.dof > 1:
        progress("deriving: M, B, G and K in the independent coordinates")
        multibody = derive_multibody(mechanism)
        plan = build_multibody_plan(multibody)
        progress("verifying against the model")
        verify_multibody(multibody, plan)
        progress("emitting C")
        return plan
    derivation = derive(mechanism, lambda step: progress(f"deriving: {step}"))
    plan = build_plan(derivation)
    progress("verifying against the model")
    verify(derivation.mechanism, plan, derivation.user)
    progress("emitting C")
    return plan


def runtime(folder: Path | None = None) -> dict[str, str]:
    """File name -> text of the shared runtime's C sources (of resources.runtime() unless
    told), as generated/runtime/ carries them: a copy, byte for byte."""
    folder = resources.runtime() if folder is None else folder
    return {p.name: p.read_text() for p in sorted(folder.iterdir())
            if p.is_file() and p.suffix in RUNTIME_SOURCES}


def emit_all(names=EVERY, templates: Path = TEMPLATES, cache: Path | None = None
             ) -> dict[str, dict[str, str]]:
    """Folder -> its files, for the runtime and every named (shipped) mechanism; with a cache
    folder, a mechanism is derived again only when its fingerprint changed."""
    folders = {RUNTIME: runtime()}
    for name in names:
        folders[name] = _emit_shipped(name, templates, cache)
    return folders


#: Each folder generate writes lists the files it wrote there, so that a later run removes
#: only its own stale files, never one it did not write.
MANIFEST = ".mechvib-manifest"


def _manifest(out: Path) -> set[str]:
    try:
        return set(json.loads((out / MANIFEST).read_text()))
    except (OSError, ValueError, TypeError):
        return set()


def write_folder(out: Path, files: dict[str, str]) -> list[str]:
    """Write files into out (each atomically), removing those an earlier run wrote there
    that are no longer emitted; the names written (unchanged files are left alone, so their
    times do not trigger rebuilds). A file generate did not write is never removed."""
    out.mkdir(parents=True, exist_ok=True)
    for stale_file in (_manifest(out) & _present(out)) - set(files):
        (out / stale_file).unlink()
    written = []
    for name, text in files.items():
        path = out / name
        if not path.is_file() or path.read_text() != text:
            write_text(path, text)
            written.append(name)
    manifest = json.dumps(sorted(files)) + "\n"
    if not (out / MANIFEST).is_file() or (out / MANIFEST).read_text() != manifest:
        write_text(out / MANIFEST, manifest)
    return sorted(written)


def write(out: Path | None = None, names=EVERY, templates: Path = TEMPLATES,
          cache: Path | None = None) -> list[str]:
    """Write the runtime and every named mechanism into out (default: default_output());
    the files that changed, as FOLDER/NAME."""
    out = default_output() if out is None else Path(out)
    folders = emit_all(names, templates, cache)
    return [f"{folder}/{name}" for folder, files in folders.items()
            for name in write_folder(out / folder, files)]


def stale(out: Path | None = None, names=EVERY, templates: Path = TEMPLATES,
          cache: Path | None = None) -> str:
    """A unified diff of committed files against what the generator emits now ('' if none)."""
    out = default_output() if out is None else Path(out)
    diff = []
    folders = emit_all(names, templates, cache)
    # every mechanism's folder when all are checked (one left over is stale), else the named
    present = {p.name for p in out.iterdir() if p.is_dir()} if out.is_dir() and \
        set(names) == set(EVERY) else set()
    for folder in sorted(set(folders) | present):
        files = folders.get(folder, {})
        here = _present(out / folder)
        for name in sorted(set(files) | here):
            old = (out / folder / name).read_text() if name in here else ""
            new = files.get(name, "")
            diff += difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                         f"committed/{folder}/{name}",
                                         f"generator/{folder}/{name}")
    return "".join(diff)
