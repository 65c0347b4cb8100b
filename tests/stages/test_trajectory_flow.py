"""Trajectory wells in OPM Flow decks, end to end (issue 26): the sample cases trajectories_cp
(native corner-point deck) and trajectories_pebi (connection form), each with a horizontal
producer and a deviated injector, built by the workflow's stages and simulated by Flow.

* the deck's WELSPECS and COMPDAT records are exactly those of wells.nc (cells through
  ``cell_flow_index``, factors to the last bit, directions, diameter and skin);
* Flow connects exactly those cells in that order with our factors and directions, and puts
  the first connection at the bottom-hole pressure's reference depth;
* both simulations run to day 900, the producer produces and the injector injects its rate;
  the two grids of the same reservoir give the same oil within 1 %;
* a box case's trajectory wells along x, y and z (one with a lateral: one well, its cells in
  MD order): Flow's own COMPDAT factor (item 8 defaulted) equals ours in wells.nc.

Three Flow runs (two simulations of about 1,400 and 1,900 cells, one step of a 72-cell box).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import resfo
import xarray as xr
import yaml
from flow_tools import flow_connection_factors, flow_executable

from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.io.flow_results import read_summary
from gridlib.io.wells_file import read_wells
from gridlib.stages import case_outputs, run_stage
from gridlib.stages.flow_deck import flow_deck_from_results, stage_flow_deck
from gridlib.stages.simulate import run_flow

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "config" / "cases"
SAMPLES = ("trajectories_cp", "trajectories_pebi")
FLOAT32 = 1e-6  # the restart file stores factors and depths as float32
DAYS = [90, 180, 360, 540, 720, 900]

# A box with trajectory wells along its axes: 6 x 5 columns of 100 x 80 m, 3 layers of 10 m;
# each well crosses whole cells (it starts and ends outside the grid).
BOX = {
    "name": "axisbox",
    "seed": 3,
    "horizons": {
        "lattice": {"x": {"start": 0, "stop": 600, "num": 7}, "y": {"start": 0, "stop": 400, "num": 6}},
        "surfaces": [
            {"name": "top", "plane": {"depth": 1000}},
            {"name": "base", "plane": {"depth": 1030}},
        ],
    },
    "wells": [
        {
            "name": "HX",
            "survey": {"head": [-50, 120, 1015], "stations": [[0, 90, 90], [700, 90, 90]]},
            # a lateral north from x = 350 (MD 400): one well, the shared cell once
            "branches": [{"survey": {"head": [350, 120, 1015], "stations": [[400, 90, 0], [700, 90, 0]]}}],
        },
        {
            "name": "HY",
            "survey": {"head": [250, -50, 1005], "stations": [[0, 90, 0], [500, 90, 0]]},
            "radius": 0.108,
            "skin": 1.5,
        },
        {"name": "VZ", "survey": {"head": [450, 360, 980], "stations": [[0, 0, 0], [70, 0, 0]]}},
    ],
    "grid": {"type": "cornerpoint", "dims": [6, 5], "layers": 3},
    "petrophysics": {
        "porosity": {"constant": 0.2},
        "permeability": {"field": {"model": "exponential", "len_scale": 200, "mean": 150, "std": 0.7}},
        "kv_kh": 0.2,
        "ntg": {"layers": [0.9, 0.7, 1.0]},
    },
    "simulation": {
        "initial": {"pressure": 100},
        "wells": [
            {"name": "HX", "type": "producer", "bhp": 50},
            {"name": "HY", "type": "producer", "bhp": 50},
            {"name": "VZ", "type": "injector", "rate": 100},
        ],
        "report_days": [1],
    },
}


# The stages a deck needs (not the exports: pictures, VTU, the case's netCDF).
DECK_STAGES = ("horizons", "grid", "geometry", "petrophysics", "transmissibility", "wells", "flow_deck")


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The two sample cases and the box, built by the workflow's stages up to the deck."""
    flow_executable()
    root = tmp_path_factory.mktemp("trajectories")
    box = root / "axisbox.yaml"
    box.write_text(yaml.safe_dump(BOX, sort_keys=False))
    folders = {}
    for path in (*(CASES / f"{name}.yaml" for name in SAMPLES), box):
        case = load_case(path)
        folders[case.name] = root / case.name
        paths = case_outputs(case.name, folders[case.name])
        for stage in DECK_STAGES:
            run_stage(stage, case, paths)
    return folders


