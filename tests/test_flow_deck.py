"""gridlib.io.flow without the simulator: the connection form's text reads back exactly, its
boxes keep every cell's centre depth without overlapping, bad input is refused before any
file is written; the case's `simulation` section is checked when the case is read; the
cells a vertical well crosses."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import gridlib as gl
from gridlib.completions import points_in_polygons, vertical_well_cells
from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.io.flow import ConnectionGrid, FlowWell, Simulation, box_depths, write_flow_deck
from gridlib.io.grdecl import read_grdecl


def layered_connection_grid(rng: np.random.Generator, ncol: int = 40, nlay: int = 4, missing: int = 10):
    """Cells of a (ncol, 1, nlay) box, some missing, with random depths ordered down each column,
    thick enough to overlap their neighbours, and random connections."""
    full = np.arange(ncol * nlay)
    index = np.sort(rng.choice(full, full.size - missing, replace=False))
    k = index // ncol
    depth = 2000.0 + 10.0 * k + rng.uniform(-3.0, 3.0, index.size) + 0.01 * (index % ncol)
    n = index.size
    pairs = np.unique(np.sort(rng.integers(0, n, (3 * n, 2)), axis=1), axis=0)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    trans = rng.lognormal(0.0, 2.0, pairs.shape[0])
    trans[:5] = 1e-9  # tiny ones
    return ConnectionGrid(
        dims=(ncol, 1, nlay),
        index=index,
        porv=rng.uniform(10.0, 1000.0, n),
        depth=depth,
        thickness=rng.uniform(5.0, 30.0, n),
        poro=rng.uniform(0.1, 0.3, n),
        permeability=rng.uniform(1.0, 500.0, (n, 3)),
        pairs=pairs,
        trans=trans,
        spacing=25.0,
    )


SIM = Simulation("oil-water", 2000.0, 200.0, 2030.0, (), (30.0, 60.0))


def test_connection_form_reads_back_exactly(tmp_path):
    rng = np.random.default_rng(4)
    grid = layered_connection_grid(rng)
    well = FlowWell("P1", "producer", grid.index[:2], 0.1, 0.0, [1.5, 2.25], bhp=150.0)
    sim = Simulation("oil-water", 2000.0, 200.0, 2030.0, (well,), (30.0, 60.0))
    deck = write_flow_deck(tmp_path, "case", grid, sim, header=["provenance line"])
    assert deck.path == tmp_path / "CASE.DATA" and deck.form == "connections"
    assert sorted(p.name for p in deck.files) == [
        "CASE.DATA",
        "CASE_GRID.INC",
        "CASE_NNC.INC",
        "CASE_PORV.INC",
    ]
    text = deck.path.read_text()
    assert text.startswith("-- provenance line\n")
    for keyword in ("RUNSPEC", "GRID", "EDIT", "PROPS", "SOLUTION", "SUMMARY", "SCHEDULE"):
        assert f"\n{keyword}\n" in text
    assert (
        text.index("\nGRID\n") < text.index("\nEDIT\n") < text.index("\nPROPS\n") < text.index("\nSCHEDULE\n")
    )
    compdat = [line for line in text.splitlines() if line.startswith(" 'P1' ") and "'Z' /" in line]
    g0, g1 = (int(v) for v in grid.index[:2])
    assert compdat == [
        f" 'P1' {g0 % 40 + 1} 1 {g0 // 40 + 1} {g0 // 40 + 1} 'OPEN' 1* 1.5 0.2 1* 0 1* 'Z' /",
        f" 'P1' {g1 % 40 + 1} 1 {g1 // 40 + 1} {g1 // 40 + 1} 'OPEN' 1* 2.25 0.2 1* 0 1* 'Z' /",
    ]
    nx, ny, nz = grid.dims
    (tmp_path / "WRAP.GRDECL").write_text(
        f"DIMENS\n {nx} {ny} {nz} /\nINCLUDE\n 'CASE_GRID.INC' /\nINCLUDE\n 'CASE_NNC.INC' /\n"
    )
    back = read_grdecl(tmp_path / "WRAP.GRDECL")
    assert back.cart_dims == (nx, ny, nz)
    active = np.zeros(nx * ny * nz, dtype=bool)
    active[grid.index] = True
    np.testing.assert_array_equal(back.active, active)
    np.testing.assert_array_equal(back.cell_data["PORO"][grid.index], grid.poro)
    np.testing.assert_array_equal(back.cell_data["PERMZ"][grid.index], grid.permeability[:, 2])
    assert (back.cell_data["MULTX"] == 0).all() and (back.cell_data["MULTZ"] == 0).all()
    tops, dz = box_depths(grid)
    z = back.zcorn_array().reshape(nz, 2, ny, 2, nx, 2)  # the boxes' corners (read_grdecl's COORD/ZCORN)
    np.testing.assert_array_equal(z[:, 0, :, 0, :, 0].ravel(), tops)
    np.testing.assert_array_equal(z[:, 1, :, 1, :, 1].ravel(), tops + dz)
    # the NNC records: every pair with its exact value, 1-based I J K of the Flow cells
    nnc = back.nnc_keyword
    g = np.sort(grid.index[grid.pairs], axis=1)
    np.testing.assert_array_equal(np.sort(nnc.cells, axis=1), g)
    np.testing.assert_array_equal(nnc.values, grid.trans)
    porv = (tmp_path / "CASE_PORV.INC").read_text()
    assert porv.count("PORV") == 1
    # the tiny non-neighbour connections Flow will drop are reported
    step = g[:, 1] - g[:, 0]
    expected = np.flatnonzero(~np.isin(step, [1, nx, nx * ny]) & (grid.trans < 1e-6))
    np.testing.assert_array_equal(deck.vanished, expected)
    assert "vanish" in deck.notes[0] and f"{expected.size} of them" in (tmp_path / "CASE_NNC.INC").read_text()


def test_trajectory_wells_get_one_compdat_record_per_connection(tmp_path):
    """A trajectory well (directions, factors, reference depth) beside a vertical well whose
    records are today's (native form: Flow's factor, 'Z'): WELSPECS at the first connection's
    I J, COMPORD INPUT, COMPDAT in the order given with each connection's factor and axis."""
    deck = gl.simple_grdecl([4, 3, 2], flat=True, phys_dims=(400.0, 300.0, 20.0))
    rock = {"PORO": np.full(24, 0.2), "PERMX": np.full(24, 100.0)}
    deck = replace(deck, zcorn=deck.zcorn + 1000.0, cell_data=rock, units="METRIC")
    vertical = FlowWell("V", "injector", [5, 17], 0.1, rate=100.0, bhp=300.0)
    # 0-based rows in MD order: I J K (2, 1, 2) to (4, 1, 2) along x, then to (4, 3, 2) along y
    cells = [13, 14, 15, 19, 23]
    factors = [12.5, 20.25, 7.0, 3.0000000000000004, 1e-3]
    horizontal = FlowWell(
        "H1",
        "producer",
        cells,
        0.108,
        1.5,
        factors,
        bhp=150.0,
        directions=[0, 0, 1, 1, 2],
        reference_depth=1012.5,
    )
    sim = Simulation("oil-water", 1000.0, 200.0, 1030.0, (vertical, horizontal), (30.0,))
    text = write_flow_deck(tmp_path, "traj", deck, sim).path.read_text().splitlines()
    welspecs = text.index("WELSPECS")
    assert text[welspecs + 3 : welspecs + 6] == [
        " 'V' 'G' 2 2 1* 'WATER' /",
        " 'H1' 'G' 2 1 1012.5 'OIL' /",
        "/",
    ]
    compord = text.index("COMPORD")
    assert text[compord + 2 : compord + 5] == [" 'V' 'INPUT' /", " 'H1' 'INPUT' /", "/"]
    compdat = text.index("COMPDAT")
    assert text[compdat + 3 : compdat + 11] == [
        " 'V' 2 2 1 1 'OPEN' 1* 1* 0.2 1* 0 1* 'Z' /",
        " 'V' 2 2 2 2 'OPEN' 1* 1* 0.2 1* 0 1* 'Z' /",
        " 'H1' 2 1 2 2 'OPEN' 1* 12.5 0.216 1* 1.5 1* 'X' /",
        " 'H1' 3 1 2 2 'OPEN' 1* 20.25 0.216 1* 1.5 1* 'X' /",
        " 'H1' 4 1 2 2 'OPEN' 1* 7.0 0.216 1* 1.5 1* 'Y' /",
        " 'H1' 4 2 2 2 'OPEN' 1* 3.0000000000000004 0.216 1* 1.5 1* 'Y' /",
        " 'H1' 4 3 2 2 'OPEN' 1* 0.001 0.216 1* 1.5 1* 'Z' /",
        "/",
    ]
    assert text[text.index("WELLDIMS") + 2] == " 2 5 1 2 /"
    for directions, message in (
        ([0, 0, 1, 3, 2], "0, 1 or 2"),
        (["X"] * 5, "0, 1 or 2"),
        ([0, 1], "0, 1 or 2"),
    ):
        bad = replace(horizontal, directions=np.asarray(directions))
        with pytest.raises(
            InputError, match=rf"wells\[1\] \('H1'\): expected one direction per completion, {message}"
        ):
            write_flow_deck(tmp_path / "bad", "traj", deck, replace(sim, wells=(vertical, bad)))


