"""Stage ``horizons``: the case's horizons on their lattice, ordered, as ``horizons.nc``."""

from __future__ import annotations

import json
import os

import numpy as np

from ..case.horizons import case_horizons
from ..config import Case
from ..io.horizon_files import write_horizons
from .common import log


def stage_horizons(case: Case, *, horizons: str | os.PathLike) -> None:
    """Interpolate and order the case's horizons; write them to ``horizons`` (``horizons.nc``)."""
    ds = case_horizons(case)
    write_horizons(horizons, ds)
    for note in json.loads(ds.attrs.get("notes", "[]")):  # interpolation and ordering repairs
        log.info("note: %s", note)
    depth = ds["depth"].values
    log.info(
        "wrote %s: %d horizons on %d x %d nodes, depths %.6g to %.6g m",
        horizons,
        depth.shape[0],
        depth.shape[2],
        depth.shape[1],
        np.nanmin(depth),
        np.nanmax(depth),
    )
