"""Stage ``horizons``: the case's horizons on their lattice, ordered, as ``horizons.nc``."""

from __future__ import annotations

import os

import numpy as np

from ..case.horizons import case_horizons
from ..config import load_case
from ..io.horizon_files import write_horizons
from .common import log


def stage_horizons(case_file: str | os.PathLike, horizons_out: str | os.PathLike) -> None:
    """Interpolate and order the case's horizons; write ``horizons.nc``."""
    case = load_case(case_file)
    ds = case_horizons(case)
    write_horizons(horizons_out, ds)
    depth = ds["depth"].values
    log.info(
        "wrote %s: %d horizons on %d x %d nodes, depths %.6g to %.6g m",
        horizons_out,
        depth.shape[0],
        depth.shape[2],
        depth.shape[1],
        np.nanmin(depth),
        np.nanmax(depth),
    )
