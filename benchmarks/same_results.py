#!/usr/bin/env python3
"""`make same-results`: the raw results of two revisions' C libraries, bit for bit.

Builds every shipped mechanism's library twice -- from BASE's generated/ (``git archive``)
and from the working tree's generated/ (or --tree DIR) -- each in four ways: double and
float (-DCODEGEN_FLOAT), with inline interval enclosures (-DCODEGEN_INLINE_INTERVALS) and
with interval programs (-DCODEGEN_INTERVAL_PROGRAMS), all with the same compiler and flags
(-std=c99 -O2). For each mechanism a small C driver is written from the revision's own
NAME.h and NAME_api.json: it reads parameter sets and writes, for each, the raw bytes of
what the library answers -- the status and the whole result struct (zeroed first) of
NAME_analyze and NAME_isolate (one coordinate) or NAME_analyze (n coordinates), the
enclosures of G, every function of the API at three fixed points, a short time response,
an RK4 step and the frequency response (or, for n coordinates, the range centres, box
enclosures, modes, receptance and accelerations). The two revisions' bytes are compared
set by set; the differing sets are decoded field by field (status, counts, angles, and
every field that differs).

Parameter sets (the same for both revisions, reproducible from --seed): the example of
NAME_api.json, then sets whose every parameter is its example times 10^u, u uniform in
[-spread, spread] (sign kept); a parameter in radians is drawn uniformly in (-pi, pi];
one whose example is 0 stays 0 in half the sets and is +-10^u (SI units) in the others.

Standard library only, and nothing of either revision's Python: BASE's Python may differ.
Exit status: 0 when every result is identical, 1 when any differs, 2 when something could
not be built or run. generated/ is compared file by file too (informational: a generator
change is expected to change files; only the results decide).

Usage: same_results.py [--base REV | --base-dir DIR] [--tree DIR] [--sets N] ...
"""
from __future__ import annotations

import argparse
import filecmp
import hashlib
import io
import json
import math
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import tarfile
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _flag_sets(path: Path) -> dict[str, tuple[str, ...]]:
    """The named flag sets of runtime/cflags.txt (NAME = FLAGS per line), read without the
    package: both revisions are built with the working tree's flags, so that only the
    sources differ."""
    sets = {}
    for line in path.read_text().splitlines():
        name, sep, flags = line.partition("=")
        if sep and not line.lstrip().startswith("#"):
            sets[name.strip()] = tuple(flags.split())
    return sets


_SETS = _flag_sets(ROOT / "runtime" / "cflags.txt")
CFLAGS = _SETS["base"] + _SETS["optimize"]
#: The builds, each a name and its defines; every one for both revisions.
BUILDS = {
    "double inline": ("-DCODEGEN_INLINE_INTERVALS",),
    "double programs": ("-DCODEGEN_INTERVAL_PROGRAMS",),
    "float inline": ("-DCODEGEN_FLOAT", "-DCODEGEN_INLINE_INTERVALS"),
    "float programs": ("-DCODEGEN_FLOAT", "-DCODEGEN_INTERVAL_PROGRAMS"),
}
#: The fixed inputs of the kernels (angles, rates, coordinates), cycled through.
INPUTS = (0.4, -1.3, 2.1, -0.25, 1.05, -2.7, 0.75, 3.0, -0.6, 1.6, -1.9, 0.15, 2.6)
POINTS = 3  # each kernel at this many input vectors
#: The interval ends [rad] of the one-coordinate enclosures.
INTERVALS = ((-0.6, 0.4), (1.0, 1.001), (-3.0, 3.0))
#: The boxes (lo, hi per coordinate) of the n-coordinate enclosures.
BOXES = (((-0.6, -0.6), (0.4, 0.4)), ((1.0, -2.0), (1.001, -1.999)), ((-3.0, -3.0), (3.0, 3.0)))
STEP_BUDGET = 200  # the time responses' max_steps: a stiff set ends early, with its status
SIMULATE_TIMES = (0.0, 0.002, 0.01, 0.03)
FREQUENCIES = (0.5, 5.0, 50.0)


# ---------------------------------------------------------------- reading a revision's C API

def strip_comments(text: str) -> str:
    return re.sub(r"//[^\n]*", "", re.sub(r"/\*.*?\*/", " ", text, flags=re.S))


def struct_fields(text: str, name: str) -> list[tuple[str, str]] | None:
    """The (type, member) pairs of ``typedef struct name {...} name;`` in text (comments
    stripped), arrays as ``member`` alone (their sizes are the compiler's, via sizeof)."""
    found = re.search(r"typedef\s+struct\s+" + name + r"\s*\{(.*?)\}\s*" + name + r"\s*;",
                      text, re.S)
    if not found:
        return None
    fields = []
    for declaration in found.group(1).split(";"):
        declaration = " ".join(declaration.split())
        if not declaration:
            continue
        parts = [p.strip() for p in declaration.split(",")]
        first = re.match(r"(.*?)(\w+)\s*(\[[^\]]*\])*$", parts[0])
        if not first:
            return None
        type_ = first.group(1).strip()
        names = [first.group(2)]
        for p in parts[1:]:
            more = re.match(r"\**\s*(\w+)", p)
            if not more:
                return None
            names.append(more.group(1))
        fields += [(type_, n) for n in names]
    return fields


def enum_names(text: str) -> set[str]:
    return set(re.findall(r"typedef\s+enum\s+\w*\s*\{[^}]*\}\s*(\w+)\s*;", text, re.S))


def declaration(text: str, function: str) -> list[str] | None:
    """The argument types of a function declared in text, canonical (names dropped, arrays
    as pointers, no spaces around '*'); None where it is not declared."""
    found = re.search(r"\b" + function + r"\s*\(([^;{]*?)\)\s*;", text, re.S)
    if not found:
        return None
    types = []
    for arg in found.group(1).split(","):
        arg = " ".join(arg.split())
        array = "[" in arg
        arg = re.sub(r"\[[^\]]*\]", "", arg).strip()
        named = re.match(r"(.*?[\s*])(\w+)$", arg)
        type_ = named.group(1) if named and named.group(1).strip() else arg
        type_ = re.sub(r"\s*\*\s*", "*", type_.strip()) + ("*" if array else "")
        types.append(type_)
    return types