@pytest.fixture(scope="module")
def simulated(built):
    """The two sample decks simulated by Flow: {case: the run's path without suffix}."""
    out = {}
    for name in SAMPLES:
        deck = built[name] / "flow" / f"{name.upper()}.DATA"
        result = run_flow(deck, built[name] / "run")
        assert result.returncode == 0, result.stdout[-3000:]
        out[name] = built[name] / "run" / name.upper()
    return out


def _expected_records(folder: Path) -> tuple[dict[str, list[str]], dict[str, str]]:
    """COMPDAT records and WELSPECS I J per well as wells.nc and transmissibility.nc say."""
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        index = ds["cell_flow_index"].values
        nx, ny, _ = (int(v) for v in ds.attrs["flow_dims"])
    compdat, heads = {}, {}
    for record in read_wells(folder / "wells.nc"):
        c = record.connections
        g = index[c.cell]
        i, j, k = g % nx + 1, g // nx % ny + 1, g // (nx * ny) + 1
        diameter = f"{2 * record.radius!r}".removesuffix(".0")
        skin = f"{record.skin!r}".removesuffix(".0")
        compdat[record.name] = [
            f" '{record.name}' {a} {b} {kk} {kk} 'OPEN' 1* {cf!r} {diameter} 1* {skin} 1* '{'XYZ'[d]}' /"
            for a, b, kk, cf, d in zip(i, j, k, c.factor.tolist(), c.direction, strict=True)
        ]
        heads[record.name] = f"{i[0]} {j[0]}"
    return compdat, heads


@pytest.mark.parametrize("name", SAMPLES)
def test_the_deck_completes_the_cells_of_wells_nc_with_its_factors(built, name):
    deck = (built[name] / "flow" / f"{name.upper()}.DATA").read_text()
    compdat, heads = _expected_records(built[name])
    lines = deck.splitlines()
    for well in ("I1", "P1H"):
        assert [line for line in lines if line.startswith(f" '{well}' ") and "'OPEN' 1* " in line] == compdat[
            well
        ]
        welspecs = [line for line in lines if line.startswith(f" '{well}' 'G' ")]
        assert len(welspecs) == 1 and welspecs[0].startswith(f" '{well}' 'G' {heads[well]} ")
        # the factors read back from the text are wells.nc's to the last bit
        factors = [float(line.split()[7]) for line in compdat[well]]
        record = {r.name: r for r in read_wells(built[name] / "wells.nc")}[well]
        np.testing.assert_array_equal(factors, record.connections.factor)
    assert len(compdat["P1H"]) >= 9 and len(compdat["I1"]) >= 5
    assert {line.split()[-2] for line in compdat["P1H"]} == {"'Y'"}  # the lateral runs north


