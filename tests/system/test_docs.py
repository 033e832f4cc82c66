"""The README and the guides in docs/ cannot rot: their commands run, their links resolve.

The convention, for README.md and every docs/*.md:

- A ```console block shows commands and what they print. Each line that starts with "$ " is
  a command; the lines after it, up to the next command or the end of the block, are its
  output on stdout. Every command of a file runs here, in order, in one temporary folder of
  its own (so a command may use what an earlier one of the same file wrote), through bash,
  with ``mechvib`` replaced by ``python -m codegen`` of this interpreter, and must exit 0.
- The output shown is compared line by line with the real one (trailing spaces ignored). A
  line that ends in "..." matches any line that starts with the text before it; a line that
  is only "..." ends the comparison (the rest is not shown). Without a "...", the whole output
  must be as shown; a command shown with no output is only checked for its exit status.
- A ``mechvib`` (or ``python -m codegen``) command may appear only in a console block: a
  ```sh block holds what is not run here (make targets, pip, cmake, compilers).
- The temporary folder starts with ``spring_pendulum.py``, the model listed in
  docs/models.md, ``triple_pendulum.py``, the one docs/multibody.md lists, and ``app.c``,
  the C program of the README.

A command with ``--plot``, or ``draw``, needs matplotlib and one starting with ``cc`` a C compiler: without
them that command is skipped (the test fails instead where CI is set, like need_tools).
"""
from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
COMMAND_LINE = re.compile(r"^\s*(\$\s+)?(mechvib|python3? -m codegen)(\s|$)")


@dataclass
class Block:
    lang: str
    line: int                      # 1-based line of the opening fence
    lines: list[str] = field(default_factory=list)


@dataclass
class Command:
    text: str
    line: int
    expected: list[str]


def blocks(path: Path) -> list[Block]:
    """The fenced code blocks of a Markdown file."""
    found: list[Block] = []
    current: Block | None = None
    for number, line in enumerate(path.read_text().splitlines(), 1):
        match = FENCE.match(line)
        if current is None:
            if match:
                current = Block(match.group(2), number)
        elif match and not match.group(2):
            found.append(current)
            current = None
        else:
            current.lines.append(line)
    assert current is None, f"{path.name}: the block opened at line {current.line} is not closed"
    return found


def commands(path: Path) -> list[Command]:
    """The commands of a file's console blocks, with the output each shows."""
    found: list[Command] = []
    for block in blocks(path):
        if block.lang != "console":
            continue
        assert block.lines and block.lines[0].startswith("$ "), \
            f"{path.name}:{block.line}: a console block starts with a '$ ' command"
        for offset, line in enumerate(block.lines, block.line + 1):
            if line.startswith("$ "):
                found.append(Command(line[2:].strip(), offset, []))
            else:
                found[-1].expected.append(line)
    return found


def section(path: Path, heading: str, lang: str) -> str:
    """The first block of a language after a heading of a file."""
    text = path.read_text().split(heading, 1)[1]
    return text.split(f"```{lang}\n", 1)[1].split("```", 1)[0]


def model_listing() -> str:
    return section(REPO / "docs" / "models.md", "## An example", "python")


def compare(expected: list[str], actual: list[str]) -> str | None:
    """None if the output matches what the docs show, else what differs."""
    for index, want in enumerate(expected):
        want = want.rstrip()
        if want == "...":
            return None
        if index >= len(actual):
            return f"line {index + 1}: expected {want!r}, the output has only {len(actual)} lines"
        got = actual[index].rstrip()
        if want.endswith("..."):
            if not got.startswith(want[:-3].rstrip()):
                return f"line {index + 1}: expected {want!r}, got {got!r}"
        elif got != want:
            return f"line {index + 1}: expected {want!r}, got {got!r}"
    if expected and len(actual) != len(expected):
        return f"the docs show {len(expected)} lines, the output has {len(actual)}"
    return None


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def _missing(command: str) -> str | None:
    """What the command needs that is not installed, or None."""
    if "--plot" in command or command.split()[1:2] == ["draw"]:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            return "matplotlib"
    word = command.split()[0]
    if word in ("cc", "gcc", "clang", "cmake", "make") and shutil.which(word) is None:
        return word
    return None


def _seed(folder: Path) -> None:
    (folder / "spring_pendulum.py").write_text(model_listing())
    (folder / "triple_pendulum.py").write_text(
        section(REPO / "docs" / "multibody.md", "## A model with three coordinates", "python"))
    (folder / "app.c").write_text(section(REPO / "README.md", "## The C library", "c"))
    shutil.copy(REPO / "tests" / "models" / "four_bar_pendulum.py", folder)


@pytest.mark.parametrize("path", DOCS, ids=[p.relative_to(REPO).as_posix() for p in DOCS])
def test_commands_run_and_print_what_the_docs_show(path, tmp_path):
    found = commands(path)
    if not found:
        return                     # nothing to run (performance.md shows figures only)
    _seed(tmp_path)
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"), MPLBACKEND="Agg")
    env.pop("COLUMNS", None)
    codegen = f"{shlex.quote(sys.executable)} -m codegen"
    skipped = []
    for command in found:
        where = f"{path.name}:{command.line}: $ {command.text}"
        missing = _missing(command.text)
        if missing:
            if _in_ci():
                pytest.fail(f"{where}: needs {missing} [CI is set]", pytrace=False)
            skipped.append(f"{where} (needs {missing})")
            continue
        shell = re.sub(r"^(mechvib|python3? -m codegen)\b", codegen, command.text)
        result = subprocess.run(["bash", "-c", shell], cwd=tmp_path, env=env,
                                capture_output=True, text=True, timeout=180)
        assert result.returncode == 0, (f"{where}: exit status {result.returncode}\n"
                                        f"{result.stdout[-2000:]}{result.stderr[-2000:]}")
        difference = compare(command.expected, result.stdout.splitlines())
        assert difference is None, f"{where}: {difference}\n--- output:\n{result.stdout}"
    if skipped:
        pytest.skip("ran the rest; skipped " + "; ".join(skipped))