@dataclass
class Api:
    """What the driver needs of one revision's library."""

    name: str
    folder: Path
    spec: dict
    header: str       # NAME.h, comments stripped
    model_header: str  # runtime/codegen_model.h and codegen_ode.h, comments stripped
    notes: list[str] = field(default_factory=list)

    @property
    def prefix(self) -> str:
        return self.spec["prefix"]

    @property
    def multibody(self) -> bool:
        return self.spec.get("dof", 1) > 1

    @property
    def parameters(self) -> list[str]:
        return [p["name"] for p in self.spec["parameters"]]

    def has(self, function: str, types: list[str]) -> bool:
        """Whether PREFIX_function is declared with these argument types (noted if not)."""
        found = declaration(self.header, f"{self.prefix}_{function}")
        if found is None:
            self.notes.append(f"no {self.prefix}_{function}")
            return False
        if found != types:
            self.notes.append(f"{self.prefix}_{function}({', '.join(found)}) not the driver's "
                              f"({', '.join(types)})")
            return False
        return True

    def has_macro(self, macro: str) -> bool:
        return re.search(r"#define\s+" + macro + r"\b", self.header) is not None


def read_api(folder: Path) -> Api:
    name = folder.name
    runtime = folder.parent / "runtime"
    model = "".join((runtime / h).read_text() for h in ("codegen_model.h", "codegen_ode.h")
                    if (runtime / h).exists())
    return Api(name, folder, json.loads((folder / f"{name}_api.json").read_text()),
               strip_comments((folder / f"{name}.h").read_text()), strip_comments(model))


# ---------------------------------------------------------------- the driver

class Driver:
    """The C source of one revision's driver: items, each a block of C that writes parts
    (raw bytes), and a layout() that prints every part's kind and size and every struct's
    members, for the comparison to decode them."""

    def __init__(self, api: Api):
        self.api = api
        self.items: list[tuple[str, str, list[tuple[str, str, str]]]] = []
        self.structs: list[tuple[str, list[tuple[str, str]]]] = []

    def item(self, name: str, code: str, parts: list[tuple[str, str, str]]) -> None:
        """parts: (label, kind, C expression of the object written); kinds int, uint, u64,
        real or struct:TYPE."""
        self.items.append((name, code, parts))

    def kind(self, type_: str) -> str:
        type_ = type_.replace("const ", "").strip()
        if type_ == "codegen_real":
            return "real"
        if type_ in ("int", "signed", "signed int"):
            return "int"
        if type_ in ("unsigned", "unsigned int"):
            return "uint"
        if type_ in enum_names(self.api.model_header) | enum_names(self.api.header):
            return "int"
        if type_ in {s for s, _ in self.structs} or self.add_struct(type_):
            return f"struct:{type_}"
        return "bytes"

    def add_struct(self, name: str) -> bool:
        fields = struct_fields(self.api.header, name) or struct_fields(self.api.model_header, name)
        if fields is None:
            return False
        self.structs.append((name, []))  # first, for recursion
        members = [(member, self.kind(type_)) for type_, member in fields]
        self.structs[[s for s, _ in self.structs].index(name)] = (name, members)
        return True

    def source(self) -> str:
        api, P = self.api, self.api.prefix
        lines = [f"/* same_results.py's driver for {api.name}: generated, do not edit. */",
                 "#include <stddef.h>", "#include <stdio.h>", "#include <stdlib.h>",
                 "#include <string.h>", f'#include "{api.name}.h"', "",
                 "static FILE *out;", "",
                 "static void put(const void *data, size_t size)", "{",
                 "    if (fwrite(data, 1, size, out) != size) {",
                 '        perror("same_results driver: write");', "        exit(3);", "    }",
                 "}", "", "static void layout(void)", "{",
                 '    printf("real %u\\nint %u\\nuint %u\\n", (unsigned)sizeof(codegen_real), '
                 "(unsigned)sizeof(int), (unsigned)sizeof(unsigned));"]
        for name, members in self.structs:
            lines.append(f'    printf("struct {name} %u\\n", (unsigned)sizeof({name}));')
            for member, kind in members:
                lines.append(f'    printf("member {name} {member} %u %u {kind}\\n", '
                             f"(unsigned)offsetof({name}, {member}), "
                             f"(unsigned)sizeof((({name} *)0)->{member}));")
        lines += ["}", "",
                  "/* Each item: its calls, then its parts written (or, for layout, described). */",
                  f"static void run_set(const {P}_params *p, int describe)", "{"]
        for name, code, parts in self.items:
            lines += [f"    {{ /* {name} */", code.rstrip(), "        if (describe) {",
                      f'            printf("item {name}\\n");']
            lines += [f'            printf("part {label} {kind} %u\\n", '
                      f"(unsigned)sizeof {expression});" for label, kind, expression in parts]
            lines.append("        } else {")
            lines += [f"            put(&{expression}, sizeof {expression});"
                      for _, _, expression in parts]
            lines += ["        }", "    }"]
        parameters = api.parameters
        n = len(parameters)
        lines += ["}", "", "int main(int argc, char **argv)", "{",
                  f"    double x[{n}];", "    FILE *in;", "    long set, first, count;",
                  '    if (argc == 2 && strcmp(argv[1], "layout") == 0) {',
                  f"        {P}_params zero;", "        memset(&zero, 0, sizeof zero);",
                  "        layout();", "        run_set(&zero, 1);", "        return 0;", "    }",
                  "    if (argc != 5) {",
                  '        fprintf(stderr, "usage: %s layout | PARAMS OUT FIRST COUNT\\n", '
                  "argv[0]);",
                  "        return 2;", "    }",
                  '    in = fopen(argv[1], "rb");', '    out = fopen(argv[2], "wb");',
                  "    first = atol(argv[3]);", "    count = atol(argv[4]);",
                  "    if (in == NULL || out == NULL) {",
                  '        perror("same_results driver: open");', "        return 2;", "    }",
                  "    if (fseek(in, first * (long)sizeof x, SEEK_SET) != 0) {",
                  '        perror("same_results driver: seek");', "        return 2;", "    }",
                  "    for (set = 0; set < count; ++set) {",
                  f"        {P}_params p;",
                  f"        if (fread(x, sizeof x[0], {n}, in) != {n}) {{",
                  '            fprintf(stderr, "same_results driver: short input\\n");',
                  "            return 2;", "        }",
                  "        memset(&p, 0, sizeof p);"]
        lines += [f"        p.{name} = (codegen_real)x[{i}];" for i, name in enumerate(parameters)]
        lines += ["        run_set(&p, 0);", "    }",
                  "    if (fclose(out) != 0) {", '        perror("same_results driver: close");',
                  "        return 3;", "    }", "    fclose(in);", "    return 0;", "}", ""]
        return "\n".join(lines)


def literal(value: float) -> str:
    return f"(codegen_real){value!r}"


def array(values) -> str:
    return "{" + ", ".join(literal(v) for v in values) + "}"


