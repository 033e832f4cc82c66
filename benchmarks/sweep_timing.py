"""Section 10 of `make bench`: a sweep of many doughty sets from the command line to Parquet.

Issue 29's target: 10^6 sets, 2 workers, under TARGET s, timed as a user runs it: one new
process per run (start-up, the sampling, the analysis, the rows and the file included),
``python -m codegen sweep --sample N --vary F=0:200 --vary k=1000:3000 --seed 1 --workers 2
--out FILE.parquet``; the median of ``repeats`` runs after one warm-up run (run.median_seconds).
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

TARGET = 10.0          # [s] for TARGET_SETS sets
TARGET_SETS = 1_000_000
WORKERS = 2
VARY = ("F=0:200", "k=1000:3000")


def measure(mechanism: str, sets: int, repeats: int,
            median_seconds: Callable[[Callable[[], object], int], float]) -> dict[str, Any]:
    """The wall time of the command (``median_seconds`` over ``repeats`` runs), its rows and
    its file's size."""
    with tempfile.TemporaryDirectory(prefix="mechvib-sweep-") as tmp:
        out = Path(tmp) / "sweep.parquet"
        command = [sys.executable, "-m", "codegen", "sweep", "--mechanism", mechanism,
                   "--sample", str(sets), *(a for v in VARY for a in ("--vary", v)),
                   "--seed", "1", "--workers", str(WORKERS), "--out", str(out)]
        seconds = median_seconds(lambda: subprocess.run(command, check=True, capture_output=True),
                                 repeats)
        import pyarrow.parquet as pq

        rows = pq.ParquetFile(out).metadata.num_rows
        size = out.stat().st_size
    return {"sets": sets, "workers": WORKERS, "seconds": seconds, "sets_per_second": sets / seconds,
            "rows": rows, "file_mb": size / 1e6,
            "met": seconds < TARGET if sets == TARGET_SETS else None}
