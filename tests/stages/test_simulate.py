"""OPM Flow runs the decks gridlib writes, and uses gridlib's numbers and nothing else.

* the connection form of a faulted PEBI case and of a composite (radial + Cartesian) case,
  through Flow's dry run: Flow's pore volume of every cell is ours (through
  ``cell_flow_index``), and Flow's connections (TRANX/Y/Z, NNC/TRANNNC) are exactly ours,
  with our values, and no other (1e-6: INIT holds float32);
* a corner-point case simulated from its native deck (Flow's own transmissibilities, pore
  volumes, depths and well factors) and from the connection form (ours) gives the same well
  rates and pressures and field totals at every report step;
* the PEBI sample case runs to its last report step and conserves water, and its results'
  PVD lists every report step of the restart file with the restart's values per cell (pyvista;
  xtgeo reads the same EGRID/UNRST, as ResInsight would);
* a failed run names the case file and quotes Flow, and leaves nothing behind.

``make test`` installs Flow (its absence is a failure: tests/system_tools.py). The runs are small
(about 1,000 to 5,000 cells): the module takes some 40 s.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv
import resfo
import xarray as xr
import xtgeo
from artifacts import run_case_without_pictures
from flow_tools import flow_connections, flow_executable, read_keywords, run_flow_dry

from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.io.flow_results import read_fip_report, read_summary
from gridlib.io.netcdf import read_geometry_netcdf
from gridlib.stages.flow_deck import flow_deck_from_results
from gridlib.stages.simulate import run_flow, stage_simulate

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "config" / "cases"
# Tight solver tolerances where two runs are compared: the two forms' matrices are assembled in
# different orders, and Flow's defaults (linear reduction 1e-2, CNV 1e-2) leave differences of
# up to 6e-5 between runs of the same model; with these the runs agree to the last float32 bit.
TIGHT = (
    "--tolerance-cnv=1e-7",
    "--tolerance-mb=1e-10",
    "--linear-solver-reduction=1e-10",
    "--linear-solver-max-iter=1000",
    "--tolerance-wells=1e-9",
)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The sample cases the tests need, built once (run_case: the workflow's stages; no pictures), and a
    composite case: composite_wells with rock."""
    flow_executable()
    root = tmp_path_factory.mktemp("cases")
    composite = root / "composite_rock.yaml"
    text = (
        (CASES / "composite_wells.yaml").read_text().replace("name: composite_wells", "name: composite_rock")
    )
    text += (
        "petrophysics:\n"
        "  porosity:\n"
        "    field: {model: gaussian, len_scale: [3, 3, 1], mean: 0.25, std: 0.03, bounds: [0.1, 0.4]}\n"
        "  permeability: {carman_kozeny: {}}\n"
    )
    composite.write_text(text)
    folders = {}
    for case in (
        CASES / "faulted_pebi.yaml",
        composite,
        CASES / "waterflood_cp.yaml",
        CASES / "waterflood_pebi.yaml",
    ):
        folders[case.stem] = root / case.stem
        run_case_without_pictures(case, folders[case.stem])
    return folders


def prt_warnings(prt: Path) -> int:
    """The count of warnings in Flow's error summary at the end of its PRT file."""
    lines = [line.split() for line in prt.read_text().splitlines() if line.startswith("Warnings")]
    return int(lines[-1][1])