def add_analyses(driver: Driver) -> None:
    api, P = driver.api, driver.api.prefix
    analysis = f"{P}_analysis"
    if not driver.add_struct(analysis):
        api.notes.append(f"no struct {analysis}")
        return
    entries = ("analyze",) if api.multibody else ("analyze", "isolate")
    for entry in entries:
        if api.has(entry, [f"const {P}_params*", f"{analysis}*"]):
            driver.item(entry, f"        {analysis} r;\n        int status;\n"
                               "        memset(&r, 0, sizeof r);\n"
                               f"        status = (int){P}_{entry}(p, &r);",
                        [("status", "int", "status"), ("result", f"struct:{analysis}", "r")])


def add_kernels(driver: Driver) -> None:
    """Every function of NAME_api.json at POINTS fixed input vectors."""
    api, P = driver.api, driver.api.prefix
    for f in api.spec["functions"]:
        types = [f"const {P}_params*"]
        types += ["const codegen_real*" if a["size"] else "codegen_real" for a in f["inputs"]]
        types += ["codegen_real*" for _ in f["outputs"]]
        if not api.has(f["name"], types):
            continue
        total = sum(o["size"] or 1 for o in f["outputs"])
        declarations = [f"        int status[{POINTS}];",
                        f"        codegen_real o[{POINTS}][{total}];"]
        calls, cursor = [], 0
        for point in range(POINTS):
            arguments = ["p"]
            for k, a in enumerate(f["inputs"]):
                n = a["size"] or 1
                values = [INPUTS[(cursor + j) % len(INPUTS)] for j in range(n)]
                cursor += n
                if a["size"]:
                    declarations.append(f"        codegen_real in{point}_{k}[{n}] = "
                                        f"{array(values)};")
                    arguments.append(f"in{point}_{k}")
                else:
                    arguments.append(literal(values[0]))
            offset = 0
            for o in f["outputs"]:
                arguments.append(f"&o[{point}][{offset}]")
                offset += o["size"] or 1
            calls.append(f"        status[{point}] = (int){P}_{f['name']}({', '.join(arguments)});")
        label = f["outputs"][0]["name"] if len(f["outputs"]) == 1 else "outputs"
        driver.item(f"kernel:{f['name']}",
                    "\n".join(declarations + ["        memset(o, 0, sizeof o);"] + calls),
                    [("status", "int", "status"), (label, "real", "o")])


def add_one_coordinate(driver: Driver) -> None:
    api, P, U = driver.api, driver.api.prefix, driver.api.prefix.upper()
    params = f"const {P}_params*"
    if api.has_macro(f"{U}_N_MODES") and api.has(
            "enclosure", [params, "unsigned", "const codegen_real*", "codegen_real*",
                          "codegen_real*", "unsigned*"]):
        n = len(INTERVALS)
        ends = [e for interval in INTERVALS for e in interval]
        driver.item("enclosure", f"""\
        static const codegen_real ends[{2 * n}] = {array(ends)};
        int status[{U}_N_MODES][{n}];
        codegen_real g[{U}_N_MODES][{n}][2], dg[{U}_N_MODES][{n}][2];
        unsigned flags[{U}_N_MODES][{n}];
        unsigned mode;
        int i;
        memset(g, 0, sizeof g);
        memset(dg, 0, sizeof dg);
        memset(flags, 0, sizeof flags);
        for (mode = 0; mode < {U}_N_MODES; ++mode) {{
            for (i = 0; i < {n}; ++i) {{
                status[mode][i] = (int){P}_enclosure(p, mode, &ends[2 * i], g[mode][i],
                                                      dg[mode][i], &flags[mode][i]);
            }}
        }}""", [("status", "int", "status"), ("g", "real", "g"), ("dg", "real", "dg"),
                ("flags", "uint", "flags")])
    if api.has("rk4_step", [params, "codegen_real", "codegen_real", "codegen_real",
                            "codegen_real*", "codegen_real*"]):
        driver.item("rk4_step", """\
        codegen_real next[2] = {0, 0};
        int status = (int)%s_rk4_step(p, (codegen_real)1e-3, (codegen_real)0.4,
                                      (codegen_real)0.1, &next[0], &next[1]);""" % P,
                    [("status", "int", "status"), ("next", "real", "next")])
    if declaration(api.model_header, "codegen_ode_defaults") == ["void"] and api.has(
            "simulate", [params, "codegen_real", "codegen_real", "const codegen_real*",
                         "size_t", "const codegen_ode_options*", "codegen_real*",
                         "codegen_real*", "size_t*"]):
        n = len(SIMULATE_TIMES)
        driver.item("simulate", f"""\
        static const codegen_real times[{n}] = {array(SIMULATE_TIMES)};
        codegen_ode_options options = codegen_ode_defaults();
        codegen_real theta[{n}], theta_d[{n}];
        size_t reached_ = 0;
        unsigned long long reached;
        int status;
        memset(theta, 0, sizeof theta);
        memset(theta_d, 0, sizeof theta_d);
        options.max_steps = {STEP_BUDGET};
        status = (int){P}_simulate(p, (codegen_real)0.4, (codegen_real)0.0, times, {n}, &options,
                                   theta, theta_d, &reached_);
        reached = (unsigned long long)reached_;""",
                    [("status", "int", "status"), ("theta", "real", "theta"),
                     ("theta_d", "real", "theta_d"), ("reached", "u64", "reached")])
    if api.has("frequency_response", [params, "codegen_real", "size_t", "const codegen_real*",
                                      "codegen_real*", "codegen_real*"]):
        n = len(FREQUENCIES)
        driver.item("frequency_response", f"""\
        static const codegen_real omega[{n}] = {array(FREQUENCIES)};
        codegen_real H_re[{n}], H_im[{n}];
        int status;
        memset(H_re, 0, sizeof H_re);
        memset(H_im, 0, sizeof H_im);
        status = (int){P}_frequency_response(p, (codegen_real)0.4, {n}, omega, H_re, H_im);""",
                    [("status", "int", "status"), ("H_re", "real", "H_re"),
                     ("H_im", "real", "H_im")])