def _restart_wells(case: Path) -> dict[str, dict[str, np.ndarray]]:
    """Per well from the first report step of ``case``.UNRST: ICON's 1-based I J K and direction
    (1, 2, 3: X, Y, Z), SCON's factor and depth, SWEL's reference depth."""
    first, seen = {}, 0
    for kw, value in resfo.read(f"{case}.UNRST"):
        kw = kw.strip()
        if kw == "SEQNUM":
            seen += 1
            if seen > 2:  # the initial state (no wells) and the first report step
                break
        first[kw] = np.asarray(value)
    head = first["INTEHEAD"]
    nwells, ncwmax, niconz, nsconz, nswelz = (int(head[i]) for i in (16, 17, 32, 33, 25))
    icon = first["ICON"].reshape(nwells, ncwmax, niconz)
    scon = first["SCON"].reshape(nwells, ncwmax, nsconz).astype(np.float64)
    swel = first["SWEL"].reshape(nwells, nswelz).astype(np.float64)
    zwel = [v.decode() if isinstance(v, bytes) else str(v) for v in first["ZWEL"]]
    names = [z.strip() for z in zwel[:: len(zwel) // nwells]]
    out = {}
    for w, name in enumerate(names):
        n = int((icon[w, :, 0] > 0).sum())
        out[name] = {
            "ijk": icon[w, :n, 1:4],
            "direction": icon[w, :n, 13],
            "factor": scon[w, :n, 0],
            "depth": scon[w, :n, 1],
            "reference": swel[w, 9],
        }
    return out


@pytest.mark.parametrize("name", SAMPLES)
def test_flow_connects_our_cells_with_our_factors_and_directions(built, simulated, name):
    flow = _restart_wells(simulated[name])
    compdat, _ = _expected_records(built[name])
    deck = (built[name] / "flow" / f"{name.upper()}.DATA").read_text()
    for well, records in compdat.items():
        ours = np.array([r.split()[1:4] for r in records], dtype=np.int64)
        np.testing.assert_array_equal(flow[well]["ijk"], ours)  # Flow kept the order (COMPORD INPUT)
        directions = ["XYZ".index(r.split()[-2].strip("'")) + 1 for r in records]
        np.testing.assert_array_equal(flow[well]["direction"], directions)
        factors = np.array([float(r.split()[7]) for r in records])
        np.testing.assert_allclose(flow[well]["factor"], factors, rtol=FLOAT32)
        reference = float(re.search(rf"^ '{well}' 'G' \d+ \d+ (\S+) ", deck, re.M).group(1))
        # the reference depth is where Flow puts the first connection, and Flow took it
        np.testing.assert_allclose([flow[well]["reference"], flow[well]["depth"][0]], reference, rtol=FLOAT32)


def test_both_grids_simulate_the_horizontal_producer_to_the_end(simulated):
    runs = {name: read_summary(simulated[name]) for name in SAMPLES}
    for name, s in runs.items():
        np.testing.assert_array_equal(s.time[s.report], DAYS)
        assert (s.values[("WOPR", "P1H")][s.report] > 500).all(), name  # sm3/day at every report
        np.testing.assert_allclose(s.values[("WWIR", "I1")][s.report], 1500.0)  # the target rate held
        assert s.values[("WWPR", "P1H")][s.report][-1] > 100, name  # the water has broken through
        prt = Path(f"{simulated[name]}.PRT").read_text().splitlines()
        assert [line.split()[1] for line in prt if line.startswith("Warnings")][-1] == "0"
    cp, pebi = runs["trajectories_cp"], runs["trajectories_pebi"]
    for key in (("FOPT", ""), ("WOPR", "P1H")):
        a, b = cp.values[key][cp.report], pebi.values[key][pebi.report]
        assert abs(b[0] - a[0]) <= 0.01 * a[0] and abs(b[-1] - a[-1]) <= 0.03 * a[-1], (key, a, b)
    for name, s in runs.items():
        oil, water = s.values[("WOPR", "P1H")][s.report], s.values[("WWPR", "P1H")][s.report]
        rates = ", ".join(
            f"day {t:g}: oil {o:.0f} water {w:.0f}"
            for t, o, w in zip(s.time[s.report], oil, water, strict=True)
        )
        print(f"{name}: P1H {rates} sm3/day; FOPT {s.values[('FOPT', '')][-1]:.0f} sm3")


def test_flows_own_factors_of_axis_aligned_trajectories_are_ours(built, tmp_path):
    """The box's deck with every COMPDAT factor defaulted: Flow computes Peaceman's in the
    record's direction from its own grid; ours (wells.nc: the pieces along the cell axes) are
    the same."""
    folder = built["axisbox"]
    deck = folder / "flow" / "AXISBOX.DATA"
    text = deck.read_text()
    defaulted = re.sub(r"^( '\w+' \d+ \d+ \d+ \d+ 'OPEN' 1\*) \S+ ", r"\1 1* ", text, flags=re.M)
    assert defaulted.count("'OPEN' 1* 1* ") == text.count("'OPEN' 1* ") > 10
    copy = tmp_path / "deck" / "AXISBOX.DATA"
    copy.parent.mkdir()
    for entry in deck.parent.iterdir():
        (copy.parent / entry.name).symlink_to(entry)
    copy.unlink()
    copy.write_text(defaulted)
    flow = flow_connection_factors(copy, tmp_path / "run")
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        index = ds["cell_flow_index"].values
    nx, ny = 6, 5
    # per well: its cells' 0-based (i, j, k) in MD order of first entry and directions; HX: the
    # main path along x through row 1 (entering column i at MD 50 + 100 i), its lateral along y
    # from MD 400 in column 3 (the cell it shares with the main path; row j from MD 280 + 80 j)
    main, lateral = [(i, 1, 1) for i in range(6)], [(3, j, 1) for j in (2, 3, 4)]
    expected = {
        "HX": (
            [*main[:4], lateral[0], main[4], lateral[1], main[5], lateral[2]],
            [0, 0, 0, 0, 1, 0, 1, 0, 1],
        ),
        "HY": ([(2, j, 0) for j in range(5)], [1] * 5),
        "VZ": ([(4, 4, k) for k in range(3)], [2] * 3),
    }
    for record in read_wells(folder / "wells.nc"):
        c = record.connections
        cells, directions = expected[record.name]
        np.testing.assert_array_equal(index[c.cell], [i + nx * (j + ny * k) for i, j, k in cells])
        np.testing.assert_array_equal(c.direction, directions)
        theirs = np.array([flow[(record.name, int(g))] for g in index[c.cell]])
        whole = index[c.cell] != 3 + nx * (1 + ny)  # but the cell both of HX's paths complete
        np.testing.assert_allclose(theirs[whole], c.factor[whole], rtol=FLOAT32, err_msg=record.name)
        # there ours adds the lateral's 40 m along y in parallel to Flow's factor of the x crossing
        assert (c.factor[~whole] > 1.1 * theirs[~whole]).all()


def test_the_connection_form_of_the_corner_point_case_has_the_same_wells(built, tmp_path):
    """``gridlib flow-deck --form connections`` of trajectories_cp: the same WELSPECS and
    COMPDAT records as the native deck (our factors in both forms); without wells.nc the
    stage names the well that needs it."""
    folder = built["trajectories_cp"]
    case_file = CASES / "trajectories_cp.yaml"
    written = flow_deck_from_results(folder, tmp_path, form="connections", case_file=case_file)
    assert written.form == "connections"

    def wells(text: str) -> list[str]:
        return [line for line in text.splitlines() if line.startswith((" 'I1' ", " 'P1H' "))]

    native = wells((folder / "flow" / "TRAJECTORIES_CP.DATA").read_text())
    assert wells(written.path.read_text()) == native and len(native) == 2 + 2 + 17 + 2
    paths = case_outputs("trajectories_cp", folder)
    inputs = {key: paths[key] for key in ("grid", "geometry", "petrophysics", "transmissibility", "grdecl")}
    with pytest.raises(InputError) as exc:
        stage_flow_deck(load_case(case_file), **inputs, flow_deck=tmp_path / "x" / "TRAJECTORIES_CP.DATA")
    assert str(exc.value) == (
        f"{case_file}: simulation.wells[0].name: well 'I1' has a trajectory: its deck needs wells.nc "
        "(the stage 'wells')"
    )


def test_the_pebi_cells_along_the_lateral_are_centred_on_it(built):
    """trajectories_pebi: away from the path's ends, the cells of P1H's lateral (a straight line
    in plan view) have their areal centroids at their sites to 1e-9 of the 60 m cell size (the
    mirrored side rows make each path cell symmetric about the path), and those sites lie on
    the lateral within the millimetre the trajectory file is printed to; the grid passes
    check_grid."""
    from gridlib.checks import check_grid
    from gridlib.geometry import compute_geometry
    from gridlib.io.netcdf import read_netcdf

    folder = built["trajectories_pebi"]
    data = read_netcdf(folder / "grid.nc")
    grid = data.grid
    check_grid(grid)
    areal = grid.layering.areal
    centroids = compute_geometry(areal).cell_centroids[:, :2]
    record = {r.name: r for r in read_wells(folder / "wells.nc")}["P1H"]
    c = record.connections
    a, b = c.entry[0, :2], c.exit[-1, :2]  # the lateral's ends in plan view
    length = np.hypot(*(b - a))
    along = (b - a) / length
    assert np.unique(data.cell_data["well"][c.cell]).size == 1  # every connected cell is P1H's
    columns = grid.layering.column[c.cell]
    sites = data.cell_data["site"][c.cell]
    offset = sites - a
    t = offset @ along
    inner = (t > 2 * 60.0) & (t < length - 2 * 60.0)  # two cells from each end
    assert inner.sum() >= 4
    np.testing.assert_array_less(np.abs(offset[inner] @ np.array([along[1], -along[0]])), 2e-3)
    np.testing.assert_array_less(np.hypot(*(centroids[columns[inner]] - sites[inner]).T), 1e-9 * 60.0)
