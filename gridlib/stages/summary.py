"""Stage ``summary``: every case's ``summary.json`` as one table, ``results/summary.csv``."""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Sequence

from ..io._atomic import atomic_path
from .common import log

COLUMNS = (
    "case",
    "grid_type",
    "griddim",
    "cells",
    "faces",
    "nodes",
    "total_volume",
    "total_bulk_volume",
    "pore_volume",
    "mean_porosity",
    "mean_permx",
    "fault_faces",
    "nnc",
    "coarse_blocks",
    "unit_system",
    "connections",
    "neighbor_connections",
    "fault_connections",
    "pinch_connections",
    "other_connections",
    "min_trans",
    "median_trans",
    "max_trans",
    "total_porv",
    "seed",
)


def stage_summary(summaries: Sequence[str | os.PathLike], csv_out: str | os.PathLike) -> None:
    """One row per case (sorted by name), the columns of COLUMNS (empty where not applicable)."""
    rows = [json.loads(open(p, encoding="utf-8").read()) for p in summaries]
    rows.sort(key=lambda r: r["case"])
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=COLUMNS, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    with atomic_path(csv_out) as tmp:
        tmp.write_text(buffer.getvalue())
    log.info("wrote %s (%d cases)", csv_out, len(rows))
