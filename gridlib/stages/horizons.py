"""Stage ``horizons``: the case's horizons on their lattice, ordered, as ``horizons.nc``."""

from __future__ import annotations

import os

import numpy as np

from ..build import _axis
from ..config import load_case
from ..errors import InputError
from ..io.horizon_files import build_horizons, write_horizons
from .common import log


def case_horizons(case):
    """The horizons Dataset of a case (depth over (horizon, y, x), m, positive down)."""
    spec = case.data["horizons"]
    x, y = _axis(spec["lattice"]["x"]), _axis(spec["lattice"]["y"])
    specs = [dict(surface) for surface in spec["surfaces"]]  # files relative to the case file (base_dir)
    try:
        return build_horizons(
            specs,
            x,
            y,
            ordering=spec.get("ordering", "error"),
            faults=[f["trace"] for f in case.data.get("faults", [])] if spec.get("per_fault_block") else (),
            per_block=bool(spec.get("per_fault_block", False)),
            base_dir=case.path.parent,
            attrs=case.provenance(),
        )
    except InputError as exc:
        raise InputError(f"{case.path}: {exc}") from exc


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
