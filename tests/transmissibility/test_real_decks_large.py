"""SPE 10 model 2 (1,122,000 cells given by DX/DY/DZ/TOPS) against OPM Flow 2022.10's dry run.

The deck is OPM's (tests/data/decks/spe10model2: FIELD units, OLDTRAN, five wells). Its
porosity and permeability files (tens of MB of text) are not vendored: the test writes a
seeded stand-in with the same layout. It is a module of its own because Flow's dry run of
a million cells takes 35-65 s and 5 GB here: under ``make test`` (pytest-xdist, a module
per worker) it runs beside the rest (tests/conftest.py starts it first).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from real_decks import (
    check_active_cells,
    check_connections,
    check_pore_volumes,
    check_transmissibilities,
    compare,
    unpack,
)


def spe10_model2(work: Path) -> Path:
    """The deck with a stand-in for its PHI and PERM include files: PORO uniform in [0.05,
    0.35] (Tarbert, layers 1-35) or [0, 0.3] with 3% exact zeros (Ness, layers 36-85);
    PERMX = PERMY lognormal, PERMZ 0.05-0.3 of PERMX (mD)."""
    root = unpack("spe10model2", work)
    nx, ny, nz = 60, 220, 85
    n = nx * ny * nz
    rng = np.random.default_rng(10)
    ness = np.repeat(np.arange(nz), nx * ny) >= 35
    poro = np.where(ness, rng.uniform(0.0, 0.3, n), rng.uniform(0.05, 0.35, n))
    poro[ness & (rng.random(n) < 0.03)] = 0.0
    permx = np.exp(rng.normal(np.where(ness, 1.0, 3.0), 2.0, n))
    permz = permx * rng.uniform(0.05, 0.3, n)
    _write_arrays(root / "SPE10MODEL2_PHI.INC", {"PORO": poro})
    _write_arrays(root / "SPE10MODEL2_PERM.INC", {"PERMX": permx, "PERMY": permx, "PERMZ": permz})
    return root / "SPE10_MODEL2.DATA"


def _write_arrays(path: Path, arrays: dict[str, np.ndarray]) -> None:
    with path.open("w") as f:
        for name, values in arrays.items():
            f.write(f"{name}\n")
            np.savetxt(f, values.reshape(-1, 6), fmt="%.6g")
            f.write("/\n")


@pytest.fixture(scope="module")
def comparison(tmp_path_factory):
    work = tmp_path_factory.mktemp("spe10_model2")
    return compare("spe10_model2", spe10_model2(work / "deck"), work / "flow")


def test_active_cells_equal_flow(comparison):
    check_active_cells(comparison)


def test_connections_equal_flow(comparison):
    check_connections(comparison)


def test_transmissibilities_equal_flow(comparison):
    check_transmissibilities(comparison)


def test_pore_volumes_equal_flow(comparison):
    check_pore_volumes(comparison)
