"""The generated C library: up to date, reproducible, strict-clean, linkable."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from codegen import generate

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
STRICT = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Wconversion", "-Wshadow",
          "-Werror"]


def test_committed_files_are_what_the_generator_emits():
    diff = generate.stale(GENERATED)
    assert not diff, f"generated/ is stale; run `make generate` and commit:\n{diff[:4000]}"


def _generate_with_seed(seed: str, out: Path) -> dict[str, bytes]:
    env = {**os.environ, "PYTHONHASHSEED": seed}
    subprocess.run([sys.executable, "-m", "codegen", "generate", "--out", str(out)],
                   check=True, env=env, cwd=ROOT, capture_output=True)
    return {p.name: p.read_bytes() for p in sorted(out.iterdir())}


def _committed() -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(GENERATED.iterdir())
            if p.suffix not in generate.BUILD_BYPRODUCTS}


def test_generation_is_byte_identical_across_hash_seeds(tmp_path):
    first = _generate_with_seed("1", tmp_path / "a")
    second = _generate_with_seed("4242", tmp_path / "b")
    assert first == second
    assert first == _committed()


def test_generated_files_name_their_origin_and_no_timestamp():
    for path in GENERATED.glob("doughty*.[ch]"):
        original = ROOT / "templates" / "c" / path.name
        if original.exists():  # hand-written sources are copied unchanged
            assert path.read_bytes() == original.read_bytes()
            continue
        head = path.read_text()[:600]
        assert "do not modify by hand" in head and "codegen" in head, path.name
    for name, data in _committed().items():
        text = data.decode()
        assert "2026" not in text and "UTC" not in text, f"{name} carries a date"


@pytest.mark.parametrize("source", sorted(p.name for p in GENERATED.glob("*.c")))
def test_c_compiles_under_strict_flags(source, tmp_path):
    cc = os.environ.get("CC", "gcc")
    result = subprocess.run([cc, *STRICT, "-I", str(GENERATED), "-c", str(GENERATED / source),
                             "-o", str(tmp_path / "x.o")], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_library_links_with_libm_only_and_has_no_mutable_globals(tmp_path):
    objects = []
    for source in sorted(GENERATED.glob("*.c")):
        obj = tmp_path / (source.stem + ".o")
        subprocess.run(["gcc", *STRICT, "-I", str(GENERATED), "-c", str(source), "-o", str(obj)],
                       check=True)
        objects.append(str(obj))
    symbols = subprocess.run(["nm", "-P", *objects], capture_output=True, text=True,
                             check=True).stdout
    undefined = {line.split()[0] for line in symbols.splitlines()
                 if len(line.split()) > 1 and line.split()[1] == "U"}
    defined_here = {line.split()[0] for line in symbols.splitlines()
                    if len(line.split()) > 1 and line.split()[1] == "T"}
    libc_libm = {"sqrt", "sin", "cos", "atan2", "atan", "fabs", "fma", "ldexp", "frexp", "pow",
                 "memset", "copysign", "memcpy", "memmove", "fmin", "fmax", "sincos", "__isnan",
                 "__isinf"}
    assert undefined - defined_here <= libc_libm, undefined - defined_here - libc_libm
    writable = [line for line in symbols.splitlines()
                if len(line.split()) > 1 and line.split()[1] in {"D", "d", "B", "b", "C"}]
    assert not writable, f"mutable global state: {writable}"
    assert "malloc" not in symbols and "printf" not in symbols and "FILE" not in symbols


def test_readme_example_compiles_and_runs(tmp_path):
    exe = tmp_path / "minimal"
    subprocess.run(["gcc", *STRICT, "-I", str(GENERATED), str(ROOT / "examples" / "minimal.c"),
                    *map(str, sorted(GENERATED.glob("*.c"))), "-lm", "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    assert out.count("theta_E") == 10 and out.count("genuine") == 6


@pytest.mark.skipif(shutil.which("g++") is None, reason="no C++ compiler")
def test_header_is_usable_from_cpp(tmp_path):
    src = tmp_path / "use.cpp"
    src.write_text('#include "doughty.h"\nint main() { return DOUGHTY_OK; }\n')
    subprocess.run(["g++", "-Wall", "-Werror", "-I", str(GENERATED), "-c", str(src), "-o",
                    str(tmp_path / "use.o")], check=True)


def test_pinned_sympy_is_the_one_installed():
    import sympy

    assert sympy.__version__ == generate.TESTED_SYMPY
    assert f"sympy=={generate.TESTED_SYMPY}" in (ROOT / "pyproject.toml").read_text()
