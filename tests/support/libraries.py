"""The generated libraries the tests walk, by kind: one coordinate's (the polynomial and
isolation routes, sigma, the work entries) and several coordinates' (tests/runtime/test_multibody.py)."""
from __future__ import annotations

import json
from pathlib import Path


def generated_libraries(generated: Path, several: bool | None = None) -> list[str]:
    """The libraries of a generated/ folder; with ``several`` only those with several
    coordinates (True) or one (False)."""
    names = sorted(p.name for p in generated.iterdir() if (p / f"{p.name}_api.json").exists())
    if several is None:
        return names
    dof = {n: json.loads((generated / n / f"{n}_api.json").read_text()).get("dof", 1)
           for n in names}
    return [n for n in names if (dof[n] > 1) == several]
