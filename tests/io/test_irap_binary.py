"""IRAP/RMS binary surfaces (gridlib.io.irap_binary) against xtgeo 4.27 as a peer: xtgeo reads our
files with equal values, undefined nodes and rotation, we read xtgeo's, the bytes are xtgeo's;
float32 rounding, flipped rows, other record lengths and bad files."""

from __future__ import annotations

import struct

import numpy as np
import pytest
import xtgeo

from gridlib import InputError, io
from gridlib.horizons import Surface
from gridlib.io.irap_binary import IRAP_BINARY_UNDEFINED, read_irap_binary, write_irap_binary


def rotated_surface() -> Surface:
    """A rotated 9 x 7 lattice with three undefined nodes; the header is float32-exact (an origin
    at a multiple of the float32 spacing there), the depths are not."""
    rng = np.random.default_rng(5)
    z = 1500.0 + rng.standard_normal((7, 9)) * 13.7
    z[0, 0] = z[3, 4] = z[6, 8] = np.nan
    return Surface(z, 456_789.125, 6_789_012.5, 12.5, 8.25, rotation=30.0, name="top")


def to_xtgeo(s: Surface) -> xtgeo.RegularSurface:
    return xtgeo.RegularSurface(
        ncol=s.nx, nrow=s.ny, xinc=s.xinc, yinc=s.yinc, xori=s.xori, yori=s.yori, rotation=s.rotation,
        values=np.ma.masked_invalid(s.z.T),
    )  # fmt: skip


def xtgeo_z(x: xtgeo.RegularSurface) -> np.ndarray:
    """xtgeo's values as our z[j, i], NaN where masked."""
    return np.ma.filled(x.values.astype(np.float64), np.nan).T


def test_xtgeo_reads_ours_with_equal_values_rotation_and_nodes(tmp_path):
    s = rotated_surface()
    path = write_irap_binary(tmp_path / "top.gri", s)
    x = xtgeo.surface_from_file(path, fformat="irap_binary")
    assert (x.ncol, x.nrow, x.xori, x.yori, x.xinc, x.yinc, x.rotation) == (9, 7, *[
        s.xori, s.yori, s.xinc, s.yinc, 30.0
    ])  # fmt: skip
    assert x.yflip == 1
    expected = s.z.astype(np.float32).astype(np.float64)  # float32 values, rounded to nearest
    np.testing.assert_array_equal(xtgeo_z(x), expected)  # NaN at the same three nodes
    assert np.abs(expected - s.z)[~np.isnan(s.z)].max() <= 2.0**-24 * 1600  # half an ulp of float32
    xs, ys, _ = x.get_xyz_values()  # world node coordinates: one rotation convention
    X, Y = s.node_coordinates()
    np.testing.assert_allclose(np.ma.getdata(xs).T, X, rtol=0, atol=1e-6)
    np.testing.assert_allclose(np.ma.getdata(ys).T, Y, rtol=0, atol=1e-6)


def test_we_read_xtgeos_file_and_write_its_bytes(tmp_path):
    s = rotated_surface()
    s32 = Surface(s.z.astype(np.float32), s.xori, s.yori, s.xinc, s.yinc, rotation=s.rotation)
    to_xtgeo(s32).to_file(tmp_path / "xt.gri", fformat="irap_binary")
    t = read_irap_binary(tmp_path / "xt.gri")
    np.testing.assert_array_equal(t.z, s32.z)  # exact, undefined nodes included
    assert (t.nx, t.ny, t.xori, t.yori, t.xinc, t.yinc, t.rotation, t.name) == (
        9, 7, s.xori, s.yori, s.xinc, s.yinc, 30.0, "xt",
    )  # fmt: skip
    write_irap_binary(tmp_path / "ours.gri", t)
    assert (tmp_path / "ours.gri").read_bytes() == (tmp_path / "xt.gri").read_bytes()
    assert (tmp_path / "ours.gri").read_bytes().count(struct.pack(">f", IRAP_BINARY_UNDEFINED)) == 3


def test_header_is_float32_too(tmp_path):
    s = Surface(np.full((2, 3), 1000.0), 461_587.553724, 5_927_061.430176, 5.0, 5.0)
    t = read_irap_binary(write_irap_binary(tmp_path / "utm.gri", s))
    assert (t.xori, t.yori) == (float(np.float32(s.xori)), float(np.float32(s.yori)))
    assert abs(t.xori - s.xori) < 0.02 and abs(t.yori - s.yori) < 0.25  # float32 spacing: 1/32, 1/2 m


