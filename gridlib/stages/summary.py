"""Stage ``summary``: every case's ``summary.json`` as one table, ``results/summary.csv``."""

from __future__ import annotations

import os
from collections.abc import Sequence

from ..io.summary_table import COLUMNS, read_summaries, write_csv
from .common import log


def stage_summary(summaries: Sequence[str | os.PathLike], csv_out: str | os.PathLike) -> None:
    """One row per case (sorted by name), the columns of COLUMNS (empty where not applicable)."""
    rows = read_summaries(summaries)
    rows.sort(key=lambda r: r["case"])
    write_csv(csv_out, COLUMNS, rows)
    log.info("wrote %s (%d cases)", csv_out, len(rows))
