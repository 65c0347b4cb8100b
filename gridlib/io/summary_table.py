"""``results/summary.csv``: every case's ``summary.json`` as one row (and the table writer the
study's ``study.csv`` shares); the ``summary.json`` files read back."""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from .atomic import atomic_path
from .datasets import damaged

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


def read_summaries(paths: Sequence[str | os.PathLike]) -> list[dict[str, Any]]:
    """The ``summary.json`` files (each a JSON object), in order; one InputError naming the
    file that is missing, not UTF-8 JSON or not an object (:func:`~gridlib.io.datasets.damaged`)."""
    out = []
    for path in paths:
        try:
            summary = json.loads(Path(path).read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise damaged(path, "no such file") from None
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise damaged(path, f"not JSON: {exc}") from None
        if not isinstance(summary, dict) or "case" not in summary:
            raise damaged(path, "not a case's summary (a JSON object with 'case')")
        out.append(summary)
    return out