@pytest.mark.parametrize("case", ["faulted_pebi", "composite_rock"])
def test_flow_takes_our_pore_volumes_and_exactly_our_connections(built, case, tmp_path):
    folder = built[case]
    deck = folder / "flow" / f"{case.upper()}.DATA"
    text = deck.read_text()
    assert "-- form connections" in text and f"gridlib case '{case}'" in text and "case sha256 " in text
    result = run_flow_dry(deck, tmp_path / "dry")
    assert prt_warnings(Path(f"{result}.PRT")) == 0  # nothing about our grid
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        index, porv = ds["cell_flow_index"].values, ds["porv"].values
        cells, trans = ds["connection_cells"].values, ds["trans"].values
        dims = tuple(int(v) for v in ds.attrs["flow_dims"])
    init = read_keywords(Path(f"{result}.INIT"))
    egrid = read_keywords(Path(f"{result}.EGRID"))
    actnum = egrid["ACTNUM"] > 0 if "ACTNUM" in egrid else np.ones(int(np.prod(dims)), dtype=bool)
    assert actnum.sum() == index.size and actnum[index].all()  # every cell of ours, and no other
    flow_porv = init["PORV"].astype(np.float64)  # PORV is written for every cell of the box
    np.testing.assert_allclose(flow_porv[index], porv, rtol=1e-6)
    # Flow's cell centre depth (gravity, equilibration, wells) is ours: the centroid's depth
    depth = read_geometry_netcdf(folder / "geometry.nc").cell_centroids[:, 2]
    position = np.cumsum(actnum)[index] - 1  # INIT's DEPTH is per active cell
    np.testing.assert_allclose(init["DEPTH"].astype(np.float64)[position], depth, rtol=1e-7)  # float32
    nx, ny, _ = dims
    pairs = np.sort(index[cells], axis=1)
    step = pairs[:, 1] - pairs[:, 0]
    vanished = ~np.isin(step, [1, nx, nx * ny]) & (trans < 1e-6)  # Flow sets those to 0 (reported)
    ours = dict(zip(map(tuple, pairs[~vanished].tolist()), trans[~vanished].tolist(), strict=True))
    flow = flow_connections(result)
    positive = {p: v for p, v in flow.items() if v > 0}
    # a vanished NNC shows in TRANNNC as minus its value (Flow's zeroed total minus the NNC input)
    assert {p for p, v in flow.items() if v < 0} == set(map(tuple, pairs[vanished].tolist()))
    assert sorted(positive) == sorted(ours)
    both = sorted(ours)
    np.testing.assert_allclose([positive[p] for p in both], [ours[p] for p in both], rtol=1e-6)
    print(
        f"{case}: {len(ours)} connections equal to Flow's, {int(vanished.sum())} vanished, {index.size} cells"
    )


def _run(deck: Path, out: Path, options=()) -> Path:
    result = run_flow(deck, out, tuple(options))
    assert result.returncode == 0, result.stdout[-3000:]
    return out / deck.stem


def test_native_and_connection_forms_give_the_same_simulation(built, tmp_path):
    """waterflood_cp: Flow's own numbers (native) against ours (connections): every well's rates
    and bottom-hole pressure and the field oil and water totals, at every report step."""
    folder = built["waterflood_cp"]
    native = folder / "flow" / "WATERFLOOD_CP.DATA"
    assert "-- form native" in native.read_text()
    connections = flow_deck_from_results(folder, tmp_path / "connections", form="connections")
    assert connections.form == "connections" and connections.vanished.size == 0
    a = read_summary(_run(native, tmp_path / "native_out", TIGHT))
    b = read_summary(_run(connections.path, tmp_path / "connections_out", TIGHT))
    assert prt_warnings(tmp_path / "native_out" / "WATERFLOOD_CP.PRT") == 0
    assert prt_warnings(tmp_path / "connections_out" / "WATERFLOOD_CP.PRT") == 0
    np.testing.assert_array_equal(a.time[a.report], [90, 180, 360, 540, 720, 900])
    np.testing.assert_array_equal(b.time[b.report], a.time[a.report])
    keys = [("FOPT", ""), ("FWPT", ""), ("FWIT", ""), ("FOPR", ""), ("FWPR", "")]
    keys += [(k, w) for w in ("INJ", "PROD") for k in ("WOPR", "WWPR", "WWIR", "WBHP")]
    worst = 0.0
    for key in keys:
        x, y = a.values[key][a.report], b.values[key][b.report]
        np.testing.assert_allclose(y, x, rtol=1e-5, atol=1e-9 * np.abs(x).max(), err_msg=str(key))
        worst = max(worst, float(np.max(np.abs(y - x) / np.maximum(np.abs(x), 1e-30))))
    assert a.values[("WWPR", "PROD")][a.report][-1] > 100  # the water has broken through: a real test
    print(f"native vs connection form: largest relative difference {worst:.3g} over {len(keys)} vectors")