def add_multibody(driver: Driver) -> None:
    api, P, U = driver.api, driver.api.prefix, driver.api.prefix.upper()
    params = f"const {P}_params*"
    if not all(api.has_macro(f"{U}_{m}") for m in ("N_DOF", "N_MATRIX", "N_EIGENVALUES")):
        api.notes.append("no N_DOF, N_MATRIX or N_EIGENVALUES: only the analysis compared")
        return
    dof = api.spec.get("dof", 2)
    point = [INPUTS[j % len(INPUTS)] for j in range(dof)]
    rate = [INPUTS[(j + 5) % len(INPUTS)] for j in range(dof)]
    if api.has("range_centres", [params, "codegen_real*"]):
        driver.item("range_centres", f"""\
        codegen_real centre[{U}_N_DOF];
        int status;
        memset(centre, 0, sizeof centre);
        status = (int){P}_range_centres(p, centre);""",
                    [("status", "int", "status"), ("centre", "real", "centre")])
    if dof == 2 and api.has("box_enclosure", [params, "const codegen_real*",
                                              "const codegen_real*", "codegen_real*",
                                              "codegen_real*", "unsigned*"]):
        n = len(BOXES)
        lo = [v for box in BOXES for v in box[0]]
        hi = [v for box in BOXES for v in box[1]]
        driver.item("box_enclosure", f"""\
        static const codegen_real lo[{2 * n}] = {array(lo)};
        static const codegen_real hi[{2 * n}] = {array(hi)};
        int status[{n}];
        codegen_real G[{n}][2 * {U}_N_DOF], K[{n}][2 * {U}_N_MATRIX];
        unsigned flags[{n}];
        int i;
        memset(G, 0, sizeof G);
        memset(K, 0, sizeof K);
        memset(flags, 0, sizeof flags);
        for (i = 0; i < {n}; ++i) {{
            status[i] = (int){P}_box_enclosure(p, &lo[2 * i], &hi[2 * i], G[i], K[i], &flags[i]);
        }}""", [("status", "int", "status"), ("G", "real", "G"), ("K", "real", "K"),
                ("flags", "uint", "flags")])
    if api.has("modes", [params, "const codegen_real*"] + ["codegen_real*"] * 6 + ["int*"]):
        driver.item("modes", f"""\
        static const codegen_real theta[{dof}] = {array(point)};
        codegen_real omega_squared[{U}_N_DOF], shapes[{U}_N_MATRIX];
        codegen_real s_re[{U}_N_EIGENVALUES], s_im[{U}_N_EIGENVALUES];
        codegen_real damping_ratio[{U}_N_EIGENVALUES], modal_damping[{U}_N_DOF];
        int stability = 0, status;
        memset(omega_squared, 0, sizeof omega_squared);
        memset(shapes, 0, sizeof shapes);
        memset(s_re, 0, sizeof s_re);
        memset(s_im, 0, sizeof s_im);
        memset(damping_ratio, 0, sizeof damping_ratio);
        memset(modal_damping, 0, sizeof modal_damping);
        status = (int){P}_modes(p, theta, omega_squared, shapes, s_re, s_im, damping_ratio,
                                modal_damping, &stability);""",
                    [("status", "int", "status"), ("omega_squared", "real", "omega_squared"),
                     ("shapes", "real", "shapes"), ("s_re", "real", "s_re"),
                     ("s_im", "real", "s_im"), ("damping_ratio", "real", "damping_ratio"),
                     ("modal_damping", "real", "modal_damping"),
                     ("stability", "int", "stability")])
    if api.has("receptance", [params, "const codegen_real*", "codegen_real", "codegen_real*",
                              "codegen_real*"]):
        driver.item("receptance", f"""\
        static const codegen_real theta[{dof}] = {array(point)};
        codegen_real H_re[{U}_N_MATRIX], H_im[{U}_N_MATRIX];
        int status;
        memset(H_re, 0, sizeof H_re);
        memset(H_im, 0, sizeof H_im);
        status = (int){P}_receptance(p, theta, (codegen_real)3.0, H_re, H_im);""",
                    [("status", "int", "status"), ("H_re", "real", "H_re"),
                     ("H_im", "real", "H_im")])
    if api.has("accelerations", [params, "const codegen_real*", "const codegen_real*",
                                 "codegen_real*"]):
        driver.item("accelerations", f"""\
        static const codegen_real theta[{dof}] = {array(point)};
        static const codegen_real theta_d[{dof}] = {array(rate)};
        codegen_real theta_dd[{U}_N_DOF];
        int status;
        memset(theta_dd, 0, sizeof theta_dd);
        status = (int){P}_accelerations(p, theta, theta_d, theta_dd);""",
                    [("status", "int", "status"), ("theta_dd", "real", "theta_dd")])
    if declaration(api.model_header, "codegen_ode_defaults") == ["void"] and api.has(
            "simulate", [params, "const codegen_real*", "const codegen_real*",
                         "const codegen_real*", "size_t", "const codegen_ode_options*",
                         "codegen_real*", "size_t*"]):
        n = len(SIMULATE_TIMES)
        driver.item("simulate", f"""\
        static const codegen_real theta0[{dof}] = {array(point)};
        static const codegen_real theta_d0[{dof}] = {array([0.0] * dof)};
        static const codegen_real times[{n}] = {array(SIMULATE_TIMES)};
        codegen_ode_options options = codegen_ode_defaults();
        codegen_real y[{n} * 2 * {U}_N_DOF];
        size_t reached_ = 0;
        unsigned long long reached;
        int status;
        memset(y, 0, sizeof y);
        options.max_steps = {STEP_BUDGET};
        status = (int){P}_simulate(p, theta0, theta_d0, times, {n}, &options, y, &reached_);
        reached = (unsigned long long)reached_;""",
                    [("status", "int", "status"), ("y", "real", "y"),
                     ("reached", "u64", "reached")])


def driver_source(api: Api) -> tuple[str, list[str]]:
    """The driver's C source and its items' names."""
    driver = Driver(api)
    add_analyses(driver)
    if api.multibody:
        add_multibody(driver)
    else:
        add_one_coordinate(driver)
    add_kernels(driver)
    return driver.source(), [name for name, _, _ in driver.items]


# ---------------------------------------------------------------- layouts and decoding

