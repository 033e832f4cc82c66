"""The runtime's codes declared once, in its C headers (codegen.ccodes): what the parser
reads, and that the cffi declarations, each library's aliases and the Python words are the
headers' codes, checked against the compiled libraries themselves.
"""
from __future__ import annotations

import re

import pytest

from codegen import ccodes
from codegen.api import load, shipped
from codegen.resources import generated
from codegen.runtime import analysis

#: The enums of codegen_model.h a one-coordinate library declares for cffi and aliases.
ANALYSIS_ENUMS = ("codegen_stability", "codegen_damping", "codegen_root_kind",
                  "codegen_uncertainty")


def test_the_parser_reads_enums_and_integer_defines():
    enums, constants = ccodes.parse("""
        /* typedef enum hidden { H = 9 } hidden; */
        typedef enum codegen_x {
            CODEGEN_A = 2,   /* a comment, with = and , inside */
            CODEGEN_B,       // one more than A
            CODEGEN_C = (-4)
        } codegen_x;
        #define CODEGEN_D -1 /* a comment */
        #  define CODEGEN_E (-11)
        #define CODEGEN_F 400000L
        #define CODEGEN_G(n) ((n) * 2)
        #define CODEGEN_H 1.5
        """)
    assert list(enums) == ["codegen_x"]
    assert enums["codegen_x"].members == (("CODEGEN_A", 2), ("CODEGEN_B", 3), ("CODEGEN_C", -4))
    assert enums["codegen_x"].names == ("A", "B", "C")
    assert constants == {"CODEGEN_A": 2, "CODEGEN_B": 3, "CODEGEN_C": -4, "CODEGEN_D": -1,
                         "CODEGEN_E": -11, "CODEGEN_F": 400000}
    with pytest.raises(ValueError, match="tag and the name"):
        ccodes.parse("typedef enum a { A = 0 } b;")


def test_the_declarations_wrap_like_a_header():
    short = ccodes.Enum("codegen_s", (("CODEGEN_A", 0), ("CODEGEN_B", 1)))
    assert ccodes.declaration(short) == ("typedef enum codegen_s { CODEGEN_A = 0, "
                                         "CODEGEN_B = 1 } codegen_s;")
    long = ccodes.Enum("codegen_l", tuple((f"CODEGEN_MEMBER_{i:02d}", i) for i in range(9)))
    lines = ccodes.declaration(long).splitlines()
    assert lines[0] == "typedef enum codegen_l {" and lines[-1] == "} codegen_l;"
    assert all(len(line) <= 100 and line.startswith("    ") for line in lines[1:-1])
    assert " ".join(lines[1:-1]).split() == " ".join(
        f"CODEGEN_MEMBER_{i:02d} = {i}{',' if i < 8 else ''}" for i in range(9)).split()


def test_python_words_index_the_headers_codes():
    enums = ccodes.enums()
    for words, enum in ((analysis.STABILITY, "codegen_stability"),
                        (analysis.DAMPING, "codegen_damping"),
                        (analysis.KINDS, "codegen_root_kind"),
                        (analysis.UNCERTAINTIES, "codegen_uncertainty")):
        # one coordinate's codes first; several coordinates add words after them
        assert words[:len(enums[enum].members)] == ccodes.words(enum, **{
            "codegen_damping": {"CRITICALLY_DAMPED": "critical", "NOT_OSCILLATORY": "none"},
            "codegen_root_kind": {"OTHER_ASSEMBLY": "other assembly mode"}}.get(enum, {}))
        assert len(words) == len(set(words))
    assert analysis.KINDS[ccodes.constants()["CODEGEN_EXTRANEOUS"]] == analysis.NOT_AN_EQUILIBRIUM
    assert analysis.DAMPING[ccodes.constants()["CODEGEN_NOT_OSCILLATORY"]] == "none"
    values = ccodes.constants()
    assert analysis.MULTIBODY_STABILITY == {values["CODEGEN_MB_STABLE"]: "stable",
                                   values["CODEGEN_MB_UNSTABLE"]: "unstable",
                                   values["CODEGEN_MB_UNDECIDED"]: "undecided"}
    assert set(analysis.MULTIBODY_UNCERTAIN) == {values["CODEGEN_BOX_CLUSTER"],
                                                  values["CODEGEN_BOX_SINGULAR"],
                                                  values["CODEGEN_MB_AT_RANGE_END"]}
    assert set(analysis.MULTIBODY_UNCERTAIN.values()) <= set(analysis.UNCERTAINTIES)
    assert set(analysis.MULTIBODY_STABILITY.values()) <= set(analysis.STABILITY)
    with pytest.raises(ValueError, match="no member"):
        ccodes.words("codegen_stability", NO_SUCH="x")


@pytest.mark.parametrize("name", shipped())
def test_the_compiled_libraries_agree_with_the_headers(name):
    """cffi's view of each one-coordinate library (compiled from generated/runtime/) gives
    every member of the analysis' enums the header's value, and the library's header aliases
    them all (NAME_STABLE for CODEGEN_STABLE)."""
    library = load(name)
    if library.dof > 1:
        pytest.skip("the multi-coordinate analysis declares its codes as #defines, read above")
    header = (generated() / library.PREFIX / f"{library.PREFIX}.h").read_text()
    for enum in ANALYSIS_ENUMS:
        for member, value in ccodes.enums()[enum].members:
            assert getattr(library.lib, member) == value, (name, member)
        for short in ccodes.enums()[enum].names:
            assert re.search(rf"^#define {library.PREFIX.upper()}_{short} CODEGEN_{short}$",
                             header, re.M), (name, short)
