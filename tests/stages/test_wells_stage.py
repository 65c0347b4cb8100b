"""The ``wells`` stage (issue 26): a corner-point case with a deviated well from a file (two
perforations and a branch) and a survey well, built as the workflow builds it; wells.nc holds
exactly the connections of the library called directly on the stage files (path_cells,
well_connections with Flow's extents from grid.grdecl, merge_connections), the exports draw
and count them, and a well that misses the grid stops the stage naming it."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml

from gridlib.case.wells import case_well_paths
from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.io.grdecl import read_grdecl
from gridlib.io.netcdf import read_geometry_netcdf, read_netcdf
from gridlib.io.rock_file import read_rock
from gridlib.io.wells_file import read_wells
from gridlib.stages import case_outputs, run_stage
from gridlib.transmissibility.peaceman import deck_cell_extents
from gridlib.units import METRIC
from gridlib.wells.connections import merge_connections, well_connections
from gridlib.wells.intersect import cell_index, path_cells

# 6 x 4 columns, 3 layers between planes dipping 2 degrees east; a fault of 10 m throw.
CASE = {
    "name": "wellbox",
    "horizons": {
        "lattice": {"x": {"start": 0, "stop": 600, "num": 7}, "y": {"start": 0, "stop": 400, "num": 5}},
        "surfaces": [
            {"name": "top", "plane": {"depth": 2000, "dip": 2.0, "azimuth": 90}},
            {"name": "base", "plane": {"depth": 2030, "dip": 2.0, "azimuth": 90}},
        ],
    },
    "faults": [{"name": "F1", "trace": [[310, -10], [330, 410]], "throw": 10}],
    "wells": [
        {
            "name": "P1",
            "trajectory": "data/p1.xyz",
            "perforations": [[2000, 2150], [2200, 2400]],
            "radius": 0.1,
            "skin": 1.5,
            "branches": [{"trajectory": "data/p1b.xyz"}],
        },
        {
            "name": "I1",
            "survey": {
                "head": [500, 100, 1900],
                "stations": [[1900, 0, 0], [2000, 40, 300], [2100, 40, 300]],
            },
        },
    ],
    "grid": {"type": "cornerpoint", "dims": [6, 4], "layers": 3},
    "petrophysics": {
        "porosity": {"constant": 0.2},
        "permeability": {"layers": [100.0, 300.0, 50.0]},
        "ntg": {"constant": 0.8},
    },
}
P1_POINTS = np.array([[50.0, 210, 1950], [100, 210, 2010], [500, 230, 2035]])  # down in, then across F1
P1_MD = 1950.0 + np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P1_POINTS, axis=0), axis=1))])
P1 = "".join(
    f"{x!r} {y!r} {z!r} {md!r}\n" for (x, y, z), md in zip(P1_POINTS.tolist(), P1_MD.tolist(), strict=True)
)
P1_BRANCH = "200 215 2016.25\n250 380 2030\n"  # off P1 at x = 200, northwards


def _case(folder: Path, data: dict) -> Path:
    (folder / "data").mkdir(parents=True, exist_ok=True)
    (folder / "data" / "p1.xyz").write_text(P1)
    (folder / "data" / "p1b.xyz").write_text(P1_BRANCH)
    path = folder / f"{data['name']}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("wells_stage")
    case = load_case(_case(folder, CASE))
    paths = case_outputs(case.name, folder / "out")
    (folder / "out").mkdir()
    for stage in (
        "horizons",
        "grid",
        "geometry",
        "petrophysics",
        "transmissibility",
        "quality",
        "wells",
        "export",
    ):
        run_stage(stage, case, paths)
    return case, paths


def test_the_stage_writes_the_connections_of_the_library_called_directly(built):
    case, paths = built
    grid = read_netcdf(paths["grid"]).grid
    geo = read_geometry_netcdf(paths["geometry"])
    rock = read_rock(paths["petrophysics"])
    perm = np.column_stack([rock["permx"], rock["permy"], rock["permz"]])
    extents = deck_cell_extents(read_grdecl(paths["grdecl"]), grid.cells.index_map)
    index = cell_index(grid, geo)
    written = read_wells(paths["wells"])
    assert [w.name for w in written] == ["P1", "I1"]
    for well, record in zip(case_well_paths(case), written, strict=True):
        radius = 0.1 if well.radius is None else well.radius
        per_path = []
        for path, intervals in zip(well.paths, well.perforations, strict=True):
            for a, b in intervals:
                pieces = path_cells(grid, geo, path.between(a, b), index=index)
                if pieces.cell.size:
                    per_path.append(
                        well_connections(
                            grid,
                            geo,
                            perm,
                            rock["ntg"],
                            pieces,
                            radius,
                            well.skin,
                            units=METRIC,
                            extents=extents,
                        )
                    )
        direct = merge_connections(*per_path)
        order = np.argsort(direct.entry_md, kind="stable")  # the stage: rows in MD order
        got = record.connections
        for field in ("cell", "entry_md", "exit_md", "entry", "exit", "length", "axis_length", "factor"):
            np.testing.assert_array_equal(getattr(got, field), getattr(direct, field)[order], err_msg=field)
        assert (record.radius, record.skin) == (radius, well.skin)
    p1, i1 = written
    assert len(p1.paths) == 2 and p1.parents == (0,)
    assert p1.perforations[0].tolist() == [[2000.0, 2150.0], [2200.0, 2400.0]]
    assert np.all(np.diff(p1.connections.entry_md) >= 0)
    assert p1.connections.cell.size > 5 and i1.connections.cell.size == 3


def test_the_exports_draw_and_count_the_wells(built):
    import pyvista as pv

    _, paths = built
    written = read_wells(paths["wells"])
    vtp = pv.read(paths["well_paths"])
    assert vtp.n_cells == 3 and vtp.field_data["well_names"].tolist() == ["P1", "I1"]
    assert vtp.field_data["path_names"].tolist() == ["P1", "P1:1", "I1"]
    np.testing.assert_array_equal(
        vtp.point_data["md"], np.concatenate([p.md for w in written for p in w.paths])
    )
    depth = np.concatenate([p.xyz[:, 2] for w in written for p in w.paths])
    np.testing.assert_array_equal(vtp.point_data["depth"], depth)
    np.testing.assert_array_equal(vtp.points[:, 2], -depth)  # the file's z is elevation
    summary = json.loads(Path(paths["summary"]).read_text())["trajectory_wells"]
    for w in written:
        assert summary[w.name] == {
            "connections": int(w.connections.cell.size),
            "completed_length": float(f"{w.connections.length.sum():.12g}"),
            "total_factor": float(f"{w.connections.factor.sum():.12g}"),
        }


def test_a_well_that_misses_the_grid_stops_the_stage_naming_it(built, tmp_path):
    _, paths = built
    data = {
        **CASE,
        "wells": [{**CASE["wells"][1], "survey": {**CASE["wells"][1]["survey"], "head": [500, 100, 100]}}],
    }
    missing = load_case(_case(tmp_path, data))
    out = case_outputs(missing.name, tmp_path / "out")
    with pytest.raises(InputError) as info:
        run_stage("wells", missing, {**paths, "wells": out["wells"]})
    assert str(info.value) == (
        f"{missing.path}: wells[0]: well 'I1' crosses no active cell of the grid where it is open (I1 MD "
        "1900 to 2100): its path misses the grid, or its perforations lie outside it"
    )
    assert not out["wells"].exists()


def test_a_path_given_in_elevations_is_named_so(built, tmp_path):
    """z is depth: a trajectory file of elevations (z negative down) lies above the grid, its
    mirror image in it; the message says so."""
    _, paths = built
    (tmp_path / "data").mkdir()
    up = P1_POINTS * [1.0, 1.0, -1.0]
    (tmp_path / "data" / "up.xyz").write_text("".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in up.tolist()))
    data = {**CASE, "wells": [{"name": "P1", "trajectory": "data/up.xyz"}]}
    case = load_case(_case(tmp_path, data))
    with pytest.raises(InputError) as info:
        run_stage("wells", case, {**paths, "wells": tmp_path / "wells.nc"})
    assert str(info.value) == (
        f"{case.path}: wells[0]: well 'P1' crosses no active cell of the grid where it is open (P1 MD "
        "0 to 479.382): its path misses the grid, or its perforations lie outside it; its z "
        "(-2035 to -1950) is above the grid (depth 2000 to 2060.95) and -z in it: z is depth, "
        "positive down, not elevation"
    )


def test_a_wells_nc_of_another_grid_is_named_by_the_deck(built, tmp_path):
    """wells.nc whose cells are not the grid's (another build's, or a damaged copy): the deck
    stage names the file and the well, not an IndexError."""
    from gridlib.io.wells_file import write_wells
    from gridlib.stages.flow_deck import stage_flow_deck

    _, paths = built
    records = read_wells(paths["wells"])
    num_cells = read_netcdf(paths["grid"]).grid.num_cells
    stale = [
        replace(r, connections=replace(r.connections, cell=r.connections.cell + num_cells)) for r in records
    ]
    write_wells(tmp_path / "wells.nc", stale, METRIC, attrs={})
    data = {
        **CASE,
        "simulation": {"wells": [{"name": "P1", "type": "producer", "bhp": 150}], "report_days": [30]},
    }
    simulated = load_case(_case(tmp_path, data))
    inputs = {key: paths[key] for key in ("grid", "geometry", "petrophysics", "transmissibility", "grdecl")}
    with pytest.raises(InputError) as info:
        stage_flow_deck(
            simulated, **inputs, wells=tmp_path / "wells.nc", flow_deck=tmp_path / "f" / "WELLBOX.DATA"
        )
    assert str(info.value) == (
        f"{tmp_path / 'wells.nc'}: well 'P1' connects cell {int(stale[0].connections.cell.max())}, but "
        f"{paths['grid']} has {num_cells} cells: wells.nc is another grid's (run the stage 'wells' again)"
    )


def test_a_field_deck_case_has_its_wells_in_feet_and_a_vertical_one_gets_compdats_factors(tmp_path):
    """A FIELD deck (a flat 3 x 2 x 2 box of 100 x 100 x 10 ft cells at 5000 ft): the default
    radius is 0.1 m in ft, everything is labelled in FIELD units, and a vertical trajectory
    through a column's centre gets in each cell exactly the factor Flow computes for its COMPDAT
    (deck_well_index: the deck's PERMX, PERMY, NTG and corners)."""
    import xarray as xr

    from gridlib.cornerpoint.generators import simple_grdecl
    from gridlib.io.grdecl import write_grdecl
    from gridlib.transmissibility.peaceman import deck_well_index
    from gridlib.units import FIELD

    deck = simple_grdecl((3, 2, 2), flat=True, undisturbed=True, phys_dims=(300.0, 200.0, 20.0))
    deck = replace(deck, zcorn=deck.zcorn + 5000.0, units="FIELD")
    rng = np.random.default_rng(7)
    rock = {
        "PORO": rng.uniform(0.1, 0.3, 12),
        "PERMX": rng.lognormal(4, 1, 12),
        "PERMY": rng.lognormal(3, 1, 12),
        "PERMZ": rng.lognormal(1, 1, 12),
        "NTG": rng.uniform(0.5, 1.0, 12),
    }
    write_grdecl(tmp_path / "BOX.GRDECL", deck, rock)
    (tmp_path / "BOX.DATA").write_text("RUNSPEC\nDIMENS\n 3 2 2 /\nFIELD\nGRID\nINCLUDE\n 'BOX.GRDECL' /\n")
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "v1.xyz").write_text("150 50 4990 4990\n150 50 5030 5030\n")
    data = {
        "name": "box",
        "grid": {"type": "deck", "file": "BOX.DATA"},
        "wells": [{"name": "V1", "trajectory": "data/v1.xyz"}],
    }
    (tmp_path / "box.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    case = load_case(tmp_path / "box.yaml")
    paths = case_outputs(case.name, tmp_path / "out")
    (tmp_path / "out").mkdir()
    for stage in ("grid", "geometry", "petrophysics", "wells"):
        run_stage(stage, case, paths)
    (v1,) = read_wells(paths["wells"])
    radius = 0.1 / 0.3048
    assert v1.radius == radius
    np.testing.assert_array_equal(v1.connections.cell, [1, 7])  # (2, 1, 1) and (2, 1, 2)
    np.testing.assert_array_equal(v1.connections.direction, [2, 2])
    np.testing.assert_allclose(v1.connections.length, [10.0, 10.0], rtol=1e-12)
    flow = deck_well_index(deck_with(deck, rock), [1, 7], radius, 0.0, "z")
    np.testing.assert_allclose(v1.connections.factor, flow, rtol=1e-12)
    with xr.open_dataset(paths["wells"]) as ds:
        assert ds.attrs["unit_system"] == "FIELD"
        assert ds["completion_factor"].attrs["units"] == FIELD.unit("transmissibility") == "cP rb/(day psi)"
        assert ds["well_radius"].attrs["units"] == "ft" and ds["completion_ijk"].values.tolist() == [
            [2, 1, 1],
            [2, 1, 2],
        ]


def deck_with(deck, rock):
    """``deck`` with the cell keywords ``rock``."""
    return replace(deck, cell_data={**deck.cell_data, **{k: np.asarray(v) for k, v in rock.items()}})
