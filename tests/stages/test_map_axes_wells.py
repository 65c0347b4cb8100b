"""A deck whose MAPAXES place its grid on the map, with a well trajectory given on the map, as
RMS, xtgeo and OPM Flow's trajectories give it: Equinor's Reek model as ECLIPSE wrote its EGRID
(local x, y; MAPAXES with origin (456510.625, 5938935.5) and the y axis towards the south) and the RMS well
file of its producer OP_1. The well finds the cells it crosses: those it crosses in the same grid
moved onto the map (the frame xtgeo and ResInsight draw it in), and every cell xtgeo's
``make_ijk_from_grid`` finds at the file's points."""

from __future__ import annotations

import logging
import lzma
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from gridlib.config import load_case
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.map_axes import MapAxes
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import InputError
from gridlib.geometry import compute_geometry
from gridlib.io.egrid import read_egrid
from gridlib.io.netcdf_parts import read_attrs
from gridlib.io.roff import map_coordinates
from gridlib.io.well_paths import read_well_path
from gridlib.io.wells_file import read_wells
from gridlib.stages import case_outputs, run_stage
from gridlib.wells.intersect import path_cells

DATA = Path(__file__).resolve().parents[1] / "data"


def test_axes_east_and_north_are_a_translation_both_ways():
    axes = MapAxes.of([456063.6, 5926552.0, 456063.6, 5926551.0, 456064.6, 5926551.0])
    local = np.array([[0.0, 0.0], [1234.5, 678.25], [-10.0, 5.5]])
    on_map = axes.to_map(local)
    np.testing.assert_array_equal(on_map, local + [456063.6, 5926551.0])
    np.testing.assert_array_equal(axes.to_grid(on_map), on_map - [456063.6, 5926551.0])


def test_a_flipped_y_axis_mirrors_and_a_rotated_frame_turns():
    flipped = MapAxes.of([100.0, 0.0, 100.0, 50.0, 200.0, 50.0])  # y axis towards the south
    np.testing.assert_array_equal(flipped.to_map(np.array([[10.0, 20.0]])), [[110.0, 30.0]])
    np.testing.assert_array_equal(flipped.to_grid(np.array([[110.0, 30.0]])), [[10.0, 20.0]])
    c, s = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    turned = MapAxes.of([-s, c, 0.0, 0.0, c, s])  # axes turned 30 degrees anticlockwise
    np.testing.assert_allclose(
        turned.to_map(np.array([[2.0, 0.0], [0.0, 1.0]])), [[2 * c, 2 * s], [-s, c]], atol=1e-15
    )
    points = np.random.default_rng(1).uniform(-1e3, 1e3, (50, 2))
    np.testing.assert_allclose(turned.to_grid(turned.to_map(points)), points, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ([0, 1, 0, 0, 0, 0], "an axis point is the origin"),
        ([2, 0, 0, 0, 1, 0], "the x and y axes are parallel"),
    ],
)
def test_a_mapaxes_that_makes_no_frame_is_named(values, message):
    with pytest.raises(ValueError, match=message):
        MapAxes.of(values)
    deck = Deck(
        (1, 1, 1),
        np.array([0, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 0, 1, 1, 1.0]),
        np.repeat([0.0, 1.0], 4),
        source="m.grdecl",
    )
    with pytest.raises(InputError, match=f"m.grdecl: MAPAXES: {message}"):
        Deck(deck.cart_dims, deck.coord, deck.zcorn, mapaxes=np.array(values, float), source="m.grdecl")


