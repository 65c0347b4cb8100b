"""``results/summary.csv``: every case's ``summary.json`` as one row (and the table writer the
study's ``study.csv`` shares)."""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Mapping, Sequence
from typing import Any

from .atomic import atomic_path

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


def write_csv(path: str | os.PathLike, columns: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> None:
    """``rows`` as a CSV table of ``columns`` (other keys left out, missing ones empty), atomically."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    with atomic_path(path) as tmp:
        tmp.write_text(buffer.getvalue())