def test_boxes_keep_the_centre_depths_and_never_overlap():
    rng = np.random.default_rng(11)
    for _ in range(20):
        grid = layered_connection_grid(rng, ncol=15, nlay=6, missing=int(rng.integers(0, 30)))
        tops, dz = box_depths(grid)
        nx, _, nz = grid.dims
        assert (dz >= 0).all() and (dz[grid.index] > 0).all()
        centre = tops[grid.index] + dz[grid.index] / 2.0
        np.testing.assert_allclose(centre, grid.depth, rtol=0, atol=1e-12 * 2000)
        assert (dz[grid.index] <= grid.thickness + 1e-9).all()
        t, b = tops.reshape(nz, nx), (tops + dz).reshape(nz, nx)
        assert (b[:-1] <= t[1:] + 1e-9).all()  # ZCORN never decreases down a column


def test_well_cells_on_a_corner_point_grid_and_a_pebi_grid():
    cp = gl.process_grdecl(gl.simple_grdecl([4, 3, 2], flat=True))
    geo = gl.compute_geometry(cp.grid)
    x = cp.grid.nodes.coords[:, 0].max()
    cells = vertical_well_cells(cp.grid, geo, [0.6 * x, 0.5])
    assert cells.size == 2 and np.diff(geo.cell_centroids[cells, 2]).min() > 0  # top down
    assert vertical_well_cells(cp.grid, geo, [2 * x, 0.5]).size == 0
    pg = gl.pebi_grid(gl.rectangle(0.0, 0.0, 100.0, 100.0), 20.0, wells=[gl.Well((40.0, 50.0), name="W")])
    layered = gl.make_layered_grid(pg.grid, thickness=[1.0, 2.0, 3.0])
    lgeo = gl.compute_geometry(layered)
    cells = vertical_well_cells(layered, lgeo, [40.0, 50.0])
    np.testing.assert_array_equal(layered.layering.layer[cells], [0, 1, 2])
    assert np.unique(layered.layering.column[cells]).size == 1
    # points on shared edges and corners of a tiling belong to exactly one polygon
    sq = gl.cart_grid([3, 3])
    from gridlib.connectivity import cell_node_cycles_2d

    pos, nodes = cell_node_cycles_2d(sq)
    for point in ([1.0, 1.0], [1.0, 0.5], [0.5, 2.0], [2.0, 2.0], [0.25, 0.75]):
        assert points_in_polygons(point, pos, nodes, sq.nodes.coords).sum() == 1


