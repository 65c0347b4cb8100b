"""ROFF grids and parameters: gridlib's files read by xtgeo, xtgeo's read by gridlib, bit for bit."""

from __future__ import annotations

import re

import numpy as np
import pytest

from gridlib.cornerpoint.corners import corner_points
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import make_model3
from gridlib.errors import InputError
from gridlib.io import registry
from gridlib.io.grdecl import read_grdecl, write_grdecl
from gridlib.io.roff import (
    layer_gaps,
    read_roff_grid,
    read_roff_parameter,
    read_roff_subgrids,
    write_roff_grid,
    write_roff_parameter,
)

xtgeo = pytest.importorskip("xtgeo")


def _rounded(shift) -> Deck:
    base = make_model3([6, 5, 4])
    coord = base.coord.reshape(-1, 6) + np.array(list(shift) * 2)
    rnd = lambda a: np.round(a * 64.0) / 64.0  # noqa: E731
    return Deck(base.cart_dims, rnd(coord), rnd(base.zcorn + shift[2]), base.actnum, source="model3")


@pytest.fixture(scope="module")
def local_deck() -> Deck:
    """make_model3 rounded to 1/64: float32 values (xtgeo keeps GRDECL coordinates as float32)."""
    return _rounded((0.0, 0.0, 0.0))


@pytest.fixture(scope="module")
def deck() -> Deck:
    """make_model3 (two faults, pinched layers, inactive cells), shifted to UTM-like
    coordinates and rounded to 1/64 so that the values less whole offsets are float32."""
    return _rounded((456000.0, 6780000.0, 1500.0))


