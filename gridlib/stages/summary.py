"""Stage ``summary``: every case's ``summary.json`` as one table, ``results/summary.csv``."""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Mapping, Sequence
from typing import Any

from ..io.atomic import atomic_path
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
    write_csv(csv_out, COLUMNS, rows)
    log.info("wrote %s (%d cases)", csv_out, len(rows))


def write_csv(path: str | os.PathLike, columns: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> None:
    """``rows`` as a CSV table of ``columns`` (other keys left out, missing ones empty), atomically."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    with atomic_path(path) as tmp:
        tmp.write_text(buffer.getvalue())