@pytest.mark.parametrize("path", DOCS, ids=[p.relative_to(REPO).as_posix() for p in DOCS])
def test_commands_appear_only_in_console_blocks(path):
    """A mechvib command in any other block would not be run by this test, so it could rot."""
    for block in blocks(path):
        if block.lang == "console":
            continue
        for offset, line in enumerate(block.lines, block.line + 1):
            assert not COMMAND_LINE.match(line), \
                f"{path.name}:{offset}: a command outside a console block: {line.strip()}"


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def _anchors(path: Path) -> set[str]:
    """GitHub's anchors for the headings of a Markdown file (outside code blocks)."""
    anchors = set()
    inside = False
    for line in path.read_text().splitlines():
        if FENCE.match(line):
            inside = not inside
        elif not inside and line.startswith("#"):
            title = line.lstrip("#").strip().lower()
            anchors.add(re.sub(r"[^\w\- ]", "", title).replace(" ", "-"))
    return anchors


@pytest.mark.parametrize("path", DOCS, ids=[p.relative_to(REPO).as_posix() for p in DOCS])
def test_relative_links_point_to_files_that_exist(path):
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    targets = LINK.findall(text)
    assert targets or path.name != "README.md", "the README links to the guides"
    for target in targets:
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):      # https:, mailto:
            continue
        name, _, anchor = target.partition("#")
        linked = (path.parent / name).resolve() if name else path
        assert linked.is_file(), f"{path.name}: the link {target} points to no file"
        assert linked.is_relative_to(REPO), f"{path.name}: the link {target} leaves the repository"
        if anchor and linked.suffix == ".md":
            assert anchor in _anchors(linked), f"{path.name}: {target}: no such heading"


def test_every_guide_is_linked_from_the_readme():
    readme = (REPO / "README.md").read_text()
    for guide in (REPO / "docs").glob("*.md"):
        assert f"(docs/{guide.name})" in readme, f"README.md does not link docs/{guide.name}"


def test_readme_is_read_in_five_minutes():
    assert len((REPO / "README.md").read_text().splitlines()) <= 300


def test_readme_quick_start_is_the_two_commands():
    """CI (.ci/run) and the packaging tests rely on these two commands."""
    quick = section(REPO / "README.md", "## Quick start", "sh").splitlines()
    assert [line.split("#")[0].strip() for line in quick] == ["make analyze", "make test"]


def test_readme_model_excerpt_is_the_listed_model():
    """The README's dozen lines of build() are cut from the model docs/models.md lists."""
    excerpt = section(REPO / "README.md", "## Your own mechanism", "python")
    assert len(excerpt.splitlines()) <= 15
    assert excerpt in model_listing()


def test_paper_is_cited_alike_in_readme_and_method():
    """What is known of the paper, and that its bibliographic details are missing, in both."""
    for path in (REPO / "README.md", REPO / "docs" / "method.md"):
        text = " ".join(path.read_text().split())
        for fact in ("10-step method", "Spanish-language journal article",
                     "a novel approach to analyze the vibrations associated with multibody "
                     "mechanical systems", "Doughty's two-slider mechanism", "OCR text without its "
                     "title page"):
            assert fact in text, f"{path.name}: {fact!r}"


def python_scripts(path: Path) -> list[Block]:
    """The Python blocks of a file that start processes (multiprocessing): run as scripts."""
    return [b for b in blocks(path) if b.lang == "python" and "multiprocessing" in "\n".join(b.lines)]


@pytest.mark.parametrize("path", DOCS, ids=[p.relative_to(REPO).as_posix() for p in DOCS])
def test_process_pool_snippets_run_as_scripts(path, tmp_path):
    """A snippet pasted into a script must not hang: a spawn pool needs the __main__ guard."""
    for block in python_scripts(path):
        code = "\n".join(block.lines) + "\n"
        assert 'if __name__ == "__main__":' in code, f"{path.name}:{block.line}: no __main__ guard"
        script = tmp_path / f"snippet_{block.line}.py"
        script.write_text(code)
        run = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                             text=True, timeout=300)
        assert run.returncode == 0, f"{path.name}:{block.line}: {run.stderr[-2000:]}"


def test_cmake_add_subdirectory_lines_build_a_consumer(need_tools, tmp_path):
    """The two documented lines, in a project outside the checkout, configure and build."""
    need_tools("cmake", "cc")
    lines = section(REPO / "docs" / "c-library.md", "## CMake and pkg-config", "cmake")
    lines = lines.replace("path/to/mechvib", REPO.as_posix())
    (tmp_path / "app.c").write_text(section(REPO / "README.md", "## The C library", "c"))
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(consumer C)\n"
        "add_executable(app app.c)\n" + lines)
    build = tmp_path / "build"
    for command in (["cmake", "-S", str(tmp_path), "-B", str(build)],
                    ["cmake", "--build", str(build), "-j2"]):
        run = subprocess.run(command, capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    app = subprocess.run([str(build / "app")], capture_output=True, text=True, timeout=60)
    assert app.returncode == 0 and "176.7155 deg" in app.stdout