def _expected_xtgeo(deck: Deck):
    """xtgeo's coordsv, zcornsv and actnumsv values the deck implies (from its own corners)."""
    nx, ny, nz = deck.cart_dims
    cells = np.arange(nx * ny * nz)
    pts = corner_points(deck, cells)
    i, j, k = cells % nx, (cells // nx) % ny, cells // (nx * ny)
    return pts, (i, j, k)


@pytest.mark.parametrize("binary", [True, False])
def test_xtgeo_reads_gridlib_roff(tmp_path, deck, binary):
    path = tmp_path / ("g.roff" if binary else "g.roffasc")
    registry.write(path, deck, kind="deck")  # binary or ASCII by the suffix
    assert path.read_bytes()[:8] == (b"roff-bin" if binary else b"roff-asc")
    grid = xtgeo.grid_from_file(path, fformat="roff")
    nx, ny, nz = deck.cart_dims
    assert grid.dimensions == (nx, ny, nz)
    coordsv = grid._coordsv  # (nx+1, ny+1, 6): top xyz, bottom xyz
    np.testing.assert_array_equal(coordsv.transpose(1, 0, 2).reshape(-1), deck.coord)
    zc = grid._zcornsv  # (nx+1, ny+1, nz+1, 4): sw, se, nw, ne cells at a node
    pts, (i, j, k) = _expected_xtgeo(deck)
    for corner in range(8):
        a, b, c = corner & 1, (corner >> 1) & 1, corner >> 2
        got = zc[i + a, j + b, k + c, 3 - a - 2 * b].astype(np.float64)
        np.testing.assert_array_equal(got, pts[:, corner, 2])
    act = grid._actnumsv.transpose(2, 1, 0).ravel()
    np.testing.assert_array_equal(act, deck.actnum)


def test_gridlib_reads_xtgeo_roff(tmp_path, local_deck):
    grdecl = tmp_path / "g.grdecl"
    write_grdecl(grdecl, local_deck)
    grid = xtgeo.grid_from_file(grdecl, fformat="grdecl")
    ref = read_grdecl(grdecl)
    for fmt in ("roff_binary", "roff_ascii"):
        path = tmp_path / f"x_{fmt}.roff"
        grid.to_file(path, fformat=fmt)
        got = registry.read(path, "deck")
        assert got.cart_dims == ref.cart_dims
        np.testing.assert_array_equal(got.coord, ref.coord)
        np.testing.assert_array_equal(got.zcorn, ref.zcorn)
        np.testing.assert_array_equal(got.actnum, ref.actnum)


@pytest.mark.parametrize("binary", [True, False])
def test_round_trip_with_subgrids_and_gaps(tmp_path, deck, binary):
    """Vertical gaps (split-8 nodes, which xtgeo 4 does not read) and subgrids round-trip
    through gridlib's own reader; xtgeo reads the subgrids of a file without gaps."""
    nx = deck.cart_dims[0]
    z = deck.zcorn_array().copy()
    z[2:, :, :nx] += 0.5  # a gap under layer 0 in the western half, and a fault
    gapped = Deck(deck.cart_dims, deck.coord, z.ravel(), deck.actnum, source="gapped")
    ny = deck.cart_dims[1]
    assert (layer_gaps(deck), layer_gaps(gapped)) == (0, 2 * ny * nx)  # layer 0's base corners, west
    path = tmp_path / "s.roff"
    write_roff_grid(path, gapped, subgrids=[1, 3], binary=binary)
    back = read_roff_grid(path)
    np.testing.assert_array_equal(back.subgrids, [1, 3])
    np.testing.assert_array_equal(read_roff_subgrids(path), [1, 3])
    np.testing.assert_array_equal(back.deck.coord, gapped.coord)
    np.testing.assert_array_equal(back.deck.zcorn, gapped.zcorn)
    np.testing.assert_array_equal(back.deck.actnum, gapped.actnum)
    write_roff_grid(path, deck, subgrids=[1, 3], binary=binary)
    grid = xtgeo.grid_from_file(path, fformat="roff")
    assert grid.subgrids == {"subgrid_0": range(1, 2), "subgrid_1": range(2, 5)}


def test_parameter_both_ways(tmp_path, deck):
    nx, ny, nz = deck.cart_dims
    poro = (np.arange(nx * ny * nz) % 17) / 64.0
    facies = np.arange(nx * ny * nz, dtype=np.int32) % 5
    grid_path = tmp_path / "g.roff"
    write_roff_grid(grid_path, deck)
    grid = xtgeo.grid_from_file(grid_path, fformat="roff")
    for name, values in (("PORO", poro), ("FACIES", facies)):
        path = tmp_path / f"{name}.roff"
        write_roff_parameter(path, name, values, deck.cart_dims)
        prop = xtgeo.gridproperty_from_file(path, fformat="roff", grid=grid, name=name)
        np.testing.assert_array_equal(prop.values.data.transpose(2, 1, 0).ravel(), values)
        assert read_roff_parameter(path) == (name, pytest.approx(values, abs=0))
        prop.name = name + "X"
        back = tmp_path / f"{name}_x.roff"
        prop.to_file(back, fformat="roff_ascii", name=name + "X")
        got_name, got = read_roff_parameter(back)
        assert got_name == name + "X"  # xtgeo writes inactive cells as undefined
        np.testing.assert_array_equal(got, np.where(deck.actnum == 1, values, -999))


def test_first_of_several_parameters(tmp_path):
    import roffio

    path = tmp_path / "two.roff"
    one = [("dimensions", {"nX": 1, "nY": 2, "nZ": 2}), ("filedata", {"filetype": "parameter"})]
    data = [
        ("parameter", {"name": n, "data": np.array(v, np.float32)})
        for n, v in (("A", [1, 2, 3, 4]), ("B", [5] * 4))
    ]
    roffio.write(path, one + data)
    name, values = read_roff_parameter(path)  # ROFF (i, j, k up) -> i fastest, k down
    assert name == "A"
    np.testing.assert_array_equal(values, [2.0, 4.0, 1.0, 3.0])


def test_damaged_and_wrong_files(tmp_path, deck):
    good = tmp_path / "g.roff"
    write_roff_grid(good, deck)
    raw = good.read_bytes()
    cut = tmp_path / "cut.roff"
    cut.write_bytes(raw[: len(raw) // 2])
    junk = tmp_path / "junk.roff"
    junk.write_bytes(b"not a roff file at all\n")
    param = tmp_path / "p.roff"
    write_roff_parameter(param, "PORO", np.zeros(deck.actnum.size), deck.cart_dims)
    for path in (cut, junk, param, tmp_path / "missing.roff"):
        with pytest.raises(InputError, match=re.escape(f"{path}: ")):
            read_roff_grid(path)
    with pytest.raises(InputError, match=r"g\.roff: a ROFF grid file, not a parameter file$"):
        read_roff_parameter(good)
