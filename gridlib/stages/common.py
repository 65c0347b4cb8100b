"""What every stage shares: logging to the rule's log file, and files with provenance.

Every output is written atomically (a temporary file renamed into place, so a
failed stage leaves nothing) and carries the case's provenance: gridlib
version, case name, case file and its SHA-256, seed.
"""

from __future__ import annotations

import json
import logging
import os
import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..errors import GridError, InputError
from ..threads import ENV

log = logging.getLogger("gridlib.stages")


def run_logged(
    log_file: str | os.PathLike,
    stage: Callable[..., None],
    *args: Any,
    threads: int | None = None,
    outputs: Iterable[str | os.PathLike] = (),
    name: str | None = None,
) -> None:
    """Run a stage with gridlib's log (and any traceback) going to ``log_file``, on at most
    ``threads`` threads (a rule's ``threads``; see :mod:`gridlib.threads`); at the end the log
    gets the stage's wall time, its peak memory and the size of each of ``outputs``. ``name``
    names the stage in the log (default: the function's name). The thread count in the
    environment is restored at the end."""
    name = name or stage.__name__
    previous = os.environ.get(ENV)
    if threads is not None:
        os.environ[ENV] = str(max(1, int(threads)))
    Path(log_file).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_file, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
    root = logging.getLogger("gridlib")
    root.addHandler(handler)
    root.setLevel(logging.INFO)
    start = time.perf_counter()
    try:
        stage(*args)
        _log_costs(root, name, time.perf_counter() - start, outputs)
    except (InputError, GridError) as exc:  # the user's input: one message, no traceback
        root.error("%s failed: %s", name, exc)
        print(f"gridlib: {exc}", file=sys.stderr)
        raise SystemExit(1) from None
    except Exception as exc:  # a bug: the whole traceback, in the log and on stderr
        root.error("%s failed: %s", name, exc, exc_info=True)
        print(f"gridlib: {exc}", file=sys.stderr)
        raise
    finally:
        root.removeHandler(handler)
        handler.close()
        if previous is None:
            os.environ.pop(ENV, None)
        else:
            os.environ[ENV] = previous


def _log_costs(log: logging.Logger, name: str, seconds: float, outputs: Iterable[str | os.PathLike]) -> None:
    """What a stage cost: wall time, peak resident memory, and the bytes it wrote."""
    import resource

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: kibibytes
    sizes = [(Path(p), Path(p).stat().st_size) for p in outputs if Path(p).is_file()]
    log.info("%s: %.1f s, peak memory %.0f MiB", name, seconds, peak / 2**20)
    for path, size in sizes:
        log.info("  %s: %.1f MiB", path.name, size / 2**20)


def nnc_variables(nnc) -> dict[str, xr.DataArray]:
    """The NNC list as variables over an ``nnc`` dimension (cells of the grid, 0-based)."""
    if nnc is None:
        return {}
    return {
        "nnc_cells": xr.DataArray(nnc.cells, dims=("nnc", "two"), attrs={"long_name": "cell pair"}),
        "nnc_global_cells": xr.DataArray(
            nnc.global_cells,
            dims=("nnc", "two"),
            attrs={"long_name": "linear index of the cells (i fastest)"},
        ),
        "nnc_kind": xr.DataArray(
            np.asarray(nnc.kind, dtype=np.int8), dims=("nnc",), attrs={"flag_meanings": "fault pinch"}
        ),
        "nnc_face": xr.DataArray(
            nnc.face, dims=("nnc",), attrs={"long_name": "connecting face, -1 for pinch"}
        ),
    }


def read_extra(path: str | os.PathLike, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The variables ``names`` present in a netCDF file (missing ones are left out)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return {n: ds[n].values for n in names if n in ds.variables}


def length_of(path: str | os.PathLike, name: str) -> int:
    """The first dimension's length of variable ``name`` of a netCDF file, without reading it
    (an InputError naming the file if the variable is missing)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        if name not in ds.variables:
            raise InputError(f"{path}: {name}: missing")
        return int(ds[name].shape[0])


def check_same_cells(grid_nc: str | os.PathLike, num_cells: int, counts: dict[Any, int]) -> None:
    """Every stage file read beside ``grid_nc`` (keys of ``counts``: the file, or the file and
    variable) holds one value per cell of that grid; else an InputError naming both files."""
    for source, count in counts.items():
        if count != num_cells:
            raise InputError(
                f"{source}: {count} cells, but {grid_nc} has {num_cells} (stage files of different "
                "grids: build the case again)"
            )


def read_attrs(path: str | os.PathLike) -> dict[str, Any]:
    """Global attributes of a netCDF file, JSON lists decoded."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        attrs = dict(ds.attrs)
    return {key: _json_or_text(value) for key, value in attrs.items()}


def _json_or_text(value: Any) -> Any:
    """A JSON list or mapping attribute decoded; any other value (text that merely starts with
    a bracket included) as it is."""
    if not (isinstance(value, str) and value[:1] in "[{"):
        return value
    try:
        return json.loads(value)
    except json.JSONDecodeError:
        return value
