"""Comparing two builds of a case: every variable and attribute of every netCDF file, the
GRDECL, VTU, VTP and ROFF files, summary.json, the OPM Flow deck with its includes (flow/*.DATA,
flow/*.INC) and the exchange files (exchange/*.gri, *.pol) must be identical (bit for bit).
Building a case without its pictures, for tests that read only those files."""

from __future__ import annotations

import copy
import dataclasses
import json
from pathlib import Path

import numpy as np
import xarray as xr

from gridlib.config import Case, load_case

COMPARED_SUFFIXES = (".nc", ".grdecl", ".vtu", ".vtp", ".json", ".roff")
DECK_SUFFIXES = (".DATA", ".INC")
EXCHANGE_SUFFIXES = (".gri", ".pol")


def compared_files(folder: Path) -> list[str]:
    """The case folder's artifacts and its Flow deck files, as paths relative to the folder."""
    names = [p.name for p in folder.iterdir() if p.suffix in COMPARED_SUFFIXES]
    if (folder / "flow").is_dir():
        names += [f"flow/{p.name}" for p in (folder / "flow").iterdir() if p.suffix in DECK_SUFFIXES]
    if (folder / "exchange").is_dir():
        names += [
            f"exchange/{p.name}" for p in (folder / "exchange").iterdir() if p.suffix in EXCHANGE_SUFFIXES
        ]
    return sorted(names)


# The provenance that names the case file a build came from (its path and SHA-256), and the
# file's digest, which covers every attribute (gridlib.io.datasets.DIGEST).
PROVENANCE_ATTRS = ("case_file", "case_sha256", "gridlib_digest")
PROVENANCE_LINES = (b"-- case file ", b"-- case sha256 ")


def _without_provenance(data: bytes) -> bytes:
    return b"\n".join(line for line in data.split(b"\n") if not line.startswith(PROVENANCE_LINES))


def assert_same_files(first: Path, second: Path, provenance: bool = True) -> list[str]:
    """Assert that the two case folders hold the same files with identical contents; returns
    the names compared. ``provenance=False``: two case files of the same content (e.g. a study's
    variant and the same case written by hand) may differ in the file's path and hash that the
    outputs record (netCDF attributes case_file and case_sha256, summary.json's case_sha256, the
    deck's "-- case file" and "-- case sha256" comment lines); everything else must be equal.
    The file names must be the same: give both cases the same name."""
    names = compared_files(first)
    assert names == compared_files(second), (first, second)
    for name in names:
        where = f"{first.name}/{name}"
        if name.endswith(".nc"):
            with xr.open_dataset(first / name) as a, xr.open_dataset(second / name) as b:
                assert sorted(a.variables) == sorted(b.variables), where
                assert a.attrs.keys() == b.attrs.keys(), where
                for key, value in a.attrs.items():
                    if not provenance and key in PROVENANCE_ATTRS:
                        continue
                    assert np.array_equal(value, b.attrs[key]), f"{where}: attribute {key}"
                for var in a.variables:
                    u, v = a[var].values, b[var].values
                    assert u.dtype == v.dtype and u.shape == v.shape, f"{where}: {var}"
                    same = u.tobytes() == v.tobytes() if u.dtype.kind != "O" else np.array_equal(u, v)
                    assert same, f"{where}: {var}: {np.count_nonzero(u != v)} of {u.size} values differ"
                    assert a[var].attrs.keys() == b[var].attrs.keys(), f"{where}: {var}"
        elif name.endswith(".json"):
            one, two = (json.loads((folder / name).read_text()) for folder in (first, second))
            if not provenance:
                for key in PROVENANCE_ATTRS:
                    one.pop(key, None), two.pop(key, None)
            assert one == two, where
        elif not provenance:
            one, two = ((folder / name).read_bytes() for folder in (first, second))
            assert _without_provenance(one) == _without_provenance(two), where
        else:
            assert (first / name).read_bytes() == (second / name).read_bytes(), where
    return names


def run_case_without_pictures(case: Case | str | Path, folder: str | Path) -> None:
    """gridlib.stages.run_case of ``case`` (loaded, or its file) into ``folder`` with
    ``outputs.pictures: false``: every other artifact, each of the compared files above
    included, is written as with the pictures (tests/stages/test_optional_pictures.py). The
    drawing is most of a small case's time, and the PNGs are checked by the tests of the
    pictures (tests/stages/test_pictures.py, test_workflow.py) instead."""
    from gridlib.stages import run_case

    loaded = case if isinstance(case, Case) else load_case(case)
    data = copy.deepcopy(loaded.data)
    data["outputs"]["pictures"] = False
    run_case(dataclasses.replace(loaded, data=data), folder)
