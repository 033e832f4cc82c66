# cffi's setuptools hook and the package data below are only reachable from setup();
# everything else is in pyproject.toml.
# One extension per library folder in generated/ (see codegen/compiler/build.py).
# The wheel (and a non-editable install) also carries, inside the package, the C library of
# every shipped mechanism, the C runtime and the templates, where codegen.resources finds them:
#   generated/NAME/*, generated/runtime/*  ->  codegen/data/generated/...
#   runtime/* (the C runtime, runtime/fmi/, cflags.txt)  ->  codegen/data/runtime/...
#   templates/*.j2, templates/fmi/*.j2  ->  codegen/data/templates/...
# An editable install reads the checkout's own folders instead and copies nothing.
import importlib.util
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py


def _resources():
    """codegen/resources.py, loaded by path (the package is not importable while it builds)."""
    spec = importlib.util.spec_from_file_location("_mechvib_resources", "codegen/resources.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


RUNTIME = _resources().RUNTIME
LIBRARIES = sorted(p.name for p in Path("generated").iterdir()
                   if (p / f"{p.name}_api.json").is_file())
#: What a library folder ships (not the objects a compiler may leave beside the sources).
SHIPPED_SUFFIXES = (".c", ".h", ".cdef", ".json")
#: What a compiler may leave beside the runtime's sources: not shipped.
BUILD_BYPRODUCTS = (".o",)


def data_files() -> list[tuple[Path, Path]]:
    """(source, destination inside the package) for every file of codegen/data/."""
    pairs = []
    for folder in LIBRARIES + [RUNTIME]:
        for src in sorted(Path("generated", folder).iterdir()):
            if src.is_file() and src.suffix in SHIPPED_SUFFIXES:
                pairs.append((src, Path("data", "generated", folder, src.name)))
    for top in ("templates", RUNTIME):
        for src in sorted(Path(top).rglob("*")):
            if src.is_file() and src.suffix not in BUILD_BYPRODUCTS:
                pairs.append((src, Path("data", src)))
    return pairs


class build_py_with_data(build_py):
    """build_py, then the generated libraries, the runtime and the templates into
    codegen/data/."""

    def run(self):
        super().run()
        if not self.editable_mode:
            for src, dst in data_files():
                target = Path(self.build_lib, "codegen", dst)
                self.mkpath(str(target.parent))
                self.copy_file(str(src), str(target))

    def get_outputs(self, include_bytecode=True):
        outputs = super().get_outputs(include_bytecode)
        if self.editable_mode:
            return outputs
        return outputs + [str(Path(self.build_lib, "codegen", dst)) for _, dst in data_files()]


setup(cffi_modules=[f"codegen/compiler/build.py:ffi_{name}" for name in LIBRARIES],
      cmdclass={"build_py": build_py_with_data})