def test_the_pebi_case_runs_to_its_end_and_conserves_water(built):
    folder = built["waterflood_pebi"]
    deck = folder / "flow" / "WATERFLOOD_PEBI.DATA"
    outputs = {
        "summary": folder / "flow" / "summary.json",
        "wells": folder / "flow" / "waterflood_pebi_wells.png",
        "pvd": folder / "flow" / "waterflood_pebi_flow.pvd",
    }
    summary = stage_simulate(
        load_case(CASES / "waterflood_pebi.yaml"),
        flow_deck=deck,
        grid=folder / "grid.nc",
        transmissibility=folder / "transmissibility.nc",
        **{f"flow_{key}": path for key, path in outputs.items()},
    )
    assert summary.time[-1] == 900.0
    np.testing.assert_array_equal(summary.time[summary.report], [90, 180, 360, 540, 720, 900])
    prt = folder / "flow" / "WATERFLOOD_PEBI.PRT"
    assert prt_warnings(prt) == 0
    assert not list((folder / "flow").glob(".WATERFLOOD_PEBI.run-*"))
    # Flow 2022.10's "Originally in place" is the state after its first time step (summary row 0)
    fip = read_fip_report(prt)
    assert fip["days"] == 900.0
    first = 0
    np.testing.assert_allclose(summary["FWIP"][first], fip["original"]["water"], atol=0.5)
    injected = summary["FWIT"][-1] - summary["FWIT"][first]
    produced = summary["FWPT"][-1] - summary["FWPT"][first]
    change = fip["current"]["water"] - fip["original"]["water"]
    assert change > 1e5
    assert abs((injected - produced) - change) <= 1e-4 * change, (injected, produced, change)
    figures = json.loads(outputs["summary"].read_text())
    assert figures["simulated_days"] == 900.0 and figures["field"]["FWIT"] == 1500.0 * 900
    assert set(figures["wells"]) == {"INJ", "PROD"} and 0 < figures["oil_recovery"] < 1
    assert outputs["wells"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    check_result_series(outputs["pvd"], folder, summary)
    print(f"water injected - produced {injected - produced:.1f} sm3, change in place {change:.0f} sm3")


def check_result_series(pvd: Path, folder: Path, summary) -> None:
    """The PVD lists every report step of the restart file (its SEQNUMs and DOUBHEAD days: the
    initial state and the summary's report steps), and each of its VTUs, read with pyvista's
    PVDReader, holds the restart's PRESSURE and SWAT (resfo, float32 widened exactly) on the
    grid's cells in their order (through cell_flow_index and the EGRID's ACTNUM), their centroid
    depth, and elevation as z."""
    flow = folder / "flow" / "WATERFLOOD_PEBI"
    restart: list[dict] = []
    for keyword, value in resfo.read(f"{flow}.UNRST"):
        keyword = keyword.strip()
        if keyword == "SEQNUM":
            restart.append({"step": int(value[0])})
        elif keyword == "DOUBHEAD":
            restart[-1]["days"] = float(value[0])
        elif keyword in ("PRESSURE", "SWAT"):
            restart[-1][keyword.lower()] = np.asarray(value, dtype=np.float64)
    assert [r["step"] for r in restart] == list(range(7))
    days = [r["days"] for r in restart]
    assert days == [0.0, *summary.time[summary.report].tolist()] == [0, 90, 180, 360, 540, 720, 900]
    egrid = read_keywords(Path(f"{flow}.EGRID"))
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        index = ds["cell_flow_index"].values
    actnum = egrid["ACTNUM"] > 0 if "ACTNUM" in egrid else np.ones(int(index.max()) + 1, dtype=bool)
    position = np.cumsum(actnum)[index] - 1
    depth = read_geometry_netcdf(folder / "geometry.nc").cell_centroids[:, 2]
    reader = pv.PVDReader(pvd)
    assert reader.time_values == days
    assert [d.path for d in reader.datasets] == [
        f"waterflood_pebi_flow/waterflood_pebi_flow_{k:04d}.vtu" for k in range(7)
    ]
    for r in restart:
        reader.set_active_time_value(r["days"])
        mesh = reader.read()[0]
        assert set(mesh.cell_data) == {"pressure", "swat", "depth"}
        for key in ("pressure", "swat"):
            np.testing.assert_array_equal(mesh.cell_data[key], r[key][position], err_msg=f"{key} {r['days']}")
        np.testing.assert_array_equal(mesh.cell_data["depth"], depth)
        assert mesh.bounds[5] < 0 and np.isclose(mesh.bounds[4], -depth.max(), atol=30)  # z is elevation
    first, last = (reader.set_active_time_value(t) or reader.read()[0] for t in (0.0, 900.0))
    assert abs(first.cell_data["swat"].min() - 0.2) < 1e-6 and last.cell_data["swat"].max() > 0.5  # flooded
    assert "pressure [bar]" in pvd.read_text() and "swat [1]" in pvd.read_text()
    # What ResInsight opens (EGRID, INIT, UNRST), read by another reader of those formats (xtgeo):
    # the box grid of the connection form, our pore volumes, and at every report step the PVD's
    # pressure per cell
    box = xtgeo.grid_from_file(f"{flow}.EGRID")
    assert box.nactive == index.size
    porv = xtgeo.gridproperty_from_file(f"{flow}.INIT", fformat="init", name="PORV", grid=box)
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        ours = ds["porv"].values
    np.testing.assert_allclose(np.ma.getdata(porv.values).ravel(order="F")[index], ours, rtol=1e-6)  # float32
    props = xtgeo.gridproperties_from_file(
        f"{flow}.UNRST", fformat="unrst", names=["PRESSURE"], dates="all", grid=box
    )
    pressures = [np.ma.getdata(p.values).ravel(order="F")[index] for p in props]  # (i, j, k) -> linear
    assert len(pressures) == len(restart)
    for values, r in zip(pressures, restart, strict=True):
        np.testing.assert_array_equal(values, r["pressure"][position])


def test_a_failed_run_names_the_case_and_quotes_flow(built, tmp_path):
    folder = tmp_path / "broken"
    shutil.copytree(built["waterflood_pebi"] / "flow", folder)
    for produced in folder.glob("WATERFLOOD_PEBI.[!D]*"):  # leave the deck and its includes only
        if produced.suffix != ".INC":
            produced.unlink()
    deck = folder / "WATERFLOOD_PEBI.DATA"
    deck.write_text(deck.read_text().replace("\nPVTW\n", "\nPVTX\n 1 2 /\nPVTW\n"))  # a misspelt keyword
    outputs = {k: folder / f"out.{k}" for k in ("summary", "wells", "pvd")}
    before = sorted(p.name for p in folder.iterdir())
    with pytest.raises(InputError) as exc:
        stage_simulate(
            load_case(CASES / "waterflood_pebi.yaml"),
            flow_deck=deck,
            grid="unused",
            transmissibility="unused",
            **{f"flow_{key}": path for key, path in outputs.items()},
        )
    message = str(exc.value)
    assert message.startswith(
        f"{CASES / 'waterflood_pebi.yaml'}: simulation: WATERFLOOD_PEBI.DATA: OPM Flow ended with status"
    )
    assert "Unknown keyword: PVTX" in message, message
    assert sorted(p.name for p in folder.iterdir()) == before  # nothing left behind


def test_a_run_failing_after_flow_leaves_none_of_flows_files(built, tmp_path):
    """Flow runs to its end, then the results' PVD cannot be written (the grid file is missing):
    the one error names the grid file, and none of Flow's files (UNRST, EGRID, PRT...) joins the
    deck, as a failed run leaves them nowhere."""
    folder = tmp_path / "late"
    shutil.copytree(built["waterflood_cp"] / "flow", folder)
    for produced in folder.glob("WATERFLOOD_CP.[!D]*"):  # leave the deck and its includes only
        if produced.suffix != ".INC":
            produced.unlink()
    outputs = {
        k: folder / f"out_{k}.{suffix}"
        for k, suffix in (("summary", "json"), ("wells", "png"), ("pvd", "pvd"))
    }
    before = sorted(p.name for p in folder.iterdir())
    missing = tmp_path / "no_such_grid.nc"
    with pytest.raises(InputError, match=r"no_such_grid\.nc"):
        stage_simulate(
            load_case(CASES / "waterflood_cp.yaml"),
            flow_deck=folder / "WATERFLOOD_CP.DATA",
            grid=missing,
            transmissibility=built["waterflood_cp"] / "transmissibility.nc",
            **{f"flow_{key}": path for key, path in outputs.items()},
        )
    left = sorted(p.name for p in folder.iterdir() if not p.name.startswith("out_"))
    assert (
        left == before
    )  # the summary and picture written before are the stage's outputs, removed by its caller


def test_connections_below_flows_threshold_vanish_as_reported(tmp_path):
    """A synthetic connection form (cells missing from the box, boxes overlapping their
    neighbours before they are shrunk, tiny transmissibilities): Flow keeps every connection
    but the reported ones, and warns about nothing."""
    from test_flow_deck import SIM, layered_connection_grid

    from gridlib.io.flow import write_flow_deck

    flow_executable()
    from gridlib.io.flow import ConnectionGrid

    grid = layered_connection_grid(np.random.default_rng(8))
    pairs = np.sort(grid.index[grid.pairs], axis=1)
    neighbours = np.isin(pairs[:, 1] - pairs[:, 0], [1, grid.dims[0]])
    trans = grid.trans.copy()
    trans[np.flatnonzero(neighbours)[:3]] = 1e-9  # tiny, but between logical neighbours: kept
    grid = ConnectionGrid(**{**grid.__dict__, "trans": trans})
    deck = write_flow_deck(tmp_path, "synthetic", grid, SIM)
    vanished = np.zeros(trans.size, dtype=bool)
    vanished[deck.vanished] = True
    np.testing.assert_array_equal(vanished, (trans < 1e-6) & ~neighbours)
    assert vanished.sum() >= 3 and ((trans < 1e-6) & neighbours).sum() == 3
    result = run_flow_dry(deck.path, tmp_path / "dry")
    assert prt_warnings(Path(f"{result}.PRT")) == 0
    flow = flow_connections(result)
    assert {p for p, v in flow.items() if v > 0} == set(map(tuple, pairs[~vanished].tolist()))
    assert {p for p, v in flow.items() if v < 0} == set(map(tuple, pairs[vanished].tolist()))
    init = read_keywords(Path(f"{result}.INIT"))
    np.testing.assert_allclose(init["PORV"].astype(np.float64)[grid.index], grid.porv, rtol=1e-6)
    # the boxes overlapped before they were shrunk: Flow would have moved them down silently
    order = np.argsort(grid.index)  # INIT's DEPTH is per active cell, in index order
    np.testing.assert_allclose(init["DEPTH"].astype(np.float64), grid.depth[order], rtol=1e-7)


def test_the_water_preset_runs_single_phase(tmp_path):
    """The `water` preset: one phase, an injector at a rate and a producer at a BHP on a
    synthetic connection form; Flow runs it to the end and conserves water."""
    from test_flow_deck import layered_connection_grid

    from gridlib.io.flow import FlowWell, Simulation, write_flow_deck

    flow_executable()
    grid = layered_connection_grid(np.random.default_rng(3), missing=0)
    ncol = grid.dims[0]
    wells = (
        FlowWell("INJ", "injector", [0, ncol, 2 * ncol], 0.1, 0.0, [5.0, 5.0, 5.0], rate=50.0, bhp=400.0),
        FlowWell("PROD", "producer", [ncol - 1, 2 * ncol - 1], 0.1, 0.0, [5.0, 5.0], bhp=150.0),
    )
    sim = Simulation("water", 2000.0, 200.0, None, wells, (10.0, 20.0))
    deck = write_flow_deck(tmp_path, "water", grid, sim)
    text = deck.path.read_text()
    assert "\nWATER\n" in text and "\nOIL\n" not in text and "SWOF" not in text
    base = _run(deck.path, tmp_path / "out")
    assert prt_warnings(Path(f"{base}.PRT")) == 0
    summary = read_summary(base)
    assert summary.time[-1] == 20.0 and ("FOPT", "") not in summary.values
    fip = read_fip_report(Path(f"{base}.PRT"))
    injected = summary["FWIT"][-1] - summary["FWIT"][0]
    produced = summary["FWPT"][-1] - summary["FWPT"][0]
    change = fip["current"]["water"] - fip["original"]["water"]
    assert summary["FWIT"][-1] == 1000.0 and produced > 0
    assert abs((injected - produced) - change) <= 2.0  # the PRT's integers


def test_flow_runs_as_a_process_of_its_own_even_inside_a_slurm_job():
    """Inside a SLURM job Open MPI would have Flow join the job step through PMI and abort
    (tests/workflow/test_slurm.py simulates there): Flow's environment has no launcher variables."""
    from gridlib.stages.simulate import flow_environment

    job = {"PATH": "/usr/bin", "SLURM_JOB_ID": "7", "SLURM_STEP_ID": "0", "PMI_RANK": "0", "OMPI_MCA_x": "1"}
    assert flow_environment("/tmp/session", job) == {
        "PATH": "/usr/bin",
        "OMPI_MCA_ess_singleton_isolated": "1",
        "OMPI_MCA_pml": "ob1",
        "OMPI_MCA_orte_tmpdir_base": "/tmp/session",
    }
