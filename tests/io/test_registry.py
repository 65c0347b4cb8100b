"""The file-format registry (gridlib.io.registry): read(path, kind=...) / write(path, obj, kind=...)
dispatch by suffix, with exact round trips of small inputs for every kind."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib import io
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.horizons import horizon_dataset
from gridlib.horizons.surface import Surface
from gridlib.io import read, write
from gridlib.petrophysics import PropertyCube


def test_every_kind_has_its_formats():
    table = {(f.kind, f.name): f.suffixes for f in io.formats()}
    assert table[("grid", "netcdf")] == (".nc",) and table[("grid", "vtu")] == (".vtu",)
    assert table[("deck", "grdecl")] == (".grdecl", ".data", ".inc", ".grd")
    assert table[("deck", "egrid")] == (".egrid", ".fegrid")
    assert table[("surface", "irap")] == ("*",) and table[("points", "text")] == ("*",)
    assert table[("sticks", "text")] == ("*",) and table[("well_path", "text")] == ("*",)
    assert table[("surface", "irap_binary")] == (".gri", ".irapbin") and table[("polygons", "rms")] == ("*",)
    kinds = {
        "grid",
        "geometry",
        "deck",
        "surface",
        "points",
        "sticks",
        "polygons",
        "well_path",
        "horizons",
        "cube",
    }
    assert {k for k, _ in table} == kinds


def test_grid_and_geometry_round_trip_exactly(tmp_path):
    g = gl.twister(gl.cart_grid([3, 2, 2]))
    geo = gl.compute_geometry(g)
    io.write(tmp_path / "g.nc", g, cell_data={"poro": np.linspace(0.1, 0.3, 12)})
    back = io.read(tmp_path / "g.nc")  # kind="grid" by default
    np.testing.assert_array_equal(back.grid.nodes.coords, g.nodes.coords)
    np.testing.assert_array_equal(back.grid.faces.nodes, g.faces.nodes)
    np.testing.assert_array_equal(back.grid.faces.neighbors, g.faces.neighbors)
    np.testing.assert_array_equal(back.cell_data["poro"], np.linspace(0.1, 0.3, 12))
    io.write(tmp_path / "geo.nc", geo, g.griddim, kind="geometry")
    again = io.read(tmp_path / "geo.nc", kind="geometry")
    np.testing.assert_array_equal(again.cell_volumes, geo.cell_volumes)
    np.testing.assert_array_equal(again.face_normals, geo.face_normals)


def test_deck_round_trips_exactly_through_grdecl(tmp_path):
    deck = simple_grdecl([3, 2, 2])
    for name in ("d.grdecl", "D.GRDECL", "d.inc"):
        io.write(tmp_path / name, deck, kind="deck")
        back = io.read(tmp_path / name, kind="deck")
        assert back.cart_dims == deck.cart_dims
        np.testing.assert_array_equal(back.coord, deck.coord)
        np.testing.assert_array_equal(back.zcorn, deck.zcorn)
        np.testing.assert_array_equal(back.actnum, deck.actnum)
    assert (tmp_path / "d.grdecl").read_bytes() == (tmp_path / "D.GRDECL").read_bytes()


def test_surface_round_trips_exactly_in_irap_under_any_suffix(tmp_path):
    z = np.array([[1000.0, 1010.5, 1020.25], [1001.0, np.nan, 1021.0]])
    s = Surface.from_axes([0.0, 100.0, 200.0], [10.0, 60.0], z)
    for name in ("top.irap", "top.grd", "top.txt"):
        io.write(tmp_path / name, s, kind="surface")
        back = io.read(tmp_path / name, kind="surface")
        np.testing.assert_array_equal(back.z, s.z)
        assert (back.xori, back.yori, back.xinc, back.yinc) == (0.0, 10.0, 100.0, 50.0)
    with pytest.raises(
        gl.InputError, match=r"top\.nc: unknown file type: cannot write '\.nc' files as surface"
    ):
        io.write(tmp_path / "top.nc", s, kind="surface")


def test_horizons_surface_from_netcdf_and_points(tmp_path):
    x, y = np.array([0.0, 50.0, 100.0]), np.array([0.0, 40.0])
    top, base = np.full((2, 3), 1000.0), np.full((2, 3), 1012.5)
    ds = horizon_dataset([top, base], x, y, names=["top", "base"])
    io.write(tmp_path / "h.nc", ds, kind="horizons")
    back = io.read(tmp_path / "h.nc", kind="horizons")
    np.testing.assert_array_equal(back["depth"].values, ds["depth"].values)
    assert [str(n) for n in back["horizon"].values] == ["top", "base"]
    surf = io.read(tmp_path / "h.nc", kind="surface", horizon="base")
    np.testing.assert_array_equal(surf.z, base)
    (tmp_path / "picks.csv").write_text("x,y,z\n0,0,1000.5\n10,20,1001.25\n")
    pts = io.read(tmp_path / "picks.csv", kind="points")
    np.testing.assert_array_equal(pts, [[0.0, 0.0, 1000.5], [10.0, 20.0, 1001.25]])


def test_cube_round_trips_exactly(tmp_path):
    values = {"poro": np.arange(12.0).reshape(2, 2, 3) / 100.0}
    cube = PropertyCube([5.0, 15.0, 25.0], [5.0, 15.0], [1.0, 3.0], values)
    io.write(tmp_path / "c.nc", cube, kind="cube")
    back = io.read(tmp_path / "c.nc", kind="cube")
    for axis in ("x", "y", "z"):
        np.testing.assert_array_equal(getattr(back, axis), getattr(cube, axis))
    np.testing.assert_array_equal(back.values["poro"], values["poro"])


def test_unknown_suffix_is_one_error_naming_the_file(tmp_path):
    g = gl.cart_grid([2, 2])
    with pytest.raises(gl.InputError) as err:
        io.read(tmp_path / "a.xyz", kind="deck")
    assert str(err.value) == (
        f"{tmp_path / 'a.xyz'}: unknown file type: cannot read '.xyz' files as deck "
        "(known: .bgrdecl, .data, .egrid, .fegrid, .grd, .grdecl, .inc, .roff, .roff_asc, .roffasc, .roffbin)"
    )
    with pytest.raises(gl.InputError, match=r"a\.vtu: unknown file type: cannot read '\.vtu' files as grid"):
        io.read(tmp_path / "a.vtu")  # VTU is written, not read
    with pytest.raises(gl.InputError, match=r"a\.egrid: unknown file type: cannot write '\.egrid'"):
        io.write(tmp_path / "a.egrid", g, kind="deck")
    with pytest.raises(
        gl.InputError, match=r"a\.txt: unknown file type: cannot read '\.txt' files as deck or grid"
    ):
        io.kind_of(tmp_path / "a.txt", ("deck", "grid"))
    assert io.kind_of(tmp_path / "A.EGRID", ("deck", "grid")) == "deck"
    assert list(tmp_path.iterdir()) == []


def test_registry_dispatches_on_suffix(tmp_path):
    g = gl.cart_grid([2, 2])
    write(tmp_path / "a.nc", g)
    assert read(tmp_path / "a.nc").grid.num_cells == 4
    with pytest.raises(gl.InputError, match=r"cannot write '\.xyz'"):
        write(tmp_path / "a.xyz", g)


def test_a_format_module_is_imported_on_first_use_only():
    """Importing the netCDF format (every workflow stage does) imports no other format module
    nor what they need; read()/write() import a format's module when they use it."""
    import subprocess
    import sys

    code = (
        "import sys, gridlib.io.netcdf, gridlib.io as io\n"
        "formats = ('grdecl', 'egrid', 'irap', 'vtu', 'cube_files', 'horizon_files', 'flow')\n"
        "mods = ['gridlib.io.' + m for m in formats]\n"
        "mods += ['gridlib.cornerpoint', 'gridlib.horizons', 'pyvista']\n"
        "print(sorted(m for m in mods if m in sys.modules))\n"
        "fmt = io.find_format('a.egrid', 'deck')\n"
        "print(fmt.reader, fmt.function('read').__module__, 'gridlib.io.egrid' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.splitlines() == ["[]", "gridlib.io.egrid:read_egrid gridlib.io.egrid True"]


@pytest.fixture
def restored_registry(monkeypatch):
    """The registered table as it was, after the test (register_format replaces it)."""
    from gridlib.io import registry

    monkeypatch.setattr(registry, "_formats", registry.formats())


def test_a_format_of_ones_own_is_registered_by_function_or_by_name(tmp_path, restored_registry):
    io.register_format("csvgrid", "grid", (".csvg",), reader=lambda path: f"read {path}")
    assert io.read(tmp_path / "a.csvg") == f"read {tmp_path / 'a.csvg'}"
    io.register_format("csvgrid", "grid", (".csvg",), writer="gridlib.io.netcdf:write_netcdf")
    with pytest.raises(gl.InputError, match=r"a\.csvg: unknown file type: cannot read '\.csvg' files"):
        io.read(tmp_path / "a.csvg")  # replaced by a write-only format of the same name and kind
    assert io.find_format("a.csvg", "grid", "write").function("write") is io.write_netcdf


def test_register_format_replaces_the_table_and_never_changes_one(restored_registry):
    from gridlib.io.registry import BUILTIN_FORMATS

    before = io.formats()
    assert before == BUILTIN_FORMATS and isinstance(before, tuple)
    first = io.register_format("csvgrid", "grid", (".CSVG",), reader="gridlib.io.netcdf:read_netcdf")
    assert first.suffixes == (".csvg",) and io.formats() == (*before, first)
    second = io.register_format("netcdf", "grid", (".nc", ".nc4"), reader="gridlib.io.netcdf:read_netcdf")
    assert io.formats() == (*(f for f in before if (f.name, f.kind) != ("netcdf", "grid")), first, second)
    assert before == BUILTIN_FORMATS  # the table read before is untouched
    assert io.find_format("a.nc4", "grid") is second