def test_bad_input_is_refused_before_any_file(tmp_path):
    rng = np.random.default_rng(2)
    grid = layered_connection_grid(rng)
    index = grid.index.copy()
    index[1] = index[0]
    cases = [
        (ConnectionGrid(**{**grid.__dict__, "index": index}), SIM, "share a Flow cell"),
        (ConnectionGrid(**{**grid.__dict__, "trans": -grid.trans}), SIM, "finite and positive"),
        (grid, Simulation("gas", 2000.0, 200.0, 2030.0), "fluid"),
        (grid, Simulation("oil-water", 2000.0, 200.0, None), "owc"),
        (grid, Simulation("oil-water", 2000.0, 200.0, 2030.0, (), (60.0, 30.0)), "report_days"),
        (
            grid,
            Simulation(
                "water", 2000.0, 200.0, None, (FlowWell("W", "producer", grid.index[:1], 0.1, 0.0, [1.0]),)
            ),
            "rate",
        ),
        (
            grid,
            Simulation(
                "water", 2000.0, 200.0, None, (FlowWell("W", "producer", [10**6], 0.1, 0.0, [1.0], 5.0),)
            ),
            "outside the active cells",
        ),
        (
            grid,
            Simulation(
                "water", 2000.0, 200.0, None, (FlowWell("W", "producer", grid.index[:1], 0.1, bhp=5.0),)
            ),
            "factor",
        ),
        (
            grid,
            Simulation(
                "water",
                2000.0,
                200.0,
                None,
                (FlowWell("TOOLONGNAME", "producer", grid.index[:1], 0.1, 0, [1.0], 1.0),),
            ),
            "1 to 8 ASCII characters",
        ),
    ]
    for layout, sim, message in cases:
        with pytest.raises(InputError, match=message):
            write_flow_deck(tmp_path / "out", "case", layout, sim)
        assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
    reversed_column = ConnectionGrid(**{**grid.__dict__, "depth": -grid.depth})
    with pytest.raises(InputError, match="not ordered top down"):
        write_flow_deck(tmp_path / "out", "case", reversed_column, SIM)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


