"""The generated C library: up to date, reproducible, strict-clean, linkable."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from codegen.compiler import generate
from codegen.resources import cflags

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated"
STRICT = cflags("base", "optimize", "strict")


def test_committed_files_are_what_the_generator_emits():
    diff = generate.stale(GENERATED)
    assert not diff, f"generated/ is stale; run `make generate` and commit:\n{diff[:4000]}"


def _files(folder: Path) -> dict[str, bytes]:
    # (not generate's manifest, .mechvib-manifest: bookkeeping of a folder, not committed)
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.glob("*/*"))
            if p.suffix not in generate.BUILD_BYPRODUCTS and not p.name.startswith(".")}


def _generate_with_seed(seed: str, out: Path) -> dict[str, bytes]:
    env = {**os.environ, "PYTHONHASHSEED": seed}
    subprocess.run([sys.executable, "-m", "codegen", "generate", "--no-cache", "--out", str(out)],
                   check=True, env=env, cwd=ROOT, capture_output=True)
    return _files(out)


LIBRARIES = sorted(p.name for p in GENERATED.iterdir() if (p / f"{p.name}_api.json").is_file())
RUNTIME = GENERATED / generate.RUNTIME


def _sources(name: str) -> list[Path]:
    return sorted((GENERATED / name).glob("*.c"))


def _includes(name: str) -> list[str]:
    return ["-I", str(GENERATED / name), "-I", str(RUNTIME)]


def test_every_shipped_mechanism_has_a_library():
    from codegen.compiler.model import SHIPPED, SHIPPED_MULTIBODY

    assert LIBRARIES == sorted(SHIPPED + SHIPPED_MULTIBODY)


@pytest.mark.slow  # two whole derivations (about a minute): `make test` checks staleness once
def test_generation_is_byte_identical_across_hash_seeds(tmp_path):
    first = _generate_with_seed("1", tmp_path / "a")
    second = _generate_with_seed("4242", tmp_path / "b")
    assert first == second
    assert first == _files(GENERATED)


def test_generated_files_name_their_origin_and_no_timestamp():
    for path in GENERATED.glob("*/*.[ch]"):
        original = ROOT / generate.RUNTIME / path.name
        if path.parent == RUNTIME:  # hand-written sources are copied unchanged
            assert path.read_bytes() == original.read_bytes()
            continue
        head = path.read_text()[:600]
        assert "do not modify by hand" in head and "codegen" in head, path.name
    for name, data in _files(GENERATED).items():
        text = data.decode()
        assert "2026" not in text and "UTC" not in text, f"{name} carries a date"


@pytest.mark.parametrize("form", ["-DCODEGEN_INTERVAL_PROGRAMS", "-DCODEGEN_INLINE_INTERVALS"],
                         ids=["interval-programs", "inline-intervals"])
@pytest.mark.parametrize("source", sorted(f"{p.parent.name}/{p.name}"
                                          for p in GENERATED.glob("*/*.c")))
def test_c_compiles_under_strict_flags(source, form, tmp_path):
    cc = os.environ.get("CC", "gcc")
    folder = source.split("/")[0]
    includes = _includes(folder) if folder != generate.RUNTIME else ["-I", str(RUNTIME)]
    result = subprocess.run([cc, *STRICT, *filter(None, [form]), *includes, "-c",
                             str(GENERATED / source), "-o", str(tmp_path / "x.o")],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def _compile_all(tmp_path: Path) -> list[str]:
    """Every library and the runtime once, as objects."""
    objects = []
    for name in LIBRARIES + [generate.RUNTIME]:
        for source in sorted((GENERATED / name).glob("*.c")):
            obj = tmp_path / f"{name}-{source.stem}.o"
            includes = _includes(name) if name != generate.RUNTIME else ["-I", str(RUNTIME)]
            subprocess.run(["gcc", *STRICT, *includes, "-c", str(source), "-o", str(obj)],
                           check=True)
            objects.append(str(obj))
    return objects


def test_libraries_link_with_libm_only_and_have_no_mutable_globals(tmp_path):
    objects = _compile_all(tmp_path)
    symbols = subprocess.run(["nm", "-P", *objects], capture_output=True, text=True,
                             check=True).stdout
    undefined = {line.split()[0] for line in symbols.splitlines()
                 if len(line.split()) > 1 and line.split()[1] == "U"}
    defined_here = [line.split()[0] for line in symbols.splitlines()
                    if len(line.split()) > 1 and line.split()[1] == "T"]
    libc_libm = {"sqrt", "sin", "cos", "tan", "atan2", "atan", "fabs", "fma", "ldexp", "frexp", "pow",
                 "memset", "copysign", "memcpy", "memmove", "fmin", "fmax", "sincos", "__isnan",
                 "__isinf"}
    assert undefined - set(defined_here) <= libc_libm, undefined - set(defined_here) - libc_libm
    # all libraries and the runtime link into one program: no symbol is defined twice
    assert len(defined_here) == len(set(defined_here)), sorted(
        s for s in set(defined_here) if defined_here.count(s) > 1)
    # data with relocations (a library's codegen_model: pointers to its kernels) sits in
    # .data.rel.ro under a position-independent build: read-only once loaded
    sections = subprocess.run(["nm", "--format=sysv", *objects], capture_output=True, text=True,
                              check=True).stdout
    writable = [line for line in sections.splitlines() if line.count("|") == 6
                and line.split("|")[2].strip() in {"D", "d", "B", "b", "C"}
                and not line.split("|")[6].strip().startswith(".data.rel.ro")]
    assert not writable, f"mutable global state: {writable}"
    assert "malloc" not in symbols and "printf" not in symbols and "FILE" not in symbols


def test_one_program_links_every_library(tmp_path):
    includes = [arg for name in LIBRARIES for arg in _includes(name)]
    src = tmp_path / "all.c"
    src.write_text("".join(f'#include "{n}.h"\n' for n in LIBRARIES)
                   + "int main(void) { return " + " + ".join(f"(int){n.upper()}_OK"
                                                            for n in LIBRARIES) + "; }\n")
    exe = tmp_path / "all"
    subprocess.run(["gcc", *STRICT, *includes, str(src), *_compile_all(tmp_path), "-lm", "-o",
                    str(exe)], check=True)
    assert subprocess.run([str(exe)]).returncode == 0


def test_readme_example_compiles_and_runs(tmp_path):
    exe = tmp_path / "minimal"
    subprocess.run(["gcc", *STRICT, *_includes("doughty"), str(ROOT / "examples" / "minimal.c"),
                    *map(str, _sources("doughty") + sorted(RUNTIME.glob("*.c"))), "-lm", "-o",
                    str(exe)], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    assert out.count("theta_E") == 10 and out.count("genuine") == 6


@pytest.mark.skipif(shutil.which("g++") is None, reason="no C++ compiler")
@pytest.mark.parametrize("name", LIBRARIES)
def test_header_is_usable_from_cpp(name, tmp_path):
    src = tmp_path / "use.cpp"
    src.write_text(f'#include "{name}.h"\nint main() {{ return {name.upper()}_OK; }}\n')
    subprocess.run(["g++", "-Wall", "-Werror", *_includes(name), "-c", str(src), "-o",
                    str(tmp_path / "use.o")], check=True)


def test_pinned_sympy_is_the_one_installed():
    import sympy

    assert sympy.__version__ == generate.TESTED_SYMPY
    assert f"sympy=={generate.TESTED_SYMPY}" in (ROOT / "pyproject.toml").read_text()


def test_the_command_lines_cache_stands_in_only_for_unchanged_inputs(tmp_path, monkeypatch):
    """`make generate`/`make check` reuse a mechanism's files when its fingerprint (package
    sources, templates, versions) is unchanged; any change derives it again."""
    name = "torsion_pendulum"
    first = generate.emit_all([name], cache=tmp_path / "cache")
    assert first == generate.emit_all([name])            # the cache holds what emit gives
    entries = list((tmp_path / "cache").glob(f"{name}-*.json"))
    assert len(entries) == 1

    def no_derivation(*args, **kwargs):
        raise AssertionError("derived although the cache holds this fingerprint")

    monkeypatch.setattr(generate, "emit", no_derivation)
    assert generate.emit_all([name], cache=tmp_path / "cache") == first
    templates = tmp_path / "templates"
    shutil.copytree(generate.TEMPLATES, templates)
    assert generate.fingerprint(name, templates) == generate.fingerprint(name)
    with open(templates / "library.c.j2", "a") as f:
        f.write("{# a changed template #}\n")
    assert generate.fingerprint(name, templates) != generate.fingerprint(name)
    with pytest.raises(AssertionError, match="derived although"):
        generate.emit_all([name], templates, cache=tmp_path / "cache")
