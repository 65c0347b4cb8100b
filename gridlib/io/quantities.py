"""What every variable and table column gridlib writes measures: ONE table, from which every
netCDF file's ``units`` attributes and every table header's unit come (the unit itself from
the case's :class:`~gridlib.units.UnitSystem`, :meth:`~gridlib.units.UnitSystem.unit`).

:data:`VARIABLES` maps a variable name to its quantity (:data:`gridlib.units.QUANTITIES`), or
to None where the values are no physical quantity: indices, flags, counts, ids (no ``units``
attribute, as CF wants for them). A variable of the same name means the same thing in every
file (``cell_volume`` in ``geometry.nc`` and ``{case}.nc``, ``porv`` in ``transmissibility.nc``
and ``{case}.nc``). The UGRID footprint of a layered grid (``mesh2d_*``, ``areal_*``) and the
layered views of cell data (``<name>_layered``) measure what their base name measures.
:data:`COLUMNS` does the same for the figures of ``summary.json`` (``summary.csv``,
``study.csv``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..quality import MEASURES
from ..units import UnitSystem

# the flags of xtgeo's cell-quality set (0 or 1; concave_proj 0 or the concave corner + 1)
FLAG_NAMES = tuple(
    m.name
    for m in MEASURES
    if m.name in ("collapsed", "faulted", "negative_thickness") or m.name.startswith("concave")
)

VARIABLES: dict[str, str | None] = {
    # the grid (grid.nc, coarse.nc, {case}.nc): node coordinates, z is depth
    "node_x": "length",
    "node_y": "length",
    "node_z": "length",
    # geometry (geometry.nc, {case}.nc)
    "cell_volume": "cell_measure",
    "cell_centroid": "length",
    "face_area": "face_measure",
    "face_normal": "face_measure",  # area-weighted
    "face_centroid": "length",
    "cell_normal": "cell_measure",  # area-weighted normal of a surface cell
    # the builders' cell data (grid.nc, {case}.nc)
    "bulk_volume": "volume",  # ECLIPSE's bulk volume of a corner-point cell
    "depth": "length",
    "layer": None,
    "zone": None,
    "well": None,
    "site": "length",  # the generating site (x, y) of a PEBI cell's column
    "degenerate": None,
    # rock (petrophysics.nc, coarse.nc, {case}.nc)
    "poro": "fraction",
    "ntg": "fraction",
    "permx": "permeability",
    "permy": "permeability",
    "permz": "permeability",
    "pore_volume": "cell_measure",  # geometric: cell volume x poro x ntg
    # coarse.nc
    "volume": "cell_measure",
    "partition": None,
    "block": None,
    # connections (transmissibility.nc, {case}.nc)
    "trans": "transmissibility",
    "porv": "porv",
    "connection_cells": None,
    "connection_kind": None,
    "connection_face": None,
    "cell_flow_index": None,
    # wells.nc: deviated wells, their paths and connections (gridlib.io.wells_file)
    "well_name": None,
    "well_radius": "length",
    "well_skin": "dimensionless",
    "well_path_pos": None,
    "well_completion_pos": None,
    "path_name": None,
    "path_parent": None,
    "path_point_pos": None,
    "path_perforation_pos": None,
    "path_xyz": "length",
    "path_md": "length",
    "perforation_md": "length",
    "completion_cell": None,
    "completion_ijk": None,
    "completion_entry_md": "length",
    "completion_exit_md": "length",
    "completion_entry": "length",
    "completion_exit": "length",
    "completion_length": "length",
    "completion_axis_length": "length",
    "completion_factor": "transmissibility",  # a well's connection factor: a transmissibility
    "completion_direction": None,
    # topology and indices
    "cell_face_pos": None,
    "cell_faces": None,
    "face_node_pos": None,
    "face_nodes": None,
    "face_neighbors": None,
    "face_tag": None,
    "cell_face_tag": None,
    "cell_index_map": None,
    "index_map": None,
    "cell_column": None,
    "cell_layer": None,
    "mesh2d": None,
    "edge_nodes": None,  # mesh2d_edge_nodes
    "nnc_cells": None,
    "nnc_global_cells": None,
    "nnc_kind": None,
    "nnc_face": None,
    # quality.nc, {case}.nc: the cell-quality measures (gridlib.quality; degrees, ratios; flags none)
    **{m.name: None if m.name in FLAG_NAMES else m.unit for m in MEASURES},
}

COLUMNS: dict[str, str] = {
    "total_volume": "cell_measure",
    "min_cell_volume": "cell_measure",
    "max_cell_volume": "cell_measure",
    "total_face_area": "face_measure",
    "total_bulk_volume": "volume",
    "pore_volume": "cell_measure",
    "mean_porosity": "fraction",
    "mean_permx": "permeability",
    "min_trans": "transmissibility",
    "median_trans": "transmissibility",
    "max_trans": "transmissibility",
    "total_porv": "porv",
    "orientation_median": "angle",
    "orientation_p95": "angle",
    "orientation_max": "angle",
    "k_orientation_median": "angle",
    "k_orientation_p95": "angle",
    "k_orientation_max": "angle",
    # per well of summary.json's ``trajectory_wells``
    "completed_length": "length",
    "total_factor": "transmissibility",
}


def quantity_of(name: str) -> str | None:
    """The quantity variable ``name`` measures (None: no physical quantity); a KeyError for a
    name :data:`VARIABLES` does not know."""
    for prefix in ("mesh2d_", "areal_"):
        if name.startswith(prefix) and name != "mesh2d":
            name = name[len(prefix) :]
    if name.endswith("_layered"):
        name = name[: -len("_layered")]
    return VARIABLES[name]


def units_of(names: Any, system: UnitSystem, griddim: int) -> dict[str, str]:
    """The ``units`` attribute of each of ``names`` that :data:`VARIABLES` knows as a physical
    quantity, in ``system`` (names it does not know, a user's data, are left out)."""
    out = {}
    for name in names:
        try:
            quantity = quantity_of(str(name))
        except KeyError:
            continue
        if quantity is not None:
            out[str(name)] = system.unit(quantity, griddim)
    return out


def label_units(variables: Mapping[Any, Any], system: UnitSystem, griddim: int) -> None:
    """Set the ``units`` attribute of every physical variable of ``variables`` (an xarray
    Dataset's ``variables``, or a mapping of name to xarray Variable) in ``system``."""
    for name, unit in units_of(variables, system, griddim).items():
        variables[name].attrs["units"] = unit


PICTURE_TITLES = {"poro": "porosity"}  # what pictures call a variable, where not its name


def picture_quantity(name: str, system: UnitSystem, griddim: int = 3) -> tuple[str, str | None]:
    """What a picture calls variable ``name`` (an axis, a colour bar, a histogram) and the unit
    it writes: the variable's ``units`` attribute in ``system``, but ``fraction`` for a
    dimensionless fraction (stored as "1"); None where it is no physical quantity or not in
    :data:`VARIABLES`. ``volume`` is the cell measure: a cell's volume, or a 2-D cell's area.

    >>> from gridlib.units import FIELD
    >>> picture_quantity("poro", FIELD), picture_quantity("depth", FIELD), picture_quantity("zone", FIELD)
    (('porosity', 'fraction'), ('depth', 'ft'), ('zone', None))
    >>> picture_quantity("volume", FIELD, griddim=2)
    ('cell area', 'ft2')
    """
    if name == "volume":
        return ("cell volume" if griddim == 3 else "cell area"), system.unit("cell_measure", griddim)
    title = PICTURE_TITLES.get(name, name)
    try:
        quantity = quantity_of(name)
    except KeyError:
        return title, None
    if quantity is None:
        return title, None
    return title, "fraction" if quantity == "fraction" else system.unit(quantity, griddim)


def picture_label(name: str, system: UnitSystem, griddim: int = 3) -> str:
    """``title [unit]`` of :func:`picture_quantity` (the title alone without a unit).

    >>> from gridlib.units import FIELD
    >>> picture_label("poro", FIELD), picture_label("depth", FIELD), picture_label("zone", FIELD)
    ('porosity [fraction]', 'depth [ft]', 'zone')
    """
    title, unit = picture_quantity(name, system, griddim)
    return title if unit is None else f"{title} [{unit}]"