@pytest.fixture(scope="module")
def reek(tmp_path_factory):
    """The Reek EGRID as a deck case with OP_1's trajectory, its grid, geometry, rock and wells
    stages run."""
    folder = tmp_path_factory.mktemp("reek_wells")
    shutil.copyfile(DATA / "decks" / "reek" / "REEK.EGRID", folder / "REEK.EGRID")
    (folder / "OP_1.w").write_bytes(lzma.decompress((DATA / "wells" / "reek" / "OP_1.w.xz").read_bytes()))
    data = {
        "name": "reek_op1",
        "grid": {"type": "deck", "file": "REEK.EGRID"},
        "petrophysics": {"porosity": {"constant": 0.2}, "permeability": {"constant": 100}},
        "wells": [{"name": "OP_1", "trajectory": "OP_1.w"}],
    }
    (folder / "reek_op1.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    case = load_case(folder / "reek_op1.yaml")
    paths = case_outputs(case.name, folder / "out")
    (folder / "out").mkdir()
    for stage in ("grid", "geometry", "petrophysics"):
        run_stage(stage, case, paths)
    return folder, case, paths


def test_a_map_well_crosses_the_cells_it_crosses_in_the_grid_moved_onto_the_map(reek, caplog):
    folder, case, paths = reek
    with caplog.at_level(logging.INFO, logger="gridlib"):
        run_stage("wells", case, paths)
    assert any("MAPAXES places its grid on the map" in r.getMessage() for r in caplog.records)
    (record,) = read_wells(paths["wells"])
    deck = read_egrid(folder / "REEK.EGRID")
    assert read_attrs(paths["grid"])["map_axes"] == deck.mapaxes.tolist()
    ours = np.asarray(process_grdecl(deck).grid.cells.index_map)[record.connections.cell]

    path = read_well_path(folder / "OP_1.w", format="rms")
    np.testing.assert_array_equal(
        record.paths[0].xyz, deck.map_axes.xyz_to_grid(path.xyz)
    )  # drawn with the grid
    on_map = process_grdecl(map_coordinates(deck)).grid
    pieces = path_cells(on_map, compute_geometry(on_map), path)
    mapped = np.asarray(on_map.cells.index_map)[pieces.cell]  # a piece per segment and cell
    first = np.sort(np.unique(mapped, return_index=True)[1])
    np.testing.assert_array_equal(ours, mapped[first])  # in the order the well enters them
    assert ours.size == 14
    per_cell = np.bincount(np.searchsorted(ours, mapped, sorter=np.argsort(ours)), pieces.length)
    np.testing.assert_allclose(record.connections.length, per_cell[np.argsort(np.argsort(ours))], atol=1e-6)
    assert np.isfinite(record.connections.factor).all() and (record.connections.factor > 0).all()


def test_xtgeo_finds_no_cell_of_the_well_that_gridlib_misses(reek):
    import xtgeo  # a test extra; imported here, where it is used (it takes a second)

    folder, case, paths = reek
    run_stage("wells", case, paths)
    (record,) = read_wells(paths["wells"])
    nx, ny = 40, 64
    cells = np.asarray(process_grdecl(read_egrid(folder / "REEK.EGRID")).grid.cells.index_map)[
        record.connections.cell
    ]
    ours = set(
        zip(
            (cells % nx + 1).tolist(),
            (cells // nx % ny + 1).tolist(),
            (cells // (nx * ny) + 1).tolist(),
            strict=True,
        )
    )
    well = xtgeo.well_from_file(folder / "OP_1.w")
    well.make_ijk_from_grid(xtgeo.grid_from_file(folder / "REEK.EGRID"))
    frame = well.get_dataframe()
    found = frame[frame["ICELL"].notna() & (frame["ICELL"] > 0)][["ICELL", "JCELL", "KCELL"]].astype(int)
    theirs = set(map(tuple, found.to_numpy().tolist()))
    assert theirs and theirs <= ours, sorted(theirs - ours)


def test_a_vertical_well_at_a_map_point_is_completed_where_its_line_crosses_the_grid_on_the_map(tmp_path):
    """A vertical well at OP_1's head (a map point) in the Reek deck's OPM Flow deck: COMPDAT
    completes the cells a vertical line there crosses in the grid moved onto the map."""
    from gridlib.completions import vertical_well_cells

    head = (461809.590, 5932990.360)
    shutil.copyfile(DATA / "decks" / "reek" / "REEK.EGRID", tmp_path / "REEK.EGRID")
    data = {
        "name": "reek_v",
        "grid": {"type": "deck", "file": "REEK.EGRID"},
        "petrophysics": {"porosity": {"constant": 0.2}, "permeability": {"constant": 100}},
        "wells": [{"name": "V1", "point": list(head)}],
        "simulation": {
            "fluid": "water",
            "wells": [{"name": "V1", "type": "producer", "bhp": 150}],
            "report_days": [1],
        },
    }
    (tmp_path / "reek_v.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    case = load_case(tmp_path / "reek_v.yaml")
    paths = case_outputs(case.name, tmp_path / "out")
    (tmp_path / "out").mkdir()
    for stage in ("grid", "geometry", "petrophysics", "transmissibility", "flow_deck"):
        run_stage(stage, case, paths)
    text = Path(paths["flow_deck"]).read_text()
    records = [
        line
        for line in text.split("COMPDAT", 1)[1].split("\n/", 1)[0].splitlines()
        if line.startswith(" 'V1'")
    ]
    completed = [tuple(int(v) for v in line.split()[1:4]) for line in records]

    on_map = process_grdecl(map_coordinates(read_egrid(tmp_path / "REEK.EGRID"))).grid
    cells = np.asarray(on_map.cells.index_map)[vertical_well_cells(on_map, compute_geometry(on_map), head)]
    expected = list(
        zip(
            (cells % 40 + 1).tolist(),
            (cells // 40 % 64 + 1).tolist(),
            (cells // 2560 + 1).tolist(),
            strict=True,
        )
    )
    assert len(expected) == 14 and completed == expected


def test_a_section_line_given_on_the_map_cuts_the_grid_where_it_lies_on_the_map(reek):
    """pictures.section of the Reek deck case, a west-east line through OP_1's head on the map:
    the section cuts the grid along that line moved into the grid's frame (on the map's
    coordinates themselves it cut no cell)."""
    from gridlib.stages.pictures import read_scene, section_cut

    folder, case, paths = reek
    data = yaml.safe_load(case.path.read_text())
    data["pictures"] = {"section": [[460000.0, 5932990.36], [464000.0, 5932990.36]]}
    (folder / "sec").mkdir(exist_ok=True)
    shutil.copyfile(folder / "REEK.EGRID", folder / "sec" / "REEK.EGRID")
    shutil.copyfile(folder / "OP_1.w", folder / "sec" / "OP_1.w")
    (folder / "sec" / "reek_op1.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    sectioned = load_case(folder / "sec" / "reek_op1.yaml")
    scene = read_scene(sectioned, paths["grid"], paths["geometry"])
    line, cut = section_cut(sectioned, scene, ())
    np.testing.assert_array_equal(line, scene.map_axes.to_grid(np.array(data["pictures"]["section"])))
    assert cut.cells.size > 0
