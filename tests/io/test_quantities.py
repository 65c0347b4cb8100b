"""Units of what gridlib writes (issue 24, item 7): every unit from one table of quantities
(gridlib.io.quantities) and the case's unit system; netCDF files, table headers and the axis
labels of the pictures say the unit of the values they hold. In-process, on small grids."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import gridlib as gl
from gridlib.errors import GridError, InputError
from gridlib.io import read_netcdf
from gridlib.io.flow_results import FlowSummary
from gridlib.io.netcdf import write_geometry_netcdf, write_netcdf
from gridlib.io.pictures import histogram_figure
from gridlib.io.quantities import VARIABLES, quantity_of
from gridlib.io.rock_file import UNITS as ROCK_UNITS
from gridlib.io.summary_table import figure_name, header, write_csv
from gridlib.stages.simulate import wells_figure
from gridlib.units import FIELD, LAB, METRIC, QUANTITIES, UNIT_SYSTEMS

# The labels, written out by hand (not from the code under test).
EXPECTED = {
    "METRIC": ("m", "m2", "m3", "rm3", "mD", "cP m3/(day bar)"),
    "FIELD": ("ft", "ft2", "ft3", "rb", "mD", "cP rb/(day psi)"),
    "LAB": ("cm", "cm2", "cm3", "rcc", "mD", "cP cm3/(h atm)"),
    "PVT-M": ("m", "m2", "m3", "rm3", "mD", "cP m3/(day atm)"),
}


def test_each_quantity_in_each_unit_system():
    for name, system in UNIT_SYSTEMS.items():
        quantities = ("length", "area", "volume", "porv", "permeability", "transmissibility")
        assert tuple(system.unit(q) for q in quantities) == EXPECTED[name]
        length, area, volume = EXPECTED[name][:3]
        assert (system.unit("cell_measure"), system.unit("face_measure")) == (volume, area)
        assert (system.unit("cell_measure", 2), system.unit("face_measure", 2)) == (area, length)
        assert system.unit("fraction") == "1"  # CF's dimensionless
    with pytest.raises(ValueError, match="unknown quantity 'speed'"):
        METRIC.unit("speed")


def test_the_table_names_only_known_quantities():
    assert {q for q in VARIABLES.values() if q is not None} <= set(QUANTITIES)
    assert quantity_of("mesh2d_node_x") == quantity_of("areal_node_x") == "length"
    assert quantity_of("poro_layered") == "fraction" and quantity_of("mesh2d_face_nodes") is None
    assert ROCK_UNITS == {"poro": "1", "ntg": "1", "permx": "mD", "permy": "mD", "permz": "mD"}
    for system in UNIT_SYSTEMS.values():  # so petrophysics.nc needs no unit system
        assert {n: system.unit(quantity_of(n)) for n in ROCK_UNITS} == ROCK_UNITS


def _box(tmp_path, units):
    grid = gl.cart_grid((3, 2, 2), (30.0, 20.0, 4.0))
    geo = gl.compute_geometry(grid)
    path = tmp_path / f"{units}.nc"
    depth = geo.cell_centroids[:, 2]
    write_netcdf(path, grid, geo, cell_data={"depth": depth, "mine": depth}, units=units)
    return path, grid, geo


def test_a_field_grid_file_is_labelled_in_feet_and_its_values_stay(tmp_path):
    path, grid, geo = _box(tmp_path, "FIELD")
    with xr.open_dataset(path) as ds:
        assert ds.attrs["unit_system"] == "FIELD"
        units = {n: ds[n].attrs.get("units") for n in ds.variables}
        np.testing.assert_array_equal(ds["cell_volume"].values, geo.cell_volumes)  # labels only
    assert units["node_x"] == units["node_z"] == units["cell_centroid"] == units["depth"] == "ft"
    assert (units["cell_volume"], units["face_area"], units["face_normal"]) == ("ft3", "ft2", "ft2")
    assert units["face_neighbors"] is None and units["mine"] is None  # no quantity; a user's own
    assert read_netcdf(path).attrs["unit_system"] == "FIELD"
    geometry = tmp_path / "geometry.nc"
    write_geometry_netcdf(geometry, geo, 3, {"unit_system": "FIELD"})  # the unit system by attribute
    with xr.open_dataset(geometry) as ds:
        assert {n: ds[n].attrs["units"] for n in ds.variables} == {
            "cell_volume": "ft3",
            "cell_centroid": "ft",
            "face_area": "ft2",
            "face_normal": "ft2",
            "face_centroid": "ft",
        }
    with pytest.raises(GridError, match="units METRIC but attribute unit_system FIELD"):
        write_netcdf(tmp_path / "x.nc", grid, attrs={"unit_system": "FIELD"}, units=METRIC)


def test_a_2d_grid_measures_cells_in_areas_and_faces_in_lengths(tmp_path):
    grid = gl.cart_grid((3, 2), (30.0, 20.0))
    geo = gl.compute_geometry(grid)
    write_netcdf(tmp_path / "lab.nc", grid, geo, units=LAB)
    with xr.open_dataset(tmp_path / "lab.nc") as ds:
        assert (ds["cell_volume"].attrs["units"], ds["face_area"].attrs["units"]) == ("cm2", "cm")
        assert ds["mesh2d_node_x"].attrs["units"] == "cm"


def _rows():
    return [
        {
            "case": "a",
            "griddim": 3,
            "unit_system": "METRIC",
            "total_volume": 8.0,
            "mean_permx": 1.0,
            "cells": 2,
        },
        {
            "case": "b",
            "griddim": 3,
            "unit_system": "FIELD",
            "total_volume": 9.0,
            "mean_permx": 2.0,
            "cells": 3,
        },
        {
            "case": "c",
            "griddim": 2,
            "unit_system": "METRIC",
            "total_volume": 4.0,
            "mean_permx": 3.0,
            "cells": 4,
        },
    ]


def test_table_headers_give_each_rows_unit(tmp_path):
    rows = _rows()
    assert header("total_volume", rows[:1]) == "total_volume [m3]"
    assert header("total_volume", rows) == "total_volume [m3: METRIC 3-D; ft3: FIELD 3-D; m2: METRIC 2-D]"
    assert header("total_volume", rows[:2]) == "total_volume [m3: METRIC; ft3: FIELD]"
    assert header("mean_permx", rows) == "mean_permx [mD]"  # the same in every system
    assert header("total_volume", [*rows[:1], {**rows[1], "total_volume": ""}]) == "total_volume [m3]"
    assert header("cells", rows) == "cells" and figure_name("total_volume [m3]") == "total_volume"
    columns = ("case", "griddim", "unit_system", "cells", "total_volume", "mean_permx")
    write_csv(tmp_path / "t.csv", columns, rows[:2])
    lines = (tmp_path / "t.csv").read_text().splitlines()
    assert lines[0] == "case,griddim,unit_system,cells,total_volume [m3: METRIC; ft3: FIELD],mean_permx [mD]"
    assert lines[2] == "b,3,FIELD,3,9.0,2.0"
    with pytest.raises(InputError, match="the summary of case a has no unit_system"):
        header("total_volume", [{"case": "a", "griddim": 3, "total_volume": 1.0}])


def _labels(fig):
    import matplotlib.pyplot as plt

    labels = [(ax.get_xlabel(), ax.get_ylabel()) for ax in fig.axes]
    plt.close(fig)
    return labels


def test_histogram_axes_carry_the_units_of_the_case():
    grid = gl.cart_grid((3, 2, 2), (30.0, 20.0, 4.0))
    geo = gl.compute_geometry(grid)
    poro, trans = np.full(12, 0.2), np.array([1.0, 10.0, 100.0])
    fig = histogram_figure(geo, poro, 3, "spe9", FIELD, trans)
    assert _labels(fig) == [
        ("cell volume [ft3]", "count"),
        ("face area [ft2]", "count"),
        ("porosity [fraction]", "count"),
        ("log10 T, T in cP rb/(day psi)", "count"),
    ]
    flat = gl.cart_grid((3, 2), (30.0, 20.0))
    fig = histogram_figure(gl.compute_geometry(flat), None, 2, "flat", METRIC)
    assert _labels(fig) == [("cell area [m2]", "count"), ("face length [m]", "count")]


def test_the_wells_picture_labels_rates_and_pressures_in_the_decks_units():
    t = np.array([1.0, 2.0, 3.0])
    summary = FlowSummary(t, np.array([2]), {("WOPR", "P1"): t, ("WBHP", "P1"): 3000.0 + t})
    fig = wells_figure(summary, "spe9: wells", FIELD)
    assert fig.get_suptitle() == "spe9: wells (FIELD)"
    assert _labels(fig) == [
        ("time [day]", "surface rate [stb/day]"),
        ("time [day]", "bottom-hole pressure [psia]"),
    ]