CASE = """name: {name}
horizons:
  lattice: {{x: {{start: 0, stop: 1000, num: 11}}, y: {{start: 0, stop: 800, num: 9}}}}
  surfaces:
    - {{name: top, plane: {{depth: 1000}}}}
    - {{name: base, plane: {{depth: 1040}}}}
grid: {{type: cornerpoint, dims: [10, 8], layers: 2}}
petrophysics: {{porosity: {{constant: 0.2}}, permeability: {{constant: 100}}}}
wells:
  - {{name: INJ, point: {inj}}}
  - {{name: PROD, point: [800, 400]}}
simulation:
  initial: {{pressure: 150}}
  wells:
    - {{name: INJ, type: injector, rate: 100}}
    - {{name: {prod}, type: producer, bhp: 100}}
  report_days: {days}
"""


SURVEY_WELL = "{name: INJ, survey: {head: [200, 400, 990], stations: [[0, 30, 90], [60, 30, 90]]}}"


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"inj": "[1500, 400]"}, "wells[0].point: well 'INJ' at (1500, 400) lies outside the domain"),
        (
            {"prod": "PRODX"},
            "simulation.wells[1].name: 'PRODX' is not among the case's wells (wells: INJ, PROD)",
        ),
        ({"days": "[30, 30]"}, "simulation.report_days[1]: 30 does not come after 30 (days must increase)"),
        ({"prod": "INJ"}, "simulation.wells[1].name: well 'INJ' is listed twice"),
    ],
)
def test_the_simulation_section_is_checked_when_the_case_is_read(tmp_path, changes, message):
    values = {"name": "sim", "inj": "[200, 400]", "prod": "PROD", "days": "[30, 60]"} | changes
    path = tmp_path / "sim.yaml"
    path.write_text(CASE.format(**values))
    with pytest.raises(InputError) as exc:
        load_case(path)
    assert str(exc.value) == f"{path}: {message}"