@dataclass
class Layout:
    """A driver's record per parameter set: items of parts, and the structs' members."""

    sizes: dict[str, int]                  # real, int, uint, u64
    structs: dict[str, tuple[int, list]]   # name -> (size, [(member, offset, size, kind)])
    items: dict[str, list]                 # name -> [(label, kind, size)], in output order

    @property
    def record(self) -> int:
        return sum(size for parts in self.items.values() for _, _, size in parts)

    def spans(self) -> dict[str, tuple[int, int]]:
        """Each item's (start, end) within a record."""
        spans, at = {}, 0
        for name, parts in self.items.items():
            size = sum(s for _, _, s in parts)
            spans[name] = (at, at + size)
            at += size
        return spans

    @classmethod
    def parse(cls, text: str) -> "Layout":
        sizes, structs, items = {"u64": 8}, {}, {}
        current = None
        for line in text.splitlines():
            words = line.split()
            if words[0] in ("real", "int", "uint"):
                sizes[words[0]] = int(words[1])
            elif words[0] == "struct":
                structs[words[1]] = (int(words[2]), [])
            elif words[0] == "member":
                structs[words[1]][1].append((words[2], int(words[3]), int(words[4]), words[5]))
            elif words[0] == "item":
                current = items[words[1]] = []
            elif words[0] == "part":
                current.append((words[1], words[2], int(words[3])))
        return cls(sizes, structs, items)

    def leaves(self, item: str, data: bytes) -> dict[str, bytes]:
        """An item's bytes as {path: bytes} for every scalar in it (padding left out)."""
        out, at = {}, 0
        for label, kind, size in self.items[item]:
            self._leaves(label, kind, data[at:at + size], out)
            at += size
        return out

    def _leaves(self, path: str, kind: str, data: bytes, out: dict) -> None:
        if kind.startswith("struct:"):
            size, members = self.structs[kind[7:]]
            for i in range(len(data) // size):
                element = data[i * size:(i + 1) * size]
                prefix = path if len(data) == size else f"{path}[{i}]"
                for member, offset, msize, mkind in members:
                    self._leaves(f"{prefix}.{member}", mkind, element[offset:offset + msize],
                                 out)
            return
        size = self.sizes.get(kind, len(data)) or len(data)
        count = len(data) // size
        for i in range(count):
            out[path if count == 1 else f"{path}[{i}]"] = data[i * size:(i + 1) * size]

    def value(self, path: str, raw: bytes, kinds: dict[str, str]) -> object:
        kind = kinds.get(path, "bytes")
        if kind == "real":
            return struct.unpack("d" if len(raw) == 8 else "f", raw)[0]
        if kind in ("int", "uint", "u64"):
            return int.from_bytes(raw, sys.byteorder, signed=kind == "int")
        return raw.hex()

    def kinds(self, item: str) -> dict[str, str]:
        """{leaf path: kind} of an item."""
        out: dict[str, str] = {}
        for label, kind, size in self.items[item]:
            self._kinds(label, kind, size, out)
        return out

    def _kinds(self, path: str, kind: str, size: int, out: dict) -> None:
        if kind.startswith("struct:"):
            ssize, members = self.structs[kind[7:]]
            for i in range(size // ssize):
                prefix = path if size == ssize else f"{path}[{i}]"
                for member, _, msize, mkind in members:
                    self._kinds(f"{prefix}.{member}", mkind, msize, out)
            return
        unit = self.sizes.get(kind, size) or size
        count = size // unit
        for i in range(count):
            out[path if count == 1 else f"{path}[{i}]"] = kind


def show(value) -> str:
    if isinstance(value, float):
        return f"{value!r}"
    return str(value)


def headline(layout: Layout, item: str, data: bytes) -> str:
    """status, counts and angles of an analysis result, decoded."""
    leaves, kinds = layout.leaves(item, data), layout.kinds(item)

    def get(path):
        return layout.value(path, leaves[path], kinds) if path in leaves else None

    words = [f"status {get('status')}"]
    for count in ("n_roots", "n_equilibria", "n_singular", "n_unassembled", "n_uncertain"):
        if f"result.{count}" in leaves:
            words.append(f"{count} {get('result.' + count)}")
    n = get("result.n_roots")
    if isinstance(n, int) and 0 <= n <= 64:
        words.append("theta [" + ", ".join(f"{get(f'result.roots[{i}].theta'):.17g}"
                                           for i in range(n)) + "]")
    n = get("result.n_equilibria")
    if isinstance(n, int) and 0 <= n <= 32:
        dof = sum(1 for p in leaves if p.startswith("result.theta[")) // 32 or 2
        words.append("theta [" + ", ".join(
            "(" + ", ".join(f"{get(f'result.theta[{i * dof + k}]'):.17g}" for k in range(dof))
            + ")" for i in range(n)) + "]")
    return "; ".join(words)


# ---------------------------------------------------------------- building

class Compiler:
    """gcc over a thread pool, with objects cached by the hash of everything they depend on
    (so that files the two revisions share are compiled once)."""

    def __init__(self, cc: str, cache: Path, ar: str = "ar"):
        self.cc, self.cache, self.ar = cc, cache, ar
        cache.mkdir(parents=True, exist_ok=True)
        try:
            version = subprocess.run([cc, "--version"], capture_output=True, text=True,
                                     check=True).stdout
        except (OSError, subprocess.CalledProcessError) as error:
            raise Failure(f"cannot run {cc}: {error}")
        self.version = version
        self.compiled = self.reused = 0
        self.seconds = 0.0  # in the compiler and the linker
        self.lock = threading.Lock()
        self.locks: dict[str, threading.Lock] = {}

    def object(self, source: Path, includes: list[Path], flags: tuple[str, ...]) -> Path:
        key = hashlib.sha256()
        key.update(self.version.encode())
        key.update(repr((CFLAGS, flags)).encode())
        key.update(source.read_bytes())
        for folder in includes:
            for header in sorted(folder.glob("*.h")):
                key.update(header.name.encode() + b"\0" + header.read_bytes())
        target = self.cache / f"{source.stem}-{key.hexdigest()[:24]}.o"
        with self.lock:
            lock = self.locks.setdefault(target.name, threading.Lock())
        with lock:  # the same object wanted twice at once is compiled once
            if target.exists():
                with self.lock:
                    self.reused += 1
                return target
            partial = target.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
            command = [self.cc, *CFLAGS, *flags, *(f"-I{d}" for d in includes), "-c",
                       str(source), "-o", str(partial)]
            started = time.perf_counter()
            done = subprocess.run(command, capture_output=True, text=True)
            with self.lock:
                self.seconds += time.perf_counter() - started
            if done.returncode != 0:
                partial.unlink(missing_ok=True)
                raise BuildError(f"{' '.join(command)}\n{done.stderr}")
            os.replace(partial, target)
            with self.lock:
                self.compiled += 1
            return target

    def archive(self, objects: list[Path]) -> Path:
        """A static library of the objects (cached like them): an executable linked with it
        holds only the objects it uses, so that a change to a runtime file a library does not
        call leaves that library's executable byte for byte as it was."""
        key = hashlib.sha256("\0".join(o.name for o in objects).encode()).hexdigest()[:24]
        target = self.cache / f"libruntime-{key}.a"
        with self.lock:
            lock = self.locks.setdefault(target.name, threading.Lock())
        with lock:
            if target.exists():
                return target
            partial = target.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
            command = [self.ar, "rcsD", str(partial), *map(str, objects)]
            done = subprocess.run(command, capture_output=True, text=True)
            if done.returncode != 0:
                partial.unlink(missing_ok=True)
                raise BuildError(f"{' '.join(command)}\n{done.stderr}")
            os.replace(partial, target)
            return target

    def link(self, objects: list[Path], executable: Path) -> Path:
        command = [self.cc, *CFLAGS, *map(str, objects), "-lm", "-o", str(executable)]
        started = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True)
        with self.lock:
            self.seconds += time.perf_counter() - started
        if done.returncode != 0:
            raise BuildError(f"{' '.join(command)}\n{done.stderr}")
        return executable


class BuildError(RuntimeError):
    pass


class Failure(RuntimeError):
    """The comparison cannot be made (a revision that does not exist, no compiler...)."""


@dataclass
class Side:
    """One revision: its generated/ folder, label and where its builds go."""

    label: str
    generated: Path
    work: Path
    apis: dict[str, Api] = field(default_factory=dict)
    drivers: dict[str, Path] = field(default_factory=dict)
    items: dict[str, list[str]] = field(default_factory=dict)


def build(compiler: Compiler, side: Side, mechanism: str,
          build_name: str) -> tuple[Path, Layout, str]:
    """The driver's executable, its layout and the executable's hash."""
    folder = side.generated / mechanism
    runtime = side.generated / "runtime"
    flags = BUILDS[build_name]
    library = compiler.archive([compiler.object(c, [runtime], flags)
                                for c in sorted(runtime.glob("*.c"))])
    objects = [compiler.object(side.drivers[mechanism], [folder, runtime], flags)]
    objects += [compiler.object(c, [folder, runtime], flags) for c in sorted(folder.glob("*.c"))]
    executable = side.work / f"{mechanism}-{build_name.replace(' ', '-')}"
    compiler.link([*objects, library], executable)
    text = subprocess.run([str(executable), "layout"], capture_output=True, text=True,
                          check=True).stdout
    return executable, Layout.parse(text), hashlib.sha256(executable.read_bytes()).hexdigest()


# ---------------------------------------------------------------- parameter sets

def parameter_sets(apis: list[Api], sets: int, spread: float, seed: int) -> dict[str, list]:
    """{parameter name: [value per set]}: set 0 the example (of the first API naming it)."""
    columns: dict[str, list] = {}
    for api in apis:
        for p in api.spec["parameters"]:
            name = p["name"]
            if name in columns:
                continue
            example = float(p["example"])
            draw = random.Random(f"{seed}:{api.name}:{name}")
            column = [example]
            for _ in range(1, sets):
                u = draw.uniform(-spread, spread)
                if p.get("unit") == "rad":
                    column.append(math.pi - draw.uniform(0.0, 2.0 * math.pi))
                elif example == 0.0:
                    sign = -1.0 if draw.random() < 0.5 else 1.0
                    column.append(0.0 if draw.random() < 0.5 else sign * 10.0 ** u)
                else:
                    column.append(example * 10.0 ** u)
            columns[name] = column
    return columns


def write_sets(path: Path, api: Api, columns: dict[str, list], sets: int) -> None:
    order = api.parameters
    with path.open("wb") as f:
        for s in range(sets):
            f.write(struct.pack(f"{len(order)}d", *(columns[name][s] for name in order)))


# ---------------------------------------------------------------- comparing

@dataclass
class Outcome:
    mechanism: str
    build: str
    sets: int = 0
    identical: int = 0
    differing: list = field(default_factory=list)   # (set, [item...])
    items: list = field(default_factory=list)        # items compared
    notes: list = field(default_factory=list)
    details: list = field(default_factory=list)      # text per shown set
    error: str = ""
    same_executable: bool = False  # both revisions' executables identical: run once
    seconds: float = 0.0  # the drivers', both revisions, summed over their processes


def compare(outcome: Outcome, base: Side, tree: Side, a: Layout, b: Layout, ra: bytes,
            rb: bytes, columns: dict[str, list], show_sets: int) -> None:
    """Compares BASE's records ra (layout a) with the tree's rb (layout b) set by set: an
    item byte for byte where both lay it out alike, else field by field."""
    sets = outcome.sets
    common = [name for name in b.items if name in a.items]
    for name in a.items:
        if name not in b.items:
            outcome.notes.append(f"{name} only in {base.label}")
    for name in b.items:
        if name not in a.items:
            outcome.notes.append(f"{name} only in {tree.label}")
    same_layout = {name for name in common if a.items[name] == b.items[name]
                   and (a.structs == b.structs
                        or not any(k.startswith("struct:") for _, k, _ in a.items[name]))}
    for name in common:
        if name not in same_layout:
            fields_a = {re.sub(r"\[\d+\]", "[]", f) for f in a.kinds(name)}
            fields_b = {re.sub(r"\[\d+\]", "[]", f) for f in b.kinds(name)}
            only = [f"{', '.join(sorted(fields))} only in {label}" for fields, label in
                    ((fields_a - fields_b, base.label), (fields_b - fields_a, tree.label))
                    if fields]
            outcome.notes.append(f"{name}: layouts differ, the fields both have compared one "
                                 "by one" + (f" ({'; '.join(only)})" if only else ""))
    outcome.items = common
    sa, sb = a.spans(), b.spans()
    if len(ra) != a.record * sets or len(rb) != b.record * sets:
        outcome.error = "a driver wrote fewer bytes than its layout says"
        return
    if a == b and ra == rb:
        outcome.identical = sets
        return
    columns_order = tree.apis[outcome.mechanism].parameters
    for s in range(sets):
        record_a = ra[s * a.record:(s + 1) * a.record]
        record_b = rb[s * b.record:(s + 1) * b.record]
        differing = []
        for name in common:
            da = record_a[sa[name][0]:sa[name][1]]
            db = record_b[sb[name][0]:sb[name][1]]
            if name in same_layout:
                if da != db:
                    differing.append(name)
            else:
                la, lb = a.leaves(name, da), b.leaves(name, db)
                if any(la[p] != lb[p] for p in la if p in lb):
                    differing.append(name)
        if not differing:
            outcome.identical += 1
            continue
        outcome.differing.append((s, differing))
        if len(outcome.details) >= show_sets:
            continue
        text = [f"  set {s}: " + ", ".join(f"{n} = {columns[n][s]!r}" for n in columns_order)]
        for name in differing:
            da = record_a[sa[name][0]:sa[name][1]]
            db = record_b[sb[name][0]:sb[name][1]]
            la, lb = a.leaves(name, da), b.leaves(name, db)
            ka, kb = a.kinds(name), b.kinds(name)
            paths = [p for p in la if p in lb and la[p] != lb[p]]
            text.append(f"    {name}: {len(paths)} field(s) differ")
            if name in ("analyze", "isolate"):
                ha, hb = headline(a, name, da), headline(b, name, db)
                if ha == hb:
                    text.append(f"      both: {ha}")
                else:
                    text.append(f"      {base.label}: {ha}")
                    text.append(f"      {tree.label}: {hb}")
            for p in paths[:8]:
                text.append(f"      {p}: {show(a.value(p, la[p], ka))} -> "
                            f"{show(b.value(p, lb[p], kb))}")
            if len(paths) > 8:
                text.append(f"      ... and {len(paths) - 8} more")
        outcome.details.append("\n".join(text))


CHUNKS = 4  # each run split in this many processes, so that the pool ends evenly


def run_all(compiler: Compiler, base: Side, tree: Side, mechanisms: list[str],
            builds: list[str], sets: int, columns: dict[str, dict], jobs: int,
            show_sets: int, run_both: bool) -> list[Outcome]:
    """Builds every (revision, mechanism, build), runs each over the sets in CHUNKS
    processes, and compares each pair of runs as soon as both are complete. Where the two
    revisions' executables are byte for byte the same (nothing the library links differs)
    it runs once, unless run_both: the same program on the same input."""
    outcomes = {(m, b): Outcome(m, b, sets) for m in mechanisms for b in builds}
    sides = (base, tree)
    for side in sides:
        side.work.mkdir(parents=True, exist_ok=True)
        for m in mechanisms:
            write_sets(side.work / f"{m}.params", side.apis[m], columns[m], sets)
    # The largest libraries first: their compilations are the longest.
    size = {m: sum(f.stat().st_size for f in (tree.generated / m).glob("*.c")) for m in mechanisms}
    keys = sorted(((side, m, b) for m in mechanisms for b in builds for side in sides),
                  key=lambda k: (-size[k[1]], builds.index(k[2]), sides.index(k[0])))
    built: dict = {}
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {pool.submit(build, compiler, side, m, b): (side, m, b) for side, m, b in keys}
        for future, (side, m, b) in futures.items():
            try:
                built[side.label, m, b] = future.result()
            except (BuildError, subprocess.CalledProcessError) as error:
                outcomes[m, b].error = f"{side.label}: {error}"
        step = -(-sets // CHUNKS)
        runs, pending = {}, {}
        for m in mechanisms:
            for b in builds:
                outcomes[m, b].same_executable = not outcomes[m, b].error and not run_both \
                    and built[base.label, m, b][2] == built[tree.label, m, b][2]
        for side, m, b in keys:
            if outcomes[m, b].error or (side is tree and outcomes[m, b].same_executable):
                continue
            executable = built[side.label, m, b][0]
            for first in range(0, sets, step):
                out = side.work / f"{executable.name}.{first}.out"
                count = min(step, sets - first)
                future = pool.submit(run_driver, executable, side.work / f"{m}.params", out,
                                     first, count)
                runs[future] = (m, b)
                pending.setdefault((m, b), []).append((side, first, out, future))
        for future in as_completed(runs):
            m, b = runs[future]
            if (m, b) not in pending:  # compared already
                continue
            if not all(f.done() for _, _, _, f in pending[m, b]):
                continue
            chunks = pending.pop((m, b))
            outcome = outcomes[m, b]
            try:
                outcome.seconds = sum(f.result() for _, _, _, f in chunks)
                data = {side.label: b"".join(out.read_bytes() for s2, _, out, _ in
                                             sorted(chunks, key=lambda c: c[1]) if s2 is side)
                        for side in sides}
                if outcome.same_executable:
                    data[tree.label] = data[base.label]
            except BuildError as error:
                outcome.error = str(error)
            else:
                compare(outcome, base, tree, built[base.label, m, b][1],
                        built[tree.label, m, b][1], data[base.label], data[tree.label],
                        columns[m], show_sets)
            for _, _, out, _ in chunks:
                out.unlink(missing_ok=True)
    return [outcomes[m, b] for m in mechanisms for b in builds]


def run_driver(executable: Path, params: Path, out: Path, first: int, count: int) -> float:
    """Runs a driver over count sets from first; its CPU seconds."""
    started = time.perf_counter()
    done = subprocess.run([str(executable), str(params), str(out), str(first), str(count)],
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise BuildError(f"{executable} {first} {count} failed ({done.returncode}): "
                         f"{done.stderr}")
    return time.perf_counter() - started


def compare_trees(base: Path, tree: Path) -> tuple[list[str], list[str], list[str], int]:
    """Files only in base, only in tree, differing; and how many are identical."""
    def files(root: Path) -> set[str]:
        return {str(p.relative_to(root)) for p in root.rglob("*")
                if p.is_file() and not p.name.startswith(".") and p.suffix not in (".o", ".pyc")
                and "__pycache__" not in p.parts}
    a, b = files(base), files(tree)
    both = sorted(a & b)
    differing = [f for f in both if not filecmp.cmp(base / f, tree / f, shallow=False)]
    return sorted(a - b), sorted(b - a), differing, len(both) - len(differing)


# ---------------------------------------------------------------- main

def extract(rev: str, into: Path) -> Path:
    """BASE's generated/ (git archive) under into/generated."""
    try:
        tar = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", rev, "generated"],
                             capture_output=True, check=True).stdout
    except subprocess.CalledProcessError as error:
        raise Failure(f"git archive {rev} generated: "
                         f"{error.stderr.decode().strip()}")
    with tarfile.open(fileobj=io.BytesIO(tar)) as archive:
        if hasattr(tarfile, "data_filter"):
            archive.extractall(into, filter="data")
        else:  # Python < 3.12 without the backported filters
            archive.extractall(into)
    return into / "generated"


def mechanisms_of(generated: Path) -> set[str]:
    return {d.name for d in generated.iterdir() if d.is_dir() and d.name != "runtime"
            and (d / f"{d.name}.h").exists() and (d / f"{d.name}_api.json").exists()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--base", default="HEAD", help="the revision to compare with (HEAD)")
    where.add_argument("--base-dir", type=Path, help="a generated/ folder instead of --base")
    parser.add_argument("--tree", type=Path, default=ROOT / "generated",
                        help="the generated/ folder compared with BASE's (the working tree's)")
    parser.add_argument("--sets", type=int, default=2000, help="parameter sets per mechanism")
    parser.add_argument("--spread", type=float, default=1.0,
                        help="decades each parameter is drawn over either side of its example")
    parser.add_argument("--seed", type=int, default=49)
    parser.add_argument("--mechanisms", nargs="*", help="only these (default: every one)")
    parser.add_argument("--builds", nargs="*", choices=sorted(BUILDS), metavar="BUILD",
                        help=f"only these of {sorted(BUILDS)}")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--cc", default=os.environ.get("CC") or "gcc")
    parser.add_argument("--cache", type=Path, default=ROOT / "build" / "same-results" / "objects",
                        help="where compiled objects are kept, keyed by their inputs' hash")
    parser.add_argument("--show", type=int, default=3,
                        help="differing sets shown in detail per mechanism and build")
    parser.add_argument("--keep", type=Path, help="build in this folder and keep it")
    parser.add_argument("--run-both", action="store_true",
                        help="run both revisions' drivers even where their executables are "
                             "byte for byte the same (by default such a pair runs once)")
    args = parser.parse_args(argv)
    if args.sets < 1:
        parser.error("--sets must be at least 1")
    started = time.perf_counter()

    work = args.keep or Path(tempfile.mkdtemp(prefix="same-results-"))
    work.mkdir(parents=True, exist_ok=True)
    try:
        if args.base_dir:
            base_generated, base_label = args.base_dir.resolve(), str(args.base_dir)
        else:
            base_generated = extract(args.base, work / "base")
            base_label = args.base
        tree_generated = args.tree.resolve()
        for folder in (base_generated, tree_generated):
            if not (folder / "runtime").is_dir():
                raise Failure(f"{folder} has no runtime/: not a generated/ folder")
        base = Side(f"BASE ({base_label})", base_generated, work / "base-builds")
        tree = Side("tree", tree_generated, work / "tree-builds")
        print(f"same-results: BASE = {base_label} ({base_generated}), tree = {tree_generated}")

        only_base, only_tree, differing, identical = compare_trees(base_generated, tree_generated)
        print(f"\ngenerated/: {identical} files identical, {len(differing)} differ, "
              f"{len(only_base)} only in BASE, {len(only_tree)} only in the tree")
        for label, names in (("differs", differing), ("only in BASE", only_base),
                             ("only in the tree", only_tree)):
            for name in names:
                print(f"  {label}: {name}")

        in_base, in_tree = mechanisms_of(base_generated), mechanisms_of(tree_generated)
        for name in sorted(in_base - in_tree):
            print(f"  mechanism {name}: only in BASE, not compared")
        for name in sorted(in_tree - in_base):
            print(f"  mechanism {name}: only in the tree, not compared")
        mechanisms = sorted(in_base & in_tree)
        if args.mechanisms:
            unknown = set(args.mechanisms) - set(mechanisms)
            if unknown:
                raise Failure(f"not in both revisions: {sorted(unknown)}")
            mechanisms = [m for m in mechanisms if m in args.mechanisms]
        builds = args.builds or list(BUILDS)

        for side in (base, tree):
            side.work.mkdir(parents=True, exist_ok=True)
            for name in mechanisms:
                api = read_api(side.generated / name)
                source, items = driver_source(api)
                path = side.work / f"driver_{name}.c"
                path.write_text(source)
                side.apis[name], side.drivers[name], side.items[name] = api, path, items
        for name in mechanisms:
            for side in (base, tree):
                for note in side.apis[name].notes:
                    print(f"  {name} in {side.label}: {note}; not compared")
            pa, pb = base.apis[name].parameters, tree.apis[name].parameters
            if pa != pb:
                print(f"  {name}: parameters differ: BASE {pa}, tree {pb}")
        columns = {name: parameter_sets([tree.apis[name], base.apis[name]], args.sets,
                                        args.spread, args.seed) for name in mechanisms}

        compiler = Compiler(args.cc, args.cache)
        print(f"\n{len(mechanisms)} mechanisms x {len(builds)} builds x 2 revisions, "
              f"{args.sets} sets each ({args.cc} {' '.join(CFLAGS)}; {args.jobs} jobs; "
              f"seed {args.seed}, spread 10^+-{args.spread:g})", flush=True)
        outcomes = run_all(compiler, base, tree, mechanisms, builds, args.sets, columns,
                           args.jobs, args.show, args.run_both)
        compile_seconds, run_seconds = compiler.seconds, sum(o.seconds for o in outcomes)
        outcomes.sort(key=lambda o: (mechanisms.index(o.mechanism), builds.index(o.build)))
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)

    print(f"\n{'mechanism':<18} {'build':<16} {'sets':>6} {'identical':>9} {'differing':>9} "
          f"{'seconds':>8}  runs")
    failed = differs = False
    for o in outcomes:
        if o.error:
            failed = True
            print(f"{o.mechanism:<18} {o.build:<16} {'build or run failed':>26}")
            continue
        differs |= bool(o.differing)
        print(f"{o.mechanism:<18} {o.build:<16} {o.sets:>6} {o.identical:>9} "
              f"{len(o.differing):>9} {o.seconds:>8.1f}  {1 if o.same_executable else 2}")
    if any(o.same_executable for o in outcomes):
        print("  runs 1: both revisions' executables are byte for byte the same (nothing they "
              "link differs): run once (--run-both runs them twice)")
    seen, notes = set(), {}
    for o in outcomes:
        if o.mechanism not in seen and o.items:
            seen.add(o.mechanism)
            print(f"  {o.mechanism}: compared {', '.join(o.items)}")
        for note in o.notes:
            notes.setdefault((o.mechanism, note), []).append(o.build)
    for (mechanism, note), where in notes.items():
        print(f"  {mechanism} ({'every build' if len(where) == len(builds) else ', '.join(where)})"
              f": {note}")
    shown: dict = {}
    for o in outcomes:
        if o.error:
            print(f"\n{o.mechanism} ({o.build}) failed:\n{o.error}")
        if o.differing:
            same = shown.get((o.mechanism, repr(o.differing), repr(o.details)))
            if same:
                print(f"\n{o.mechanism} ({o.build}): the same {len(o.differing)} sets differ, "
                      f"the same fields, as in {same}")
                continue
            shown[o.mechanism, repr(o.differing), repr(o.details)] = o.build
            counts: dict[str, int] = {}
            for _, names in o.differing:
                for n in names:
                    counts[n] = counts.get(n, 0) + 1
            print(f"\n{o.mechanism} ({o.build}): {len(o.differing)} of {o.sets} sets differ "
                  "(" + ", ".join(f"{n} in {c}" for n, c in counts.items()) + "); "
                  f"the first {len(o.details)}, BASE -> tree:")
            for text in o.details:
                print(text)
    elapsed = time.perf_counter() - started
    print(f"\n{elapsed:.0f} s on {args.jobs} jobs; summed over processes: compiling and linking "
          f"{compile_seconds:.1f} s ({compiler.compiled} objects compiled, {compiler.reused} "
          f"reused from {args.cache}), the drivers {run_seconds:.1f} s")
    if failed:
        print("same-results: FAILED to build or run")
        return 2
    if differs:
        print("same-results: results DIFFER")
        return 1
    print("same-results: every result identical, bit for bit")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
    except Failure as failure:
        print(f"same_results: {failure}", file=sys.stderr)
        sys.exit(2)
    except Exception:  # a failure of the tool is no verdict on the results: exit 2, not 1
        import traceback
        traceback.print_exc()
        sys.exit(2)
