"""Build each generated C library into its own cffi (API mode) extension.

setuptools runs this through ``cffi_modules`` on ``pip install .`` / ``pip install -e .``:
every folder of generated/ holding a library (NAME/NAME_api.json) becomes the module
``codegen._native_NAME``, compiled from its sources and the shared runtime. ``build_into``
does the same for a user's library, into any folder.
setuptools executes this file by path (not as part of the package), from the source tree
(a checkout or an unpacked sdist): it imports nothing of the codegen package, and loads
codegen/resources.py (standard library only) by path for the runtime's name and the compiler
flags. Imported from an installed package it defines no builders (there is no source tree),
and ``build_into`` still works.
The strict warning flags are applied to generated/ by the test suite (cffi's own wrapper
code is not -Wpedantic clean, so it is not held to them here).
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from cffi import FFI

ROOT = Path(__file__).resolve().parents[2]  # codegen/compiler/build.py -> the checkout
GENERATED = ROOT / "generated"
#: True when this file is in a source tree (setup.py beside codegen/), not installed.
SOURCE_TREE = (ROOT / "setup.py").is_file()


def _resources():
    """codegen/resources.py, loaded by path (see the module docstring)."""
    path = Path(__file__).resolve().parents[1] / "resources.py"
    spec = importlib.util.spec_from_file_location("_mechvib_build_resources", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_RESOURCES = _resources()
RUNTIME = _RESOURCES.RUNTIME
#: generate.MANIFEST (this file imports nothing of codegen): the files generate wrote there.
MANIFEST = ".mechvib-manifest"
#: runtime/cflags.txt's, and the enclosures inline: the faster form on a host
#: (codegen_interval.h, interval programs).
COMPILE_FLAGS = [*_RESOURCES.cflags("base", "optimize"), "-DCODEGEN_INLINE_INTERVALS"]


def _c_string(text: str) -> str:
    return json.dumps(text)  # a JSON string literal is a valid C string literal here


def _path(p: Path) -> str:
    """Relative to the checkout when inside it (setuptools wants relative sources)."""
    return str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p)


def libraries(generated: Path = GENERATED) -> list[str]:
    """Names of the mechanism libraries in a generated/ folder."""
    return sorted(p.name for p in generated.iterdir()
                  if (p / f"{p.name}_api.json").is_file()) if generated.is_dir() else []


def _written(folder: Path) -> list[Path]:
    """The C files generate wrote into a folder (its manifest), never a file of the user's
    beside them; every one where there is no manifest (a library copied without it)."""
    try:
        names = json.loads((folder / MANIFEST).read_text())
    except FileNotFoundError:
        return sorted(folder.glob("*.c"))
    return sorted(folder / n for n in names if n.endswith(".c"))


def _every(folder: Path) -> list[Path]:
    """Every C file of a folder: a checkout's generated/ holds only the committed library
    (its manifest is local and may predate a pulled change)."""
    return sorted(folder.glob("*.c"))


def make_builder(name: str, generated: Path = GENERATED, package: str = "codegen.",
                 sources_of: Callable[[Path], list[Path]] = _every) -> FFI:
    folder = generated / name
    spec = (folder / f"{name}_api.json").read_text()
    ffi = FFI()
    ffi.cdef((folder / f"{name}.cdef").read_text())
    ffi.cdef("const char *codegen_api_spec(void);")
    sources = sources_of(folder) + sources_of(generated / RUNTIME)
    # Python.h (included first) asks for POSIX and GNU extensions, under which <math.h>
    # defines names plain C99 leaves free, such as M_PI; a parameter of such a name is a
    # field of NAME_params, so the wrapper undefines it before the header declares the struct.
    fields = "".join(f"#undef {p['name']}\n" for p in json.loads(spec)["parameters"])
    ffi.set_source(
        f"{package}_native_{name}",
        f"#include <math.h>\n{fields}"
        f'#include "{name}.h"\n'
        # The wrapper's own metadata: which functions exist and their array sizes.
        f"static const char *codegen_api_spec(void) {{ return {_c_string(spec)}; }}\n",
        sources=[_path(s) for s in sources],
        include_dirs=[_path(folder), _path(generated / RUNTIME)],
        libraries=["m"],
        extra_compile_args=COMPILE_FLAGS,
    )
    return ffi


def build_into(out: Path, name: str) -> Path:
    """Compile the library generated into out/NAME (with out/runtime) as out/_native_NAME.*,
    from the C files generate wrote there only (each folder's manifest)."""
    out = Path(out).resolve()
    ffi = make_builder(name, out, package="", sources_of=_written)
    work = tempfile.mkdtemp(prefix=".build-", dir=out)  # this build's alone
    try:
        built = ffi.compile(tmpdir=work, verbose=False)
        target = out / Path(built).name
        Path(built).replace(target)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return target


# One builder per shipped library, named for setup.py's cffi_modules ("...:ffi_NAME").
BUILDERS = {name: make_builder(name) for name in libraries()} if SOURCE_TREE else {}
globals().update({f"ffi_{name}": builder for name, builder in BUILDERS.items()})

if __name__ == "__main__":  # an in-place build for development: codegen/_native_*.so
    os.chdir(ROOT)
    try:
        for builder in BUILDERS.values():
            builder.compile(tmpdir=str(ROOT), verbose=False)
    finally:  # distutils leaves objects beside relative sources
        for obj in GENERATED.glob("*/*.o"):
            obj.unlink()