def test_flipped_rows_are_the_same_nodes(tmp_path):
    z = np.arange(12.0).reshape(3, 4) + 1000.0
    x = xtgeo.RegularSurface(
        ncol=4, nrow=3, xinc=10.0, yinc=20.0, xori=100.0, yori=500.0, rotation=30.0, yflip=-1, values=z.T
    )
    x.to_file(tmp_path / "flip.gri", fformat="irap_binary")
    t = read_irap_binary(tmp_path / "flip.gri")
    assert t.yinc == 20.0 and t.rotation == 30.0
    xs, ys, vs = (np.ma.getdata(a).T for a in x.get_xyz_values())
    X, Y = t.node_coordinates()
    order = np.lexsort((xs.ravel(), ys.ravel()))
    ours = np.lexsort((X.ravel(), Y.ravel()))
    np.testing.assert_allclose(X.ravel()[ours], xs.ravel()[order], atol=1e-9)
    np.testing.assert_allclose(Y.ravel()[ours], ys.ravel()[order], atol=1e-9)
    np.testing.assert_array_equal(t.z.ravel()[ours], vs.ravel()[order])


def test_records_of_any_length_and_the_ascii_null(tmp_path):
    """Values in records of 5 (not one per row), 9999900.0 as a second null, elevation."""
    head = struct.pack(
        ">3i6f3i3f2i7ii", 32, -996, 2, 0.0, 20.0, 0.0, 5.0, 10.0, 5.0, 32, 16, 3, 0.0, 0.0, 0.0, 16, 28,
        *(0,) * 7, 28,
    )  # fmt: skip
    values = [1000.0, 1001.0, 9999900.0, 1003.0, 1004.0, 1e30]
    recs = b"".join(
        struct.pack(f">i{len(c)}fi", 4 * len(c), *c, 4 * len(c)) for c in (values[:5], values[5:])
    )
    (tmp_path / "odd.irapbin").write_bytes(head + recs)
    s = io.read(tmp_path / "odd.irapbin", kind="surface")
    np.testing.assert_array_equal(s.z, [[1000.0, 1001.0, np.nan], [1003.0, 1004.0, np.nan]])
    assert read_irap_binary(tmp_path / "odd.irapbin", elevation=True).z[1, 0] == -1003.0
    x = xtgeo.surface_from_file(tmp_path / "odd.irapbin", fformat="irap_binary")
    assert np.ma.getdata(x.values)[2, 0] == 9999900.0  # xtgeo's null is 1e30 only: why we write that


def test_bytes_after_the_values_are_ignored(tmp_path):
    """ResInsight appends a text footer of metadata after the last value record."""
    s = rotated_surface()
    path = write_irap_binary(tmp_path / "top.gri", s)
    path.write_bytes(path.read_bytes() + b"----RESINSIGHT_METADATA_V1----\nsampleSpacing=50\n")
    np.testing.assert_array_equal(read_irap_binary(path).z, s.z.astype(np.float32))


def test_registry_writes_gri_as_binary(tmp_path):
    s = rotated_surface()
    io.write(tmp_path / "top.gri", s, kind="surface")
    assert (tmp_path / "top.gri").read_bytes()[:8] == struct.pack(">2i", 32, -996)
    back = io.read(tmp_path / "top.gri", kind="surface")
    np.testing.assert_array_equal(back.z, s.z.astype(np.float32))


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"-996 2 1 1\n", r"bad\.gri: not an IRAP binary surface: 11 bytes"),
        (struct.pack(">3i", 32, -995, 2) + bytes(88), r"bad\.gri: not an IRAP binary surface \(big-endian"),
        ("cut", r"bad\.gri: byte 120: bad IRAP binary record \(length 12, not matched"),
        ("short", r"bad\.gri: IRAP binary surface of 6 nodes has 3 values"),
        ("xinc", r"bad\.gri: IRAP binary header: xinc must be finite and positive, got -1\.0"),
    ],
)
def test_bad_files_name_the_file(tmp_path, data, message):
    good = write_irap_binary(tmp_path / "good.gri", Surface(np.full((2, 3), 1.0), 0.0, 0.0, 1.0, 1.0))
    raw = good.read_bytes()
    if data == "cut":
        data = raw[:-6]
    elif data == "short":
        data = raw[:-20]
    elif data == "xinc":
        data = raw[:28] + struct.pack(">f", -1.0) + raw[32:]  # xinc: the header's 8th word
    (tmp_path / "bad.gri").write_bytes(data)
    with pytest.raises(InputError, match=message):
        read_irap_binary(tmp_path / "bad.gri")


def test_values_that_would_read_back_undefined_are_refused(tmp_path):
    s = Surface(np.array([[1000.0, 9999900.0]]), 0.0, 0.0, 1.0, 1.0)
    with pytest.raises(InputError, match=r"x\.gri: write_irap_binary: values must lie below 9999900"):
        write_irap_binary(tmp_path / "x.gri", s)
    assert not (tmp_path / "x.gri").exists()