def test_a_good_simulation_section_gets_its_defaults(tmp_path):
    path = tmp_path / "sim.yaml"
    path.write_text(CASE.format(name="sim", inj="[200, 400]", prod="PROD", days="[30, 60]"))
    case = load_case(path)
    assert case.has_simulation and case.writes_flow_deck and case.flow_name == "SIM"
    sim = case.data["simulation"]
    assert sim["fluid"] == "oil-water" and "initial" in sim
    no_rock = Path(tmp_path / "norock.yaml")
    no_rock.write_text(path.read_text().replace("name: sim", "name: norock").split("petrophysics:")[0] + "\n")
    assert not load_case(no_rock).writes_flow_deck


def test_the_simulation_section_as_typed_objects(tmp_path):
    """case_simulation: the section with the case's well points, what the case leaves to the
    model as None, the schema's skin; a case without the section simulates nothing."""
    from gridlib.case.simulation import CaseSimulation, InitialState, SimulatedWell, case_simulation

    path = tmp_path / "sim.yaml"
    path.write_text(CASE.format(name="sim", inj="[200, 400]", prod="PROD", days="[30, 60]"))
    sim = case_simulation(load_case(path))
    injector = SimulatedWell("INJ", "injector", (200.0, 400.0), 100.0, None, None, 0.0, "simulation.wells[0]")
    producer = SimulatedWell(
        "PROD", "producer", (800.0, 400.0), None, 100.0, None, 0.0, "simulation.wells[1]"
    )
    assert sim == CaseSimulation(
        "oil-water", InitialState(pressure=150.0), (injector, producer), (30.0, 60.0)
    )
    bare = tmp_path / "bare.yaml"
    bare.write_text(path.read_text().replace("name: sim", "name: bare").split("simulation:")[0])
    assert case_simulation(load_case(bare)) == CaseSimulation("oil-water", InitialState(), (), ())


@pytest.mark.parametrize(
    ("well", "simulated", "message"),
    [
        (
            "{name: INJ, path: [[100, 400], [300, 400]]}",
            "{name: INJ, type: injector, rate: 100}",
            "simulation.wells[0].name: well 'INJ' is a plan-view path (it refines a pebi grid); simulated "
            "wells are vertical at a point or have a trajectory or survey",
        ),
        (
            SURVEY_WELL,
            "{name: INJ, type: injector, rate: 100, skin: 2}",
            "simulation.wells[0].skin: well 'INJ' has a trajectory: its radius and skin are the case "
            "well's (wells[0], used for the factors in wells.nc)",
        ),
    ],
)
def test_a_simulated_well_needs_a_point_or_a_path_in_depth(tmp_path, well, simulated, message):
    path = tmp_path / "sim.yaml"
    text = CASE.format(name="sim", inj="[200, 400]", prod="PROD", days="[30, 60]")
    text = text.replace("{name: INJ, point: [200, 400]}", well)
    path.write_text(text.replace("{name: INJ, type: injector, rate: 100}", simulated))
    with pytest.raises(InputError) as exc:
        load_case(path)
    assert str(exc.value) == f"{path}: {message}"


def test_a_trajectory_well_is_simulated_without_a_point(tmp_path):
    from gridlib.case.simulation import SimulatedWell, case_simulation

    path = tmp_path / "sim.yaml"
    text = CASE.format(name="sim", inj="[200, 400]", prod="PROD", days="[30, 60]")
    path.write_text(text.replace("{name: INJ, point: [200, 400]}", SURVEY_WELL))
    injector, producer = case_simulation(load_case(path)).wells
    assert injector == SimulatedWell("INJ", "injector", None, 100.0, None, None, 0.0, "simulation.wells[0]")
    assert injector.has_trajectory and not producer.has_trajectory
