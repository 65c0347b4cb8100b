"""The exchange stage and ROFF case grids: {case}.roff (grid, rock, zones as subgrids) read by
xtgeo equal to gridlib's arrays bit for bit; exchange/ (IRAP binary horizons, fault polygons)
read by xtgeo equal to the horizons and faults; a case whose grid is a ROFF file (written by
xtgeo, binary and ASCII, with its rock in ROFF parameter files) builds the same grid as the
GRDECL it came from."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from gridlib import artifacts
from gridlib.case.grid import build_case_grid
from gridlib.config import load_case
from gridlib.cornerpoint.corners import corner_points
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import make_model3
from gridlib.errors import InputError
from gridlib.io.atomic import atomic_directory
from gridlib.io.grdecl import read_grdecl, write_grdecl
from gridlib.io.horizon_files import read_horizons
from gridlib.io.netcdf import read_netcdf
from gridlib.io.rock_file import read_rock
from gridlib.io.roff import read_roff_grid
from gridlib.stages import case_outputs, run_stage
from gridlib.stages.exchange import fault_polylines, horizon_surfaces

xtgeo = pytest.importorskip("xtgeo")

ROOT = Path(__file__).resolve().parents[2]
DIMS = (6, 5, 4)


def _run(case_file: Path, folder: Path, *, upto: str = "exchange") -> dict[str, Path]:
    """The case's stages up to ``upto`` (those it has), in process; the artifacts' paths."""
    case = load_case(case_file)
    paths = case_outputs(case.name, folder)
    for stage in artifacts.STAGES:
        if stage.outputs_of(case) and not stage.on_request and stage.name in (
            "horizons", "grid", "geometry", "petrophysics", "exchange"
        ):  # fmt: skip
            run_stage(stage.name, case, paths)
        if stage.name == upto:
            break
    return paths


def _deck() -> Deck:
    """make_model3 (two faults, pinched layers, inactive cells) at 1500 m depth, rounded to
    1/64: float32 values (xtgeo holds a grid's coordinates as float32)."""
    base = make_model3(list(DIMS))
    shift = np.array([0.0, 0.0, 1500.0])
    rnd = lambda a: np.round(a * 64.0) / 64.0  # noqa: E731
    coord = rnd(base.coord.reshape(-1, 6) + np.tile(shift, 2))
    return Deck(base.cart_dims, coord, rnd(base.zcorn + shift[2]), base.actnum, source="model3")


def _rock() -> dict[str, np.ndarray]:
    """Porosity and permeability per cell (float32 values: ROFF parameters are float32)."""
    n = int(np.prod(DIMS))
    rng = np.random.default_rng(5)
    poro = rng.uniform(0.1, 0.3, n).astype(np.float32).astype(np.float64)
    permx = rng.lognormal(4, 1, n).astype(np.float32).astype(np.float64)
    return {"PORO": poro, "PERMX": permx}


@pytest.fixture(scope="module")
def xtgeo_roff_cases(tmp_path_factory):
    """A GRDECL deck with its rock, and its grid and rock as xtgeo writes them as ROFF (binary
    and ASCII), each with a case file: the ROFF grid, its rock from ROFF parameter files."""
    folder = tmp_path_factory.mktemp("roff_cases")
    deck, rock = _deck(), _rock()
    grdecl = folder / "model.grdecl"
    write_grdecl(grdecl, Deck(deck.cart_dims, deck.coord, deck.zcorn, deck.actnum, cell_data=rock))
    grid = xtgeo.grid_from_file(grdecl, fformat="grdecl")
    cases = {}
    _case(folder / "from_grdecl.yaml", {"type": "deck", "file": "model.grdecl"})
    cases["grdecl"] = folder / "from_grdecl.yaml"
    for fmt in ("roff_binary", "roff_ascii"):
        grid.to_file(folder / f"{fmt}.roff", fformat=fmt)
        files = {}
        for keyword in rock:
            prop = xtgeo.gridproperty_from_file(grdecl, fformat="grdecl", name=keyword, grid=grid)
            prop.name = keyword.lower()  # RMS's names need not be ECLIPSE's: the key says which
            prop.to_file(folder / f"{fmt}_{keyword}.roff", fformat=fmt)
            files[keyword] = f"{fmt}_{keyword}.roff"
        name = f"from_{fmt}"
        _case(folder / f"{name}.yaml", {"type": "deck", "file": f"{fmt}.roff", "parameters": files})
        cases[fmt] = folder / f"{name}.yaml"
    return deck, rock, cases


def _case(path: Path, grid: dict, **more) -> None:
    path.write_text(yaml.safe_dump({"name": path.stem, "grid": grid, **more}))


@pytest.mark.parametrize("fmt", ["roff_binary", "roff_ascii"])
def test_a_roff_case_has_the_grid_and_rock_of_the_grdecl_it_came_from(xtgeo_roff_cases, fmt):
    deck, rock, cases = xtgeo_roff_cases
    ref, got = (build_case_grid(load_case(cases[k])) for k in ("grdecl", fmt))
    for a, b in (
        (ref.grid.nodes.coords, got.grid.nodes.coords),
        (ref.grid.cells.index_map, got.grid.cells.index_map),
    ):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(ref.grid.faces.neighbors, got.grid.faces.neighbors)
    np.testing.assert_array_equal(ref.grid.faces.nodes, got.grid.faces.nodes)
    np.testing.assert_array_equal(ref.deck.zcorn, got.deck.zcorn)
    np.testing.assert_array_equal(ref.deck.coord, got.deck.coord)
    assert load_case(cases[fmt]).has_petrophysics  # the ROFF rock gives the case its rock
    for keyword, values in rock.items():
        np.testing.assert_array_equal(got.deck.cell_data[keyword], np.where(deck.active, values, 0.0))


@pytest.fixture(scope="module")
def roff_case_built(xtgeo_roff_cases, tmp_path_factory):
    """The binary ROFF case through its stages up to exchange."""
    _, _, cases = xtgeo_roff_cases
    return _run(cases["roff_binary"], tmp_path_factory.mktemp("built") / "roff_case")


def _xtgeo_arrays(grid):
    """xtgeo's grid as gridlib's Deck arrays (COORD, ZCORN per cell corner, ACTNUM)."""
    coord = grid._coordsv.transpose(1, 0, 2).reshape(-1)
    return coord, grid._zcornsv, grid._actnumsv.transpose(2, 1, 0).ravel()


def _assert_xtgeo_reads_the_deck(grid, deck: Deck) -> None:
    """xtgeo's grid is ``deck``: COORD (float64) and ACTNUM equal, its zcorn (float32 in xtgeo)
    the deck's corner depths rounded to float32 (the same values where they are float32)."""
    coord, zc, act = _xtgeo_arrays(grid)
    np.testing.assert_array_equal(coord, deck.coord)
    nx, ny, nz = deck.cart_dims
    cells = np.arange(nx * ny * nz)
    pts = corner_points(deck, cells)
    i, j, k = cells % nx, (cells // nx) % ny, cells // (nx * ny)
    for corner in range(8):
        a, b, c = corner & 1, (corner >> 1) & 1, corner >> 2
        got = zc[i + a, j + b, k + c, 3 - a - 2 * b]
        np.testing.assert_array_equal(got, pts[:, corner, 2].astype(np.float32))
    np.testing.assert_array_equal(act, deck.actnum)


def test_xtgeo_reads_the_roff_of_a_roff_case_as_gridlib_holds_it(roff_case_built):
    paths = roff_case_built
    deck = read_grdecl(paths["grdecl"])
    grid = xtgeo.grid_from_file(paths["roff"])
    _assert_xtgeo_reads_the_deck(grid, deck)
    assert grid.subgrids is None  # xtgeo wrote no subgrids
    stored = read_netcdf(paths["grid"]).grid
    rock = read_rock(paths["petrophysics"])
    for name, keyword in (("poro", "PORO"), ("permx", "PERMX"), ("permz", "PERMZ")):
        prop = xtgeo.gridproperty_from_file(paths["roff"], name=keyword, grid=grid)
        values = np.ma.filled(prop.values, -999.0).transpose(2, 1, 0).ravel()
        expected = np.full(values.size, -999.0)
        expected[stored.cells.index_map] = rock[name].astype(np.float32)
        np.testing.assert_array_equal(values[stored.cells.index_map], expected[stored.cells.index_map])
        assert prop.values.mask.transpose(2, 1, 0).ravel().sum() == values.size - stored.num_cells


def _small_anticline(folder: Path) -> Path:
    """The anticline sample on 12 x 8 columns, zones of 1 and 2 layers, its second fault
    inclined (dip 60) so that it has sticks, without coarsening."""
    data = yaml.safe_load((ROOT / "config" / "cases" / "anticline.yaml").read_text())
    data = copy.deepcopy(data)
    data["name"] = "small_anticline"
    data["grid"] = {"type": "cornerpoint", "dims": [12, 8], "layers": [1, 2]}
    data["faults"][1]["dip"] = 60
    del data["coarsen"]
    path = folder / "small_anticline.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.fixture(scope="module")
def anticline_built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("anticline")
    return _run(_small_anticline(folder), folder / "out"), folder / "small_anticline.yaml"


def test_a_cornerpoint_case_has_one_subgrid_per_zone_and_its_rock_in_its_roff(anticline_built):
    paths, _ = anticline_built
    deck = read_grdecl(paths["grdecl"])
    back = read_roff_grid(paths["roff"])
    grid = xtgeo.grid_from_file(paths["roff"])
    _assert_xtgeo_reads_the_deck(grid, back.deck)  # xtgeo reads what gridlib reads, bit for bit
    # ... which is the case's deck, x and y exactly (the lattice's), depths to float32's spacing
    # of their values less the file's whole-metre offset (ROFF is float32)
    np.testing.assert_array_equal(back.deck.coord.reshape(-1, 3)[:, :2], deck.coord.reshape(-1, 3)[:, :2])
    offset = np.floor(deck.zcorn.min())
    for a, b in ((back.deck.zcorn, deck.zcorn), (back.deck.coord[2::3], deck.coord[2::3])):
        local = b - offset
        assert np.all(np.abs((a - offset) - local) <= np.spacing(np.float32(np.abs(local).max())))
    assert grid.subgrids == {"subgrid_0": range(1, 2), "subgrid_1": range(2, 4)}
    zone = xtgeo.gridproperty_from_file(paths["roff"], name="ZONE", grid=grid)
    assert zone.isdiscrete
    np.testing.assert_array_equal(zone.values.filled(0)[0, 0, :], [1, 2, 2])
    stored = read_netcdf(paths["grid"]).grid
    rock = read_rock(paths["petrophysics"])
    for name in ("poro", "permx", "permy", "permz", "ntg"):
        prop = xtgeo.gridproperty_from_file(paths["roff"], name=name.upper(), grid=grid)
        values = prop.values.transpose(2, 1, 0).ravel()
        np.testing.assert_array_equal(values[stored.cells.index_map], rock[name].astype(np.float32))
    assert back.subgrids.tolist() == [1, 2]
    np.testing.assert_array_equal(back.parameters["ZONE"], np.repeat([1, 2, 2], 12 * 8))


def test_the_horizons_are_irap_binary_surfaces_xtgeo_reads_as_they_are(anticline_built):
    paths, _ = anticline_built
    ds = read_horizons(paths["horizons"])
    names = [str(n) for n in ds["horizon"].values]
    assert sorted(p.name for p in paths["exchange"].iterdir()) == sorted(
        [f"{n}.gri" for n in names] + ["faults.pol", "fault_sticks.pol"]
    )
    for k, name in enumerate(names):
        surf = xtgeo.surface_from_file(paths["exchange"] / f"{name}.gri", fformat="irap_binary")
        depth = ds["depth"].values[k]  # (y, x), y and x increasing
        assert (surf.ncol, surf.nrow) == (depth.shape[1], depth.shape[0])
        assert (surf.xori, surf.yori) == (float(ds["x"][0]), float(ds["y"][0]))
        assert (surf.xinc, surf.yinc) == (float(ds["x"][1] - ds["x"][0]), float(ds["y"][1] - ds["y"][0]))
        np.testing.assert_array_equal(surf.values.filled(np.nan).T, depth.astype(np.float32))
    assert float(xtgeo.surface_from_file(paths["exchange"] / "top.gri").values.max()) > 2000.0  # depth down


def test_the_faults_are_polygons_xtgeo_reads_on_the_horizons(anticline_built):
    paths, case_file = anticline_built
    case = load_case(case_file)
    surfaces = horizon_surfaces(paths["horizons"])
    traces, sticks = fault_polylines(case, surfaces[0], surfaces[-1])
    for name, lines in (("faults.pol", traces), ("fault_sticks.pol", sticks)):
        df = xtgeo.polygons_from_file(paths["exchange"] / name, fformat="xyz").get_dataframe()
        got = [g[["X_UTME", "Y_UTMN", "Z_TVDSS"]].to_numpy() for _, g in df.groupby("POLY_ID", sort=True)]
        assert len(got) == len(lines)
        for a, b in zip(got, lines, strict=True):
            np.testing.assert_array_equal(a, b)
    top, base = surfaces[0], surfaces[-1]
    assert len(traces) == 2  # each fault's trace, cut where it leaves the top's lattice
    for line in traces:  # draped on the top horizon, inside its lattice
        np.testing.assert_allclose(line[:, 2], top.sample(line[:, 0], line[:, 1]), rtol=0, atol=1e-9)
        assert line[:, 0].min() >= 0.0 and line[:, 0].max() <= 3000.0
    # F1 is vertical: sticks from the top down to the base at its draped trace's ends
    vertical = [s for s in sticks if s.shape == (2, 3) and np.array_equal(s[0, :2], s[1, :2])]
    assert len(vertical) == 2
    for stick in vertical:
        assert stick[0, 2] == pytest.approx(float(top.sample(stick[0, 0], stick[0, 1])), abs=1e-9)
        assert stick[1, 2] == pytest.approx(float(base.sample(stick[1, 0], stick[1, 1])), abs=1e-9)
    inclined = [s for s in sticks if not any(s is v for v in vertical)]
    assert inclined  # F2 dips 60 degrees: its surface's sticks move in plan with depth
    for stick in inclined:
        dz = stick[-1, 2] - stick[0, 2]
        heave = np.hypot(*(stick[-1, :2] - stick[0, :2]))
        assert heave == pytest.approx(dz / np.tan(np.radians(60.0)), rel=1e-9)


def test_a_cartesian_case_writes_no_roff_and_no_exchange_folder():
    case = load_case(ROOT / "config" / "cases" / "ellipsoid.yaml")
    assert "roff" not in {a.key for a in artifacts.case_artifacts(case)}
    assert "exchange" not in {a.key for a in artifacts.case_artifacts(case)}


def test_grid_parameters_name_the_key_of_a_missing_or_wrong_file(xtgeo_roff_cases, tmp_path):
    _, _, cases = xtgeo_roff_cases
    folder = cases["roff_binary"].parent
    missing = folder / "missing_param.yaml"
    _case(missing, {"type": "deck", "file": "roff_binary.roff", "parameters": {"PORO": "nope.roff"}})
    with pytest.raises(InputError, match=r"grid\.parameters\.PORO: 'nope\.roff' not found"):
        load_case(missing)
    other = make_model3([3, 2, 2])
    from gridlib.io.roff import write_roff_parameter

    write_roff_parameter(folder / "small_poro.roff", "PORO", np.full(12, 0.2), other.cart_dims)
    wrong = folder / "wrong_size.yaml"
    _case(
        wrong,
        {
            "type": "deck",
            "file": "roff_binary.roff",
            "parameters": {"PORO": "small_poro.roff", "PERMX": "roff_binary_PERMX.roff"},
        },
    )
    with pytest.raises(
        InputError, match=r"grid\.parameters\.PORO: small_poro\.roff: 12 values, the grid has 120"
    ):
        build_case_grid(load_case(wrong))


def test_atomic_directory_keeps_the_old_folder_when_the_writer_fails(tmp_path):
    target = tmp_path / "exchange"
    with atomic_directory(target) as folder:
        (folder / "a.gri").write_text("one")
    with pytest.raises(RuntimeError), atomic_directory(target) as folder:
        (folder / "b.gri").write_text("two")
        raise RuntimeError("writer failed")
    assert [p.name for p in tmp_path.iterdir()] == ["exchange"]
    assert [p.name for p in target.iterdir()] == ["a.gri"]
    with atomic_directory(target) as folder:
        (folder / "c.gri").write_text("three")
    assert [p.name for p in target.iterdir()] == ["c.gri"]


def test_a_failed_exchange_stage_leaves_the_folder_as_it_was(anticline_built, monkeypatch):
    """run_stage keeps a directory artifact whole: a failure while exchange/ is rewritten puts
    back the folder of the run before, file for file."""
    paths, case_file = anticline_built
    before = {p.name: p.read_bytes() for p in paths["exchange"].iterdir()}
    roff_before = paths["roff"].read_bytes()
    import gridlib.stages.exchange as stage

    def broken(*args, **kwargs):
        raise InputError("polygons: disk full")

    monkeypatch.setattr(stage, "write_polygons", broken)
    with pytest.raises(InputError, match="disk full"):
        run_stage("exchange", load_case(case_file), paths)
    assert {p.name: p.read_bytes() for p in paths["exchange"].iterdir()} == before
    assert paths["roff"].read_bytes() == roff_before
    assert sorted(p.name for p in paths["exchange"].parent.iterdir() if p.name.startswith(".")) == []


def test_restored_on_failure_puts_a_rewritten_folder_back_whole(tmp_path):
    """A later failure (run_case: a stage after exchange) puts back the folder as it was before
    the run, and removes one the run created."""
    from gridlib.stages.pipeline import restored_on_failure

    old, new = tmp_path / "exchange", tmp_path / "created"
    with atomic_directory(old) as folder:
        (folder / "top.gri").write_bytes(b"old top")
        (folder / "faults.pol").write_bytes(b"old faults")
    with pytest.raises(RuntimeError), restored_on_failure([old, new], sweep=tmp_path):
        for target in (old, new):
            with atomic_directory(target) as folder:
                (folder / "top.gri").write_bytes(b"new top")
        raise RuntimeError("a later stage failed")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["exchange"]
    assert {p.name: p.read_bytes() for p in old.iterdir()} == {
        "top.gri": b"old top",
        "faults.pol": b"old faults",
    }


def test_rms_roff_export_builds_the_grid_of_its_grdecl_export(tmp_path):
    """RMS 13's two exports of one geomodel (xtgeo-testdata's Emerald with a hole): the ROFF
    grid with its parameters (world coordinates) as a case's grid gives the GRDECL case's grid
    (local coordinates, MAPAXES a translation): the same active cells (ROFF's PORO makes the
    5,389 of zero pore volume inactive, as the GRDECL's does), faces and neighbours; nodes
    within the GRDECL's 3 decimals and ROFF's float32 (3 cm); PORO to float32."""
    from real_decks import unpack

    folder = unpack("emerald_hole", tmp_path)
    name = "eme_small_w_hole_grid_params"
    _case(folder / "grdecl_case.yaml", {"type": "deck", "file": f"{name}.grdecl", "unknown_keywords": "skip"})
    _case(folder / "roff_case.yaml", {"type": "deck", "file": f"{name}.roff"})
    ref, got = (build_case_grid(load_case(folder / f"{k}_case.yaml")) for k in ("grdecl", "roff"))
    np.testing.assert_array_equal(got.grid.cells.index_map, ref.grid.cells.index_map)
    assert got.grid.num_cells == 1768
    np.testing.assert_array_equal(got.grid.faces.neighbors, ref.grid.faces.neighbors)
    origin = ref.deck.mapaxes[2:4]  # the x axis' origin: the local frame's (0, 0)
    shifted = ref.grid.nodes.coords + np.array([*origin, 0.0])
    np.testing.assert_allclose(got.grid.nodes.coords, shifted, rtol=0, atol=0.03)
    active = ref.deck.active
    poro = got.deck.cell_data["PORO"]
    np.testing.assert_allclose(poro[active], ref.deck.cell_data["PORO"][active], rtol=0, atol=1e-9)
    assert poro[~active].tolist() == [0.0] * int((~active).sum())  # RMS's -999: 0 in inactive cells
    assert any("FACIES" in note for note in got.notes)  # not a GRID keyword: named, not used


def test_the_roff_of_a_grdecl_case_with_mapaxes_is_where_rms_puts_the_model(tmp_path):
    """The Emerald GRDECL export (local coordinates, MAPAXES) through the exchange stage gives a
    ROFF in map coordinates, as RMS's own ROFF export of the model: xtgeo reads both at the
    same place (pillars within 1.5 mm: the GRDECL's and its MAPAXES' 3 decimals), with the
    same active cells,
    their corner depths within 0.5 mm and their PORO to float32."""
    from real_decks import unpack

    folder = unpack("emerald_hole", tmp_path)
    name = "eme_small_w_hole_grid_params"
    _case(
        folder / "emerald.yaml",
        {"type": "deck", "file": f"{name}.grdecl", "unknown_keywords": "skip"},
        petrophysics={"permeability": {"constant": 100.0}},
    )
    paths = _run(folder / "emerald.yaml", folder / "out")
    ours, rms = (xtgeo.grid_from_file(p) for p in (paths["roff"], folder / f"{name}.roff"))
    (c1, _, a1), (c2, _, a2) = _xtgeo_arrays(ours), _xtgeo_arrays(rms)
    np.testing.assert_allclose(c1, c2, rtol=0, atol=1.5e-3)
    np.testing.assert_array_equal(a1, a2)
    deck = read_roff_grid(paths["roff"]).deck
    rms_deck = read_roff_grid(folder / f"{name}.roff").deck
    cells = np.flatnonzero(deck.active)
    np.testing.assert_allclose(
        corner_points(deck, cells)[:, :, 2], corner_points(rms_deck, cells)[:, :, 2], rtol=0, atol=5e-4 + 2e-4
    )
    ours_poro, rms_poro = (
        xtgeo.gridproperty_from_file(p, name="PORO", grid=g).values
        for p, g in ((paths["roff"], ours), (folder / f"{name}.roff", rms))
    )
    stored = read_netcdf(paths["grid"]).grid  # PORO 0 cells are inactive in the case, -999 in our ROFF
    on = np.zeros(deck.active.size, bool)
    on[stored.cells.index_map] = True
    flat = lambda v: np.ma.filled(v, np.nan).transpose(2, 1, 0).ravel()  # noqa: E731
    np.testing.assert_array_equal(flat(ours_poro)[on], flat(rms_poro)[on])


def test_a_cases_roff_as_the_grid_of_another_case_round_trips(anticline_built, tmp_path):
    """exchange -> case -> exchange: the anticline's ROFF (grid, rock and zones in one file) as
    a deck case's grid gives a ROFF with the same grid, subgrids and parameters, bit for bit."""
    paths, _ = anticline_built
    (tmp_path / "again.roff").write_bytes(paths["roff"].read_bytes())
    _case(tmp_path / "again.yaml", {"type": "deck", "file": "again.roff"})
    assert load_case(tmp_path / "again.yaml").has_petrophysics  # PORO and PERMX in the grid file
    again = _run(tmp_path / "again.yaml", tmp_path / "out")
    first, second = read_roff_grid(paths["roff"]), read_roff_grid(again["roff"])
    assert second.subgrids.tolist() == first.subgrids.tolist() == [1, 2]
    np.testing.assert_array_equal(second.deck.coord, first.deck.coord)
    np.testing.assert_array_equal(second.deck.zcorn, first.deck.zcorn)
    np.testing.assert_array_equal(second.deck.actnum, first.deck.actnum)
    assert list(second.parameters) == list(first.parameters)
    for name, values in first.parameters.items():
        np.testing.assert_array_equal(second.parameters[name], values, err_msg=name)


def test_outputs_roff_format_ascii_writes_the_same_grid_as_text(anticline_built, tmp_path):
    from dataclasses import replace

    from gridlib.stages.exchange import write_case_roff

    paths, case_file = anticline_built
    case = load_case(case_file)
    ascii_case = replace(
        case, data={**case.data, "outputs": {**case.data["outputs"], "roff_format": "ascii"}}
    )
    target = tmp_path / "small_anticline.roff"
    write_case_roff(ascii_case, target, paths["grid"], paths["grdecl"], paths["petrophysics"])
    assert target.read_bytes()[:8] == b"roff-asc" and paths["roff"].read_bytes()[:8] == b"roff-bin"
    text, binary = (xtgeo.grid_from_file(p) for p in (target, paths["roff"]))
    for a, b in zip(_xtgeo_arrays(text), _xtgeo_arrays(binary), strict=True):
        np.testing.assert_array_equal(a, b)
    assert text.subgrids == binary.subgrids
    for name in ("PORO", "ZONE"):
        one, two = (
            xtgeo.gridproperty_from_file(p, name=name, grid=g)
            for p, g in ((target, text), (paths["roff"], binary))
        )
        np.testing.assert_array_equal(one.values, two.values)
