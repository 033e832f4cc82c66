"""Layer 5: build the generated C library into a cffi (API mode) extension.

setuptools runs this through ``cffi_modules`` on ``pip install .`` / ``pip install -e .``;
``python -m codegen.build_ext`` builds in place. The extension compiles the generated
sources as C99; the strict warning flags are applied to generated/ by the test suite
(cffi's own wrapper code is not -Wpedantic clean, so it is not held to them here).
"""
from __future__ import annotations

import json
import os
from pathlib import Path

from cffi import FFI

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
PREFIX = "doughty"
COMPILE_FLAGS = ["-std=c99", "-O2"]


def _c_string(text: str) -> str:
    return json.dumps(text)  # a JSON string literal is a valid C string literal here


def make_builder(generated: Path = GENERATED) -> FFI:
    spec = (generated / f"{PREFIX}_api.json").read_text()
    ffi = FFI()
    ffi.cdef((generated / f"{PREFIX}.cdef").read_text())
    ffi.cdef("const char *codegen_api_spec(void);")
    sources = sorted(str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p)
                     for p in generated.glob("*.c"))
    ffi.set_source(
        "codegen._native",
        f'#include "{PREFIX}.h"\n'
        # The wrapper's own metadata: which functions exist and their array sizes.
        f"static const char *codegen_api_spec(void) {{ return {_c_string(spec)}; }}\n",
        sources=sources,
        include_dirs=[os.path.relpath(generated, ROOT)],
        libraries=["m"],
        extra_compile_args=COMPILE_FLAGS,
    )
    return ffi


ffibuilder = make_builder()

if __name__ == "__main__":  # an in-place build for development: codegen/_native.*.so
    os.chdir(ROOT)
    try:
        ffibuilder.compile(tmpdir=str(ROOT), verbose=False)
    finally:  # distutils leaves objects beside relative sources
        for obj in GENERATED.glob("*.o"):
            obj.unlink()
