"""Decks we write are read by OPM Flow, and Flow computes our pore volumes and connections.

Needs ``flow`` (Debian ``libopm-simulators-bin``) on the PATH: ``make test`` installs it, and
a missing ``flow`` is a failure (tests/system_tools.py).
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest
from flow_tools import flow_executable, rest_of_deck

from gridlib import check_grid, compute_geometry
from gridlib.cornerpoint.between_horizons import FaultTrace, horizons_to_grdecl
from gridlib.cornerpoint.generators import make_model3, simple_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.egrid import read_egrid
from gridlib.io.grdecl import write_grdecl

WRAPPER = """\
-- minimal oil-water deck around {grid} (grid and initialisation tests only)
RUNSPEC
DIMENS
 {nx} {ny} {nz} /
OIL
WATER
{units}
TABDIMS
 1 1 20 20 /
EQLDIMS
 1 /
START
 1 'JAN' 2020 /
UNIFOUT
GRID
INIT
INCLUDE
 '{grid}' /
EQUALS
 'PERMX' 100.0 /
 'PERMY' 100.0 /
 'PERMZ' 10.0 /
/
{rest}"""


@pytest.fixture(scope="module")
def flow() -> str:
    return flow_executable()


def run_flow_on_grdecl(
    flow: str, grdecl, workdir, *, units: str = "METRIC", poro: float | None = None
) -> dict[str, np.ndarray]:
    """OPM Flow's dry run on a deck that INCLUDEs ``grdecl``; its EGRID and INIT arrays."""
    import resfo

    from gridlib.io.grdecl import read_grdecl

    workdir.mkdir(parents=True, exist_ok=True)
    deck = read_grdecl(grdecl)
    nx, ny, nz = deck.cart_dims
    finite = deck.zcorn[np.isfinite(deck.zcorn)]
    extra = "" if poro is None else f"EQUALS\n 'PORO' {poro} /\n/\n"
    text = WRAPPER.format(
        grid=Path(grdecl).resolve(),
        nx=nx,
        ny=ny,
        nz=nz,
        rest=rest_of_deck(finite.min(), finite.max() + 1),
        units=units,
    ).replace("EQUALS\n 'PERMX'", extra + "EQUALS\n 'PERMX'")
    (workdir / "CASE.DATA").write_text(text)
    out = workdir / "out"
    done = subprocess.run(
        [flow, "--enable-dry-run=true", "--threads-per-process=1", f"--output-dir={out}", "CASE.DATA"],
        cwd=workdir,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    arrays: dict[str, np.ndarray] = {}
    for name in ("CASE.EGRID", "CASE.INIT"):
        for kw, arr in resfo.read(out / name):
            arrays.setdefault(kw.strip(), np.asarray(arr))
    return arrays


def run_flow(flow: str, deck, cell_data: dict, tmp_path) -> dict[str, np.ndarray]:
    """Write ``deck`` + properties, let Flow initialise it, return its EGRID and INIT arrays."""
    write_grdecl(tmp_path / "grid.grdecl", deck, cell_data)
    return run_flow_on_grdecl(flow, tmp_path / "grid.grdecl", tmp_path)


def _fault_model():
    x, y = np.linspace(0.0, 2000.0, 21), np.linspace(0.0, 1500.0, 16)
    X, Y = np.meshgrid(x, y)
    top = 2000.0 + 0.02 * X + 30.0 * np.sin(Y / 400.0)
    faults = [
        FaultTrace([(950.0, -10.0), (1100.0, 1510.0)], throw=12.0, name="EAST"),
        FaultTrace([(-10.0, 700.0), (1300.0, 900.0)], throw=lambda s: 8.0 * (1.0 - s), name="TAPER"),
    ]
    horizons = [{"x": x, "y": y, "z": top}, {"x": x, "y": y, "z": top + 40.0 + 0.005 * X}]
    return horizons_to_grdecl(horizons, layers=5, faults=faults)


MODELS = {
    "make_model3": lambda: make_model3([20, 15, 6]),
    "simple_grdecl_sine": lambda: simple_grdecl(
        [12, 8, 4], lambda y: 4.0 * (np.sin(2 * np.pi * y / 800.0) - 0.5), phys_dims=(1000.0, 800.0, 40.0)
    ),
    "horizons_with_faults": _fault_model,
    # A throw growing along the fault meets other layers' depths at pillars (equal only up to
    # rounding there): Flow's NNCs are the exact geometry's, no connection where cells only touch.
    "simple_grdecl_linear": lambda: simple_grdecl([4, 3, 5], lambda y: 1 / 6 + 0.1 * y, flat=True),
}


@pytest.mark.parametrize("model", list(MODELS))
def test_flow_reads_our_deck_and_agrees_on_pore_volumes_and_nncs(flow, tmp_path, model):
    deck = MODELS[model]()
    rng = np.random.default_rng(1)
    poro = 0.1 + 0.25 * rng.random(deck.num_cells)
    ntg = 0.6 + 0.4 * rng.random(deck.num_cells)
    ref = run_flow(flow, deck, {"PORO": poro, "NTG": ntg}, tmp_path)

    ours = process_grdecl(deck)
    g = ours.grid
    check_grid(g, compute_geometry(g))
    flow_active = np.flatnonzero(ref["ACTNUM"] > 0)
    np.testing.assert_array_equal(g.cells.index_map, flow_active)
    porv = ref["PORV"].astype(np.float64)[flow_active]
    cells = g.cells.index_map
    np.testing.assert_allclose(ours.bulk_volumes * poro[cells] * ntg[cells], porv, rtol=1e-6)

    flow_nnc = set()
    if "NNC1" in ref:
        a, b = ref["NNC1"].astype(np.int64) - 1, ref["NNC2"].astype(np.int64) - 1
        flow_nnc = set(zip(np.minimum(a, b).tolist(), np.maximum(a, b).tolist(), strict=True))
    gc = np.sort(ours.nnc.global_cells, axis=1)
    assert set(map(tuple, gc.tolist())) == flow_nnc

    # And Flow's own EGRID, read back through read_egrid, processes to the same cells.
    (tmp_path / "out" / "CASE.EGRID").replace(tmp_path / "flow.EGRID")
    again = process_grdecl(read_egrid(tmp_path / "flow.EGRID"))
    np.testing.assert_array_equal(again.grid.cells.index_map, g.cells.index_map)
