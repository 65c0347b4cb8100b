"""netCDF-4 files of grids, geometry and cell/face data (xarray + netCDF4).

Layout
------
The full topology is stored as ragged offset arrays, so any grid round-trips
bit for bit:

* ``face_nodes`` + ``face_node_pos``, ``cell_faces`` + ``cell_face_pos``,
  ``face_neighbors`` (face, 2) with -1 for outside, ``face_tag``, optional
  ``cell_face_tag`` (W, E, S, N, T, B = 0..5) and ``cell_index_map``;
* node coordinates ``node_x``, ``node_y`` (and ``node_z``, depth, ``positive = "down"``);
* geometry (optional): ``cell_volume``, ``cell_centroid``, ``face_area``,
  ``face_normal``, ``face_centroid`` (vectors on a ``xyz`` dimension); a file may
  leave out the two face vectors (``face_vectors=False``: a case's ``{case}.nc``
  does, they are 40 % of its bytes), and :func:`read_netcdf` then recomputes them
  from the grid (:func:`~gridlib.geometry.compute_geometry`, the same bits);
* any number of cell variables (dimension of the cells) and face variables;
* global attributes ``gridlib_griddim``, ``gridlib_cart_dims``,
  ``gridlib_history`` (JSON) and any user attributes (provenance).

For UGRID-1.0 tools (xugrid, QGIS, ParaView's UGRID reader) a 2-D mesh
``mesh2d`` is added: the grid itself for planar 2-D grids (our cells are its
faces, our faces its edges, sharing the dimensions), and for layered grids the
areal footprint with ``cell_column``/``cell_layer`` and, for every float cell
variable, a ``(layer, mesh2d_nFaces)`` view named ``<name>_layered`` (NaN where
a cell is missing). ``Conventions = "CF-1.11 UGRID-1.0"`` is set then.
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import xarray as xr
from xarray.backends.common import BackendArray
from xarray.core import indexing

from ..connectivity import cell_node_cycles_2d
from ..errors import GridError
from ..geometry import Geometry, compute_geometry
from ..grid import Cells, Faces, Grid, Layering, Nodes
from ..units import UnitSystem, unit_system
from .datasets import open_artifact, read_variable, save_dataset
from .deferred import Deferred
from .quantities import label_units
from .shared_reads import read_once, shared

_AXES = ("x", "y", "z")


@dataclass(frozen=True, eq=False)
class GridDataset:
    """Everything a gridlib netCDF file holds."""

    grid: Grid
    geometry: Geometry | None = None
    cell_data: dict[str, np.ndarray] = field(default_factory=dict)
    face_data: dict[str, np.ndarray] = field(default_factory=dict)
    attrs: dict[str, object] = field(default_factory=dict)


def _dims(grid: Grid) -> dict[str, str]:
    if grid.griddim == 2 and grid.dim == 2:
        return {"cell": "mesh2d_nFaces", "face": "mesh2d_nEdges", "node": "mesh2d_nNodes"}
    return {"cell": "cell", "face": "face", "node": "node"}


def _topology_vars(grid: Grid, prefix: str, dims: dict[str, str]) -> dict[str, xr.Variable]:
    p = prefix
    out = {
        f"{p}cell_face_pos": xr.Variable(f"{p}cell_face_pos_dim", grid.cells.face_pos),
        f"{p}cell_faces": xr.Variable(f"{p}half_face", grid.cells.faces),
        f"{p}face_node_pos": xr.Variable(f"{p}face_node_pos_dim", grid.faces.node_pos),
        f"{p}face_nodes": xr.Variable(f"{p}face_node", grid.faces.nodes),
        f"{p}face_neighbors": xr.Variable(
            (dims["face"], "two"),
            grid.faces.neighbors,
            {"long_name": "cells on either side of each face, -1 = outside", "start_index": 0},
        ),
        f"{p}face_tag": xr.Variable(
            dims["face"], grid.faces.tag, {"long_name": "0 = ordinary, >0 = fault id"}
        ),
    }
    if grid.cells.face_tag is not None:
        out[f"{p}cell_face_tag"] = xr.Variable(
            f"{p}half_face",
            grid.cells.face_tag,
            {"flag_meanings": "W E S N T B", "flag_values": np.arange(6)},
        )
    if grid.cells.index_map is not None:
        out[f"{p}cell_index_map"] = xr.Variable(dims["cell"], grid.cells.index_map)
    for i in range(grid.dim):
        attrs = {"standard_name": f"projection_{_AXES[i]}_coordinate"}
        if i == 2:
            attrs = {"positive": "down", "long_name": "depth"}
        out[f"{p}node_{_AXES[i]}"] = xr.Variable(dims["node"], grid.nodes.coords[:, i], attrs)
    return out


def _grid_attrs(grid: Grid, prefix: str) -> dict[str, object]:
    attrs: dict[str, object] = {
        f"{prefix}gridlib_griddim": np.int32(grid.griddim),
        f"{prefix}gridlib_history": json.dumps(list(grid.history)),
    }
    if grid.cart_dims is not None:
        attrs[f"{prefix}gridlib_cart_dims"] = np.asarray(grid.cart_dims, dtype=np.int64)
    return attrs


def _ugrid_mesh(areal: Grid, dims: dict[str, str]) -> dict[str, xr.Variable]:
    """UGRID-1.0 2-D mesh topology of a planar grid (our cells = its faces)."""
    pos, cyc = cell_node_cycles_2d(areal)
    counts = np.diff(pos)
    width = int(counts.max())
    table = np.full((areal.num_cells, width), -1, dtype=np.int64)
    owner = np.repeat(np.arange(areal.num_cells), counts)
    table[owner, np.arange(cyc.size) - pos[owner]] = cyc
    mesh_attrs = {
        "cf_role": "mesh_topology",
        "long_name": "areal footprint (UGRID-1.0 2-D mesh)",
        "topology_dimension": np.int32(2),
        "node_coordinates": "mesh2d_node_x mesh2d_node_y",
        "face_node_connectivity": "mesh2d_face_nodes",
        "edge_node_connectivity": "mesh2d_edge_nodes",
        "face_dimension": dims["cell"],
        "edge_dimension": dims["face"],
        "max_face_nodes_dimension": "mesh2d_nMax_face_nodes",
    }
    conn = {"start_index": np.int64(0), "cf_role": "face_node_connectivity"}
    return {
        "mesh2d": xr.Variable((), np.int32(0), mesh_attrs),
        "mesh2d_node_x": xr.Variable(
            dims["node"], areal.nodes.coords[:, 0], {"standard_name": "projection_x_coordinate"}
        ),
        "mesh2d_node_y": xr.Variable(
            dims["node"], areal.nodes.coords[:, 1], {"standard_name": "projection_y_coordinate"}
        ),
        "mesh2d_face_nodes": xr.Variable((dims["cell"], "mesh2d_nMax_face_nodes"), table, conn),
        "mesh2d_edge_nodes": xr.Variable(
            (dims["face"], "two"),
            areal.faces.nodes.reshape(-1, 2),
            {"start_index": np.int64(0), "cf_role": "edge_node_connectivity"},
        ),
    }


FACE_VECTORS = ("face_normal", "face_centroid")  # the geometry a file may leave out


def _geometry_vars(geo: Geometry, dims: dict[str, str], face_vectors: bool = True) -> dict[str, xr.Variable]:
    c, f = dims["cell"], dims["face"]
    out = {
        "cell_volume": xr.Variable(c, geo.cell_volumes),
        "cell_centroid": xr.Variable((c, "xyz"), geo.cell_centroids),
        "face_area": xr.Variable(f, geo.face_areas),
    }
    if face_vectors:
        out["face_normal"] = xr.Variable((f, "xyz"), geo.face_normals, {"long_name": "area-weighted normal"})
        out["face_centroid"] = xr.Variable((f, "xyz"), geo.face_centroids)
    if geo.cell_normals is not None:
        out["cell_normal"] = xr.Variable((c, "xyz3"), geo.cell_normals)
    return out


def _data_vars(
    data: Mapping[str, np.ndarray | Deferred], n: int, dim: str, what: str
) -> dict[str, xr.Variable]:
    out = {}
    for name, values in data.items():
        arr = values if isinstance(values, Deferred) else np.asarray(values)
        if arr.shape[:1] != (n,):
            raise GridError(f"write_netcdf: {what} data '{name}' has shape {arr.shape}, expected ({n}, ...)")
        extra = tuple(f"{name}_dim{i}" for i in range(1, arr.ndim))
        out[name] = xr.Variable((dim, *extra), deferred_data(arr) if isinstance(arr, Deferred) else arr)
    return out


class _DeferredBackend(BackendArray):
    """A :class:`~gridlib.io.deferred.Deferred` array as xarray's lazy arrays: read when the
    dataset is written (xarray writes, and so reads, one variable at a time)."""

    def __init__(self, deferred: Deferred) -> None:
        self.deferred = deferred
        self.shape = tuple(deferred.shape)
        self.dtype = np.dtype(deferred.dtype)

    def __getitem__(self, key: indexing.ExplicitIndexer) -> np.ndarray:
        return indexing.explicit_indexing_adapter(key, self.shape, indexing.IndexingSupport.BASIC, self._read)

    def _read(self, key: tuple) -> np.ndarray:
        return np.asarray(self.deferred)[key]


def deferred_data(deferred: Deferred) -> indexing.LazilyIndexedArray:
    """The data of an ``xr.Variable`` read only when it is written (:func:`write_netcdf`'s
    ``extra`` takes such variables; its ``cell_data`` the :class:`Deferred` arrays themselves)."""
    return indexing.LazilyIndexedArray(_DeferredBackend(deferred))


def _attr_value(key: str, value: object) -> object:
    """A value netCDF can store as an attribute, or a GridError naming the key."""
    if isinstance(value, bool | np.bool_) or value is None:
        raise GridError(
            f"write_netcdf: attribute '{key}' is {value!r}; netCDF attributes hold str or numbers"
        )
    if isinstance(value, str | int | float | np.integer | np.floating):
        return value
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":
        return value
    try:
        return json.dumps(value)
    except TypeError as exc:
        raise GridError(
            f"write_netcdf: attribute '{key}' of type {type(value).__name__} cannot be stored"
        ) from exc


def grid_to_dataset(
    grid: Grid,
    geometry: Geometry | None = None,
    cell_data: Mapping[str, np.ndarray | Deferred] | None = None,
    face_data: dict[str, np.ndarray] | None = None,
    attrs: Mapping[str, object] | None = None,
    *,
    face_vectors: bool = True,
    units: UnitSystem | str | None = None,
) -> xr.Dataset:
    """The xarray Dataset that :func:`write_netcdf` writes; ``face_vectors=False`` leaves the
    geometry's face normals and centroids out (readers recompute them); ``units``: the unit
    system of the grid's coordinates (default: the ``unit_system`` of ``attrs``, else METRIC),
    written as the attribute ``unit_system`` and the ``units`` of every physical variable
    (:mod:`gridlib.io.quantities`)."""
    attrs = dict(attrs or {})
    system = _unit_system_of(units, attrs)
    attrs["unit_system"] = system.name
    dims = _dims(grid)
    variables = _topology_vars(grid, "", dims)
    ds_attrs: dict[str, object] = {"Conventions": "CF-1.11", "title": "gridlib grid"}
    ds_attrs.update(_grid_attrs(grid, ""))
    if geometry is not None:
        if geometry.cell_volumes.shape != (grid.num_cells,) or geometry.face_areas.shape != (grid.num_faces,):
            raise GridError("write_netcdf: the geometry does not belong to this grid (sizes differ)")
        variables.update(_geometry_vars(geometry, dims, face_vectors))
    derived: dict[str, xr.Variable] = {}
    if grid.griddim == 2 and grid.dim == 2:
        derived.update(_ugrid_mesh(grid, dims))
        ds_attrs["Conventions"] = "CF-1.11 UGRID-1.0"
    elif grid.layering is not None:
        lay = grid.layering
        areal_dims = {"cell": "mesh2d_nFaces", "face": "mesh2d_nEdges", "node": "mesh2d_nNodes"}
        derived.update(_ugrid_mesh(lay.areal, areal_dims))
        variables.update(_topology_vars(lay.areal, "areal_", areal_dims))
        ds_attrs.update(_grid_attrs(lay.areal, "areal_"))
        ds_attrs["gridlib_num_layers"] = np.int64(lay.num_layers)
        variables["cell_column"] = xr.Variable(
            dims["cell"], lay.column, {"long_name": "areal cell (mesh2d face)"}
        )
        variables["cell_layer"] = xr.Variable(dims["cell"], lay.layer, {"long_name": "layer, 0 = top"})
        for name, values in (cell_data or {}).items():
            arr = np.asarray(values)
            if arr.shape == (grid.num_cells,) and np.issubdtype(arr.dtype, np.floating):
                view = np.full((lay.num_layers, lay.areal.num_cells), np.nan)
                view[lay.layer, lay.column] = arr
                derived[f"{name}_layered"] = xr.Variable(
                    ("layer", "mesh2d_nFaces"), view, {"mesh": "mesh2d", "location": "face"}
                )
        ds_attrs["Conventions"] = "CF-1.11 UGRID-1.0"
    user = {
        **_data_vars(cell_data or {}, grid.num_cells, dims["cell"], "cell"),
        **_data_vars(face_data or {}, grid.num_faces, dims["face"], "face"),
    }
    clash = sorted(set(user) & (set(variables) | set(derived) | _RESERVED))
    if clash:
        raise GridError(f"write_netcdf: data names {clash} are used by gridlib's own variables; rename them")
    if len(user) != len(cell_data or {}) + len(face_data or {}):
        raise GridError("write_netcdf: the same name is used for cell data and face data")
    ds_attrs["gridlib_variables"] = json.dumps(sorted(set(variables) | set(derived)))
    for key, value in (attrs or {}).items():
        if key.startswith(("gridlib_", "areal_gridlib_")) and key != "gridlib_version":
            raise GridError(f"write_netcdf: attribute name '{key}' is reserved")
        ds_attrs[key] = _attr_value(key, value)
    ds = xr.Dataset({**variables, **derived, **user}, attrs=ds_attrs)
    label_units(ds.variables, system, grid.griddim)
    return ds


def _unit_system_of(units: UnitSystem | str | None, attrs: Mapping[str, object]) -> UnitSystem:
    """``units``, else the ``unit_system`` of ``attrs``, else METRIC; a GridError where both
    are given and differ."""
    stated = attrs.get("unit_system")
    system = unit_system(units if units is not None else (None if stated is None else str(stated)))
    if stated is not None and unit_system(str(stated)) is not system:
        raise GridError(f"write_netcdf: units {system.name} but attribute unit_system {stated}")
    return system


def write_netcdf(
    path: str | os.PathLike,
    grid: Grid,
    geometry: Geometry | None = None,
    cell_data: Mapping[str, np.ndarray | Deferred] | None = None,
    face_data: dict[str, np.ndarray] | None = None,
    attrs: Mapping[str, object] | None = None,
    *,
    extra: Mapping[str, xr.DataArray | xr.Variable] | None = None,
    var_attrs: Mapping[str, Mapping[str, object]] | None = None,
    face_vectors: bool = True,
    units: UnitSystem | str | None = None,
) -> Path:
    """Write a grid (and optionally geometry, cell/face data, attributes) to netCDF-4.

    ``extra``: variables with dimensions of their own (e.g. the NNC list, a partition of the
    fine cells); ``var_attrs``: attributes (units, long names) of data variables, by name;
    ``face_vectors=False``: the geometry's face normals and centroids left out; ``units``: the
    unit system of the grid (see :func:`grid_to_dataset`; the ``units`` of the ``extra``
    variables too). The write is atomic: on any error no file is left at ``path``.
    Cell data given as :class:`~gridlib.io.deferred.Deferred` arrays, and ``extra`` variables
    whose data is :func:`deferred_data`, are read one at a time as they are written (a grid
    with a ``layering`` reads its float cell data once more for the layered views).
    """
    ds = grid_to_dataset(grid, geometry, cell_data, face_data, attrs, face_vectors=face_vectors, units=units)
    for name, var in (extra or {}).items():
        ds[name] = var
    for name, meta in (var_attrs or {}).items():
        ds[name].attrs.update(meta)
    label_units(ds.variables, unit_system(str(ds.attrs["unit_system"])), grid.griddim)
    return write_dataset(path, ds)


def write_dataset(path: str | os.PathLike, ds: xr.Dataset) -> Path:
    """Write an xarray Dataset (a grid's from :func:`grid_to_dataset`, or any other) as
    netCDF-4, atomically: integers and booleans without fill values, the UGRID face-node
    table padded with -1 (its ``_FillValue``)."""
    encoding = {name: {"_FillValue": None} for name in ds.variables if ds[name].dtype.kind in "iub"}
    if "mesh2d_face_nodes" in ds:
        encoding["mesh2d_face_nodes"] = {"_FillValue": np.int64(-1)}
    return save_dataset(path, ds, encoding)


def _read_grid(ds: xr.Dataset, prefix: str) -> Grid:
    """The grid (``prefix``: "" or "areal_") of a file opened by :func:`open_artifact`."""
    p = prefix

    def var(name: str, ndim: int = 1) -> np.ndarray:
        return read_variable(ds, f"{p}{name}", "f" if name.startswith("node_") else "iu", ndim)

    def optional(name: str) -> np.ndarray | None:
        return var(name) if f"{p}{name}" in ds.variables else None

    griddim = int(ds.attrs.get(f"{p}gridlib_griddim", 0))
    if griddim not in (2, 3):
        raise ValueError(f"attribute '{p}gridlib_griddim' missing or not 2/3")
    axes = [var(f"node_{a}") for a in _AXES if f"{p}node_{a}" in ds.variables]
    if len(axes) < 2:
        raise ValueError(f"variable '{p}node_x' or '{p}node_y' is missing")
    cart = ds.attrs.get(f"{p}gridlib_cart_dims")
    history = tuple(json.loads(ds.attrs.get(f"{p}gridlib_history", "[]")))
    return Grid(
        cells=Cells(
            var("cell_face_pos"), var("cell_faces"), optional("cell_face_tag"), optional("cell_index_map")
        ),
        faces=Faces(var("face_node_pos"), var("face_nodes"), var("face_neighbors", 2), var("face_tag")),
        nodes=Nodes(np.column_stack(axes)),
        griddim=griddim,
        cart_dims=None if cart is None else tuple(int(v) for v in np.atleast_1d(cart)),
        history=history,
    )


_RESERVED = {
    "cell_face_pos", "cell_faces", "face_node_pos", "face_nodes", "face_neighbors", "face_tag",
    "cell_face_tag", "cell_index_map", "node_x", "node_y", "node_z", "cell_volume", "cell_centroid",
    "face_area", "face_normal", "face_centroid", "cell_normal", "cell_column", "cell_layer", "mesh2d",
    "mesh2d_node_x", "mesh2d_node_y", "mesh2d_face_nodes", "mesh2d_edge_nodes",
}  # fmt: skip


def _private(stored: GridDataset) -> GridDataset:
    """``stored`` with its own copies of what a caller may change (its data and attributes;
    the grid's and the geometry's arrays are read-only)."""
    return replace(
        stored,
        cell_data={name: values.copy() for name, values in stored.cell_data.items()},
        face_data={name: values.copy() for name, values in stored.face_data.items()},
        attrs=copy.deepcopy(stored.attrs),
    )


@read_once(_private)
def read_netcdf(path: str | os.PathLike) -> GridDataset:
    """Read a file written by :func:`write_netcdf` back into grid, geometry and data; any error
    reading it is one InputError naming the file (:func:`~gridlib.io.datasets.damaged`). Read
    once per run of a case's stages (:mod:`gridlib.io.shared_reads`)."""
    with open_artifact(path) as ds:
        return _grid_dataset(ds)


def _grid_dataset(ds: xr.Dataset) -> GridDataset:
    grid = _read_grid(ds, "")
    if "cell_column" in ds and "areal_cell_faces" in ds:
        areal = _read_grid(ds, "areal_")
        n_layers = int(ds.attrs["gridlib_num_layers"])
        layering = Layering(
            areal,
            read_variable(ds, "cell_column", "iu", 1),
            read_variable(ds, "cell_layer", "iu", 1),
            n_layers,
        )
        grid = Grid(grid.cells, grid.faces, grid.nodes, grid.griddim, grid.cart_dims, grid.history, layering)
    geometry = _geometry_from(ds, grid) if "cell_volume" in ds else None
    dims = _dims(grid)
    cell_data, face_data = {}, {}
    own = _RESERVED | set(json.loads(ds.attrs.get("gridlib_variables", "[]")))
    for name, v in ds.data_vars.items():
        if name in own:
            continue
        if v.dims and v.dims[0] == dims["cell"]:
            cell_data[name] = read_variable(ds, str(name), "biufUSO")
        elif v.dims and v.dims[0] == dims["face"]:
            face_data[name] = read_variable(ds, str(name), "biufUSO")
    for what, data, n in (("cell", cell_data, grid.num_cells), ("face", face_data, grid.num_faces)):
        wrong = [name for name, values in data.items() if values.shape[:1] != (n,)]
        if wrong:
            raise ValueError(
                f"{what} variable '{wrong[0]}' has {data[wrong[0]].shape[0]} values, expected {n}"
            )
    internal = {
        "gridlib_griddim",
        "gridlib_history",
        "gridlib_cart_dims",
        "gridlib_num_layers",
        "gridlib_variables",
    }
    attrs = {k: v for k, v in ds.attrs.items() if k not in internal and not k.startswith("areal_gridlib_")}
    return GridDataset(grid, geometry, cell_data, face_data, attrs)


def _geometry_from(ds: xr.Dataset, grid: Grid | None = None) -> Geometry:
    """The stored geometry; face normals and centroids recomputed from ``grid`` where the
    file leaves them out. Sizes are checked against ``grid``'s where given, else against each
    other."""
    if all(name in ds for name in FACE_VECTORS):
        normals, centroids = (read_variable(ds, name, "f", 2) for name in FACE_VECTORS)
    else:
        full = compute_geometry(grid)
        normals, centroids = full.face_normals, full.face_centroids
    geo = Geometry(
        read_variable(ds, "cell_volume", "f", 1),
        read_variable(ds, "cell_centroid", "f", 2),
        read_variable(ds, "face_area", "f", 1),
        normals,
        centroids,
        read_variable(ds, "cell_normal", "f", 2) if "cell_normal" in ds else None,
    )
    _check_geometry_sizes(geo, grid)
    return geo


def _check_geometry_sizes(geo: Geometry, grid: Grid | None) -> None:
    cells = grid.num_cells if grid is not None else geo.cell_volumes.size
    faces = grid.num_faces if grid is not None else geo.face_areas.size
    sizes = {
        "cell_volume": (geo.cell_volumes.shape[0], cells),
        "cell_centroid": (geo.cell_centroids.shape[0], cells),
        "face_area": (geo.face_areas.shape[0], faces),
    }
    if geo.face_normals.size:
        sizes["face_normal"] = (geo.face_normals.shape[0], faces)
    if geo.face_centroids.size:
        sizes["face_centroid"] = (geo.face_centroids.shape[0], faces)
    for name, (got, expected) in sizes.items():
        if got != expected:
            raise ValueError(f"variable '{name}' has {got} rows, expected {expected}")


def write_geometry_netcdf(
    path: str | os.PathLike,
    geometry: Geometry,
    griddim: int,
    attrs: dict[str, object] | None = None,
    units: UnitSystem | str | None = None,
) -> Path:
    """Geometry only (``cell`` and ``face`` dimensions), with a summary, atomically; ``units``:
    the unit system of the grid's coordinates (default: the ``unit_system`` of ``attrs``, else
    METRIC), written as the attribute ``unit_system`` and the ``units`` of every variable."""
    geo = geometry
    system = _unit_system_of(units, attrs or {})
    attrs = {**(attrs or {}), "unit_system": system.name}
    variables = _geometry_vars(geo, {"cell": "cell", "face": "face"})
    label_units(variables, system, griddim)
    summary = {
        "gridlib_griddim": np.int32(griddim),
        "total_volume": float(geo.cell_volumes.sum()),
        "min_cell_volume": float(geo.cell_volumes.min()),
        "max_cell_volume": float(geo.cell_volumes.max()),
        "min_face_area": float(geo.face_areas.min()),
    }
    user = {k: _attr_value(k, v) for k, v in (attrs or {}).items()}
    return save_dataset(path, xr.Dataset(variables, attrs={**user, **summary}))


@read_once(shared)
def read_geometry_netcdf(path: str | os.PathLike) -> Geometry:
    """Read a file written by :func:`write_geometry_netcdf` (one InputError naming the file if
    it is missing, damaged or incomplete)."""
    with open_artifact(path) as ds:
        return _geometry_from(ds)


def read_cell_geometry(path: str | os.PathLike) -> Geometry:
    """What the exports use of a geometry file: cell volumes and centroids, face areas and
    normals (the orientation figures need them), and cell normals where stored; the face
    centroids (a third of the file) are left empty: they are not written to ``{case}.nc`` (its
    readers recompute them from the grid)."""
    with open_artifact(path) as ds:
        volumes = read_variable(ds, "cell_volume", "f", 1)
        centroids = read_variable(ds, "cell_centroid", "f", 2)
        geo = Geometry(
            volumes,
            centroids,
            read_variable(ds, "face_area", "f", 1),
            read_variable(ds, "face_normal", "f", 2),
            np.zeros((0, centroids.shape[1])),
            read_variable(ds, "cell_normal", "f", 2) if "cell_normal" in ds else None,
        )
        _check_geometry_sizes(geo, None)
        return geo
