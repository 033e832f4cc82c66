# cffi's setuptools hook is only reachable from setup(); everything else is in pyproject.toml.
# One extension per library folder in generated/ (see codegen/build_ext.py).
from pathlib import Path

from setuptools import setup

LIBRARIES = sorted(p.name for p in Path("generated").iterdir()
                   if (p / f"{p.name}_api.json").is_file())
setup(cffi_modules=[f"codegen/build_ext.py:ffi_{name}" for name in LIBRARIES])
