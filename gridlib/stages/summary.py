"""Stage ``summary``: every case's ``summary.json`` as one table, ``results/summary.csv``."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence

from ..io.summary_table import COLUMNS, write_csv
from .common import log


def stage_summary(summaries: Sequence[str | os.PathLike], csv_out: str | os.PathLike) -> None:
    """One row per case (sorted by name), the columns of COLUMNS (empty where not applicable)."""
    rows = [json.loads(open(p, encoding="utf-8").read()) for p in summaries]
    rows.sort(key=lambda r: r["case"])
    write_csv(csv_out, COLUMNS, rows)
    log.info("wrote %s (%d cases)", csv_out, len(rows))
