"""`mechvib params`: a mechanism's parameters with their units, meanings and example values."""
from __future__ import annotations

from . import common

EXAMPLES = """\
examples:
  {prog} params
  {prog} params --mechanism four_bar
  {prog} params --model my_model.py"""


def listing(library) -> str:
    """The parameter table: name, unit, example value, meaning; an angle's value in degrees,
    as the command line takes it."""
    import math

    from .report import paragraph

    rows = []
    for p in library.SPEC["parameters"]:
        value = p["example"]
        if p["unit"] == "rad":
            value = f"{math.degrees(float(value)):.10g} deg"
        rows.append((p["name"], p["unit"], value, p["description"]))
    widths = [max(len(r[i]) for r in rows + [("name", "unit", "example", "")]) for i in range(3)]
    head = ("name", "unit", "example", "meaning")
    lines = ["  ".join(f"{c:<{w}}" for c, w in zip(head[:3], widths)) + "  " + head[3]]
    lines += ["  ".join(f"{c:<{w}}" for c, w in zip(r[:3], widths)) + "  " + r[3] for r in rows]
    lines.append("")
    lines.append(paragraph("Give a value with --set NAME=VALUE, in the unit shown; an angle "
                           "(unit rad) in degrees, or with its unit: 90deg, 1.5708rad."))
    return "\n".join(line.rstrip() for line in lines)


def run(args) -> int:
    library = common.load_library(args)
    print(f"Parameters of {library.TITLE}:")
    print(listing(library))
    return 0


def add(verbs, prog: str) -> None:
    prm = common.verb(verbs, "params", "a mechanism's parameters: units, meanings, example "
                      "values", EXAMPLES, prog, run)
    common.mechanism_options(prm, None, model=True)
