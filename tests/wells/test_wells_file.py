"""wells.nc (gridlib.io.wells_file): paths, branches, perforations and connections of deviated
wells, ragged over the wells; written and read back bit for bit, labelled with the units of the
case's unit system, and one error naming the file when its tables do not fit."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from gridlib.errors import InputError
from gridlib.io.wells_file import WellRecord, read_wells, write_wells
from gridlib.units import FIELD, METRIC
from gridlib.wells.connections import WellConnections
from gridlib.wells.path import WellPath

RNG = np.random.default_rng(26)


def _connections(cells: list[int]) -> WellConnections:
    n = len(cells)
    md = np.sort(RNG.uniform(2000.0, 2500.0, 2 * n)).reshape(n, 2)
    return WellConnections(
        cell=np.array(cells),
        entry_md=md[:, 0],
        exit_md=md[:, 1],
        entry=RNG.uniform(0, 1000, (n, 3)),
        exit=RNG.uniform(0, 1000, (n, 3)),
        length=md[:, 1] - md[:, 0],
        axis_length=RNG.uniform(0, 50, (n, 3)),
        factor=RNG.lognormal(3, 1, n),
        direction=RNG.integers(0, 3, n),
    )


def _records() -> tuple[WellRecord, ...]:
    main = WellPath.from_points([(0, 0, 1900), (10, 0, 2000), (400, 0, 2010)], name="ML1", start_md=1900.0)
    branch = WellPath.from_points(
        [(200, 0, 2005.128205128205), (200, 300, 2010)], name="ML1:1", start_md=2200.0
    )
    p2 = WellPath(np.array([(50.0, 500, 1990), (60, 500, 2000)]), np.array([1990.0, 2005.0]), "P2")
    return (
        WellRecord(
            "ML1",
            (main, branch),
            _connections([7, 3, 11, 4]),
            parents=(0,),
            perforations=(np.array([[1950.0, 2100.0], [2200.0, 2290.0]]), np.array([[2200.0, 2400.0]])),
            radius=0.108,
            skin=2.5,
        ),
        WellRecord("P2", (p2,), _connections([5]), perforations=(np.array([[1990.0, 2005.0]]),), radius=0.1),
    )


def _same(a: WellRecord, b: WellRecord) -> None:
    assert (a.name, a.parents, a.radius, a.skin) == (b.name, b.parents, b.radius, b.skin)
    assert len(a.paths) == len(b.paths) and len(a.perforations) == len(b.perforations)
    for p, q in zip(a.paths, b.paths, strict=True):
        assert p.name == q.name
        np.testing.assert_array_equal(p.xyz, q.xyz)
        np.testing.assert_array_equal(p.md, q.md)
    for f, g in zip(a.perforations, b.perforations, strict=True):
        np.testing.assert_array_equal(f, g)
    for field in (
        "cell",
        "entry_md",
        "exit_md",
        "entry",
        "exit",
        "length",
        "axis_length",
        "factor",
        "direction",
    ):
        x, y = getattr(a.connections, field), getattr(b.connections, field)
        np.testing.assert_array_equal(x, y)
        assert x.dtype == y.dtype, field


def test_wells_round_trip_bit_for_bit_with_units_and_ijk(tmp_path):
    records = _records()
    index_map = np.arange(20) + 100  # cells of a 10 x 4 x 3 box, from cell 100 (i, j, k) = (1, 3, 3)
    write_wells(tmp_path / "wells.nc", records, FIELD, attrs={"case_name": "c"}, cart_dims=(10, 4, 3),
                index_map=index_map)  # fmt: skip
    back = read_wells(tmp_path / "wells.nc")
    assert len(back) == 2
    for a, b in zip(records, back, strict=True):
        _same(a, b)
    with xr.open_dataset(tmp_path / "wells.nc") as ds:
        assert (ds.attrs["unit_system"], ds.attrs["case_name"], int(ds.attrs["has_factors"])) == (
            "FIELD",
            "c",
            1,
        )
        units = {name: ds[name].attrs.get("units") for name in ds.variables}
        assert units["completion_factor"] == "cP rb/(day psi)"
        assert units["path_md"] == units["completion_axis_length"] == units["well_radius"] == "ft"
        assert units["completion_cell"] is None and units["well_skin"] == "1"
        assert ds["completion_ijk"].values.tolist() == [[8, 3, 3], [4, 3, 3], [2, 4, 3], [5, 3, 3], [6, 3, 3]]
        assert ds["well_completion_pos"].values.tolist() == [0, 4, 5]
        assert ds["path_parent"].values.tolist() == [-1, 0, -1]
        assert ds["completion_direction"].attrs["flag_meanings"] == "x y z"


def test_a_grid_without_logical_indices_has_no_ijk(tmp_path):
    records = _records()[1:]
    write_wells(tmp_path / "wells.nc", records, METRIC, attrs={}, has_factors=False)
    with xr.open_dataset(tmp_path / "wells.nc") as ds:
        assert "completion_ijk" not in ds and int(ds.attrs["has_factors"]) == 0
        assert ds["completion_factor"].attrs["units"] == "cP m3/(day bar)"
    _same(read_wells(tmp_path / "wells.nc")[0], records[0])


def test_offsets_that_do_not_fit_their_tables_are_one_error_naming_the_file(tmp_path):
    path = tmp_path / "wells.nc"
    write_wells(path, _records(), METRIC, attrs={})
    with xr.open_dataset(path) as ds:
        broken = ds.load()
    broken["well_completion_pos"].values[1] = 9
    broken.to_netcdf(tmp_path / "broken.nc")
    with pytest.raises(InputError) as info:
        read_wells(tmp_path / "broken.nc")
    assert str(info.value) == (
        f"{tmp_path / 'broken.nc'}: damaged or incomplete (its wells do not fit together (ValueError: "
        "well_completion_pos do not cover their 5 rows)); delete it and rerun the workflow"
    )
