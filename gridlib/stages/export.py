"""Stage ``export``: everything about a case in the formats people open.

* ``{case}.nc``: one self-describing netCDF file: grid, cell geometry and face
  areas (face normals and centroids are left out: :func:`gridlib.io.netcdf.read_netcdf`
  recomputes them from the grid), the builder's
  cell data (bulk volume, well, zone, layer), rock properties, the coarse block
  of every cell, pore volume, the NNC list, and the variables of
  ``transmissibility.nc`` (connections with their T, ``porv`` and
  ``cell_flow_index``);
* ``{case}.vtu``: the grid with the same cell data (ParaView, pyvista);
* ``{case}_faults.vtp``: the fault faces as polygons (lines in 2-D) with their
  fault id (names in the field data ``fault_names``) and, where the case has
  transmissibilities, ``trans``: the T of the connection the face belongs to (of
  the face's cell pair: faces between the same two cells share it), 0 where none;
* ``{case}_wells.vtp`` (cases with trajectory or survey wells): the paths of ``wells.nc``
  as polylines with their MD (:func:`gridlib.io.vtp.write_well_paths`);
* the cell-quality measures of ``quality.nc`` (:mod:`gridlib.stages.quality`) in ``{case}.nc``
  and the VTU as cell variables;
* ``summary.json``: the case's figures (the regression tests compare them); for a deck case
  with degenerate cells (:mod:`gridlib.stages.grid`) also ``degenerate_cells``: their count,
  how many have a non-positive polyhedral volume and how many do not close, and the first
  100 as 1-based (i, j, k). The grid's orientation (:mod:`gridlib.orientation`), in degrees:
  ``orientation_median``, ``orientation_p95`` and ``orientation_max`` of the angle between
  each interior face's normal and the line joining its two cells' centres, and with rock
  ``k_orientation_median``, ``_p95`` and ``_max`` of the angle between K n and that line
  (the larger of the face's two cells), to 1e-6 degree. The centres are those of the
  transmissibility stage: a PEBI grid's generating sites at each cell's centroid depth, else
  the centroids. Cases with horizons given by picks get ``pick_residuals``: per such horizon
  the number of picks, the RMS and largest magnitude of their residuals against the
  interpolated surface (m, :mod:`gridlib.horizons.residuals`). Cases with trajectory or survey
  wells also get ``trajectory_wells``: per well its connections, ``completed_length`` and
  ``total_factor`` (:func:`wells_summary`). With ``quality.nc``: ``quality``, per measure its
  median, p95 and max and the flagged cells (:func:`quality_figures`), and ``qc``, the results
  of the case's qc rules.

Every value is in the case's unit system (``unit_system``: METRIC, or a deck's own, e.g.
FIELD for SPE9: ft, ft2, ft3, rb, mD), and every file, picture and figure says so: the
``units`` of each netCDF variable, the axis labels, ``unit_system`` in ``summary.json``
(:mod:`gridlib.io.quantities`).

``pore_volume`` (geometric cell volume x porosity x NTG, m3 or ft3) predates the
transmissibility stage and is kept; ``porv`` is the simulator's pore volume (for
corner-point decks from ECLIPSE's bulk volumes) at reservoir conditions (rm3 or rb). They differ
most on a deck's degenerate cells, whose polyhedral volume may be zero or negative:
``porv`` (``total_porv``) is the one a simulator uses.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..cell_names import ijk
from ..config import Case
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid
from ..horizons.residuals import PickResiduals, residual_figures
from ..io.atomic import atomic_path
from ..io.coarse_file import read_partition
from ..io.deferred import Deferred
from ..io.grid_nnc import nnc_variables, read_nnc
from ..io.horizon_files import read_pick_residuals
from ..io.netcdf import GridDataset, read_cell_geometry, read_netcdf, write_netcdf
from ..io.netcdf_parts import check_same_cells, read_attrs, stored_unit_system
from ..io.quality_file import FLAGS, deferred_quality, measure_attrs
from ..io.rock_file import read_rock
from ..io.transmissibility_file import CELL_VARS, deferred_connection_variables, read_transmissibility
from ..io.vtp import write_fault_faces, write_well_paths
from ..io.vtu import write_vtu
from ..io.wells_file import WellRecord, read_wells
from ..orientation import grid_face_angles, orientation_figures
from ..pillars.nnc import NNC
from ..quality import MEASURE
from ..transmissibility import face_connections
from ..units import UnitSystem
from .common import log
from .transmissibility import cell_centres


def _face_trans(grid: Grid, variables) -> np.ndarray:
    """Per face of the grid, the T of the connection of its two cells (0 where none) on the
    fault faces, the one use of it (the faults' VTP); 0 on every other face (only the fault
    faces are looked up: that of every face took 0.9 GiB more on a 4e6-cell grid)."""
    out = np.zeros(grid.num_faces)
    faults = np.flatnonzero(grid.faces.tag > 0)
    if not faults.size:
        return out
    nb = grid.faces.neighbors[faults]
    cells = variables["connection_cells"].values
    beside = np.zeros(grid.num_cells, dtype=bool)
    beside[nb[nb >= 0]] = True
    # the connections between cells beside the faults, in their order: the same first match
    candidates = np.flatnonzero(beside[cells[:, 0]] & beside[cells[:, 1]]) if cells.size else cells[:0, 0]
    conn = face_connections(nb, cells[candidates])
    t = variables["trans"].values[candidates]
    out[faults] = np.where(conn >= 0, t[np.maximum(conn, 0)] if t.size else 0.0, 0.0)
    return out


def transmissibility_figures(variables, attrs) -> dict[str, Any]:
    """The summary's figures of the connections: counts by kind, min/median/max T, total porv."""
    t = variables["trans"].values
    kind = variables["connection_kind"].values
    names = str(variables["connection_kind"].attrs["flag_meanings"]).split()
    counts = np.bincount(kind.astype(np.int64), minlength=len(names))
    out: dict[str, Any] = {"unit_system": str(attrs["unit_system"]), "connections": int(t.size)}
    out |= {f"{name}_connections": int(counts[k]) for k, name in enumerate(names)}
    if t.size:
        out |= {
            "min_trans": _figure(t.min()),
            "median_trans": _figure(np.median(t)),
            "max_trans": _figure(t.max()),
        }
    out["total_porv"] = _figure(variables["porv"].values.sum())
    return out


def degenerate_figures(grid: Grid, flags: np.ndarray, listed: int = 100) -> dict[str, Any]:
    """The summary's account of a deck's degenerate cells (``flags``: the grid stage's
    ``degenerate`` cell data): how many, of which kind, and the first ``listed`` as 1-based
    (i, j, k) (cell numbers where the grid has no logical indices)."""
    cells = np.flatnonzero(flags)
    shown = cells[:listed]
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        named = ijk(grid.cells.index_map[shown], grid.cart_dims).tolist()
    else:
        named = shown.tolist()
    return {
        "count": int(cells.size),
        "non_positive_volume": int(np.count_nonzero(flags & 1)),
        "not_closed": int(np.count_nonzero(flags & 2)),
        "cells": named,
    }


def _figure(value: float) -> float:
    """Round to 12 significant digits: summaries stay stable across platforms' last bits."""
    return float(f"{value:.12g}")


@dataclass
class _Gathered:
    """What the export writes: the grid, its geometry and every per-cell array, the NNC list
    and connection variables, the file attributes, and what the summary needs."""

    grid: Grid
    geo: Geometry
    units: UnitSystem
    fault_names: list[str]
    well_names: list[str]
    cell_data: dict[str, np.ndarray]
    var_attrs: dict[str, dict[str, Any]]
    rock: dict[str, np.ndarray] | None
    depth: np.ndarray | None
    blocks: int | None
    trans_figures: dict[str, Any] | None  # transmissibility_figures, where the case has connections
    nnc: NNC | None
    extra: dict[str, Any]
    provenance: dict[str, Any]
    face_trans: np.ndarray | None
    orientation: dict[str, float]  # orientation_summary
    quality: tuple[dict[str, Any], list[dict[str, Any]]] | None = None  # quality_figures, qc results


def stage_export(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    petrophysics: str | os.PathLike | None = None,
    coarse: str | os.PathLike | None = None,
    transmissibility: str | os.PathLike | None = None,
    wells: str | os.PathLike | None = None,
    horizons: str | os.PathLike | None = None,
    quality: str | os.PathLike | None = None,
    nc: str | os.PathLike,
    vtu: str | os.PathLike | None = None,
    faults: str | os.PathLike,
    well_paths: str | os.PathLike | None = None,
    summary: str | os.PathLike,
) -> None:
    """Write the case's exports from its stage files (``grid``, ``geometry`` and, where the case
    has them, ``petrophysics``, ``coarse``, ``transmissibility``, ``wells``, ``quality``): ``nc`` ({case}.nc),
    ``vtu`` (where ``outputs.vtu``), ``faults``, ``well_paths`` (where the case has deviated
    wells), and ``summary`` (summary.json); the pictures are stage ``pictures``'
    (:mod:`gridlib.stages.pictures`)."""
    written = {"nc": nc, "vtu": vtu, "faults": faults}
    outputs = {key: str(path) for key, path in written.items() if path is not None}
    g = _gather(case, grid, geometry, petrophysics, coarse, transmissibility, quality)
    records = read_wells(wells) if wells is not None else ()
    if well_paths is not None:
        write_well_paths(Path(well_paths), [(r.name, r.paths) for r in records])
    n_fault_faces = _write_files(outputs, g)
    figures = _summary(case, g, n_fault_faces) | wells_summary(records)
    if horizons is not None:
        figures |= pick_residuals_summary(*read_pick_residuals(horizons))
    with atomic_path(summary) as tmp:
        tmp.write_text(json.dumps(figures, indent=2) + "\n")
    log.info("wrote the exports of %s (%d cells)", case.name, g.grid.num_cells)


def _gather(
    case: Case,
    grid_nc: str | os.PathLike,
    geometry_nc: str | os.PathLike,
    petrophysics_nc: str | os.PathLike | None,
    coarse_nc: str | os.PathLike | None,
    transmissibility_nc: str | os.PathLike | None,
    quality_nc: str | os.PathLike | None = None,
) -> _Gathered:
    """Read the artifacts and gather the cell data, NNCs, connection variables and attributes.

    The figures of the summary that need arrays the files do not keep are made as those arrays
    are read, and the arrays let go: the face normals (the orientation's), the connections
    (counts, T, face T of the faults; the connection variables and the quality measures are
    :class:`~gridlib.io.deferred.Deferred`, read again one at a time as ``{case}.nc`` and the
    VTU are written). What stays is the grid and one array per cell of each kind: a 1e7-cell
    case's export fits in 6 GiB."""
    stored = read_netcdf(grid_nc)
    grid, attrs = stored.grid, read_attrs(grid_nc)
    units = stored_unit_system(grid_nc, attrs)
    geo = read_cell_geometry(geometry_nc)
    check_same_cells(grid_nc, grid.num_cells, {geometry_nc: geo.cell_volumes.size})
    fault_names = list(attrs.get("fault_names", []))
    well_names = list(attrs.get("well_names", []))
    centres, _ = cell_centres(case, grid_nc, stored, geo)
    # the rock read for the orientation alone, again after it: it holds the permeability only
    orientation = orientation_summary(
        grid, geo, centres, read_rock(petrophysics_nc) if petrophysics_nc else None
    )
    geo = replace(geo, face_normals=np.zeros((0, geo.face_normals.shape[1])))  # the orientation's alone
    del centres
    rock = read_rock(petrophysics_nc) if petrophysics_nc else None
    partition = read_partition(coarse_nc) if coarse_nc else None
    trans = read_transmissibility(transmissibility_nc, CELL_VARS) if transmissibility_nc else None
    if trans is not None:
        check_same_cells(grid_nc, grid.num_cells, {f"{transmissibility_nc}: porv": trans[0]["porv"].size})
    cell_data, var_attrs, depth = _cell_data(stored, geo, rock, partition, trans)
    quality = None
    if quality_nc is not None:
        measures, qc = deferred_quality(quality_nc)
        check_same_cells(grid_nc, grid.num_cells, {quality_nc: next(iter(measures.values())).size})
        for name, values in measures.items():
            cell_data[name] = values
            var_attrs[name] = measure_attrs(MEASURE[name])
        quality = (quality_figures(_Read(measures)), qc)
    blocks = None if partition is None else int(partition.max()) + 1
    nnc = read_nnc(grid_nc)
    provenance = {
        **case.provenance(),
        "unit_system": units.name,
        "fault_names": fault_names,
        "well_names": well_names,
    }
    extra = nnc_variables(nnc)
    face_trans = trans_figures = None
    if trans is not None:
        variables, tattrs = trans
        if stored_unit_system(transmissibility_nc, tattrs) is not units:
            raise InputError(
                f"{transmissibility_nc}: unit_system {tattrs['unit_system']}, but {grid_nc} has "
                f"{units.name} (stage files of different grids: build the case again)"
            )
        provenance |= {k: tattrs[k] for k in ("trans_units", "porv_units", "flow_dims")}
        # the connection variables each step needs, read for it and let go (3e7 of them at 1e7 cells)
        figures_vars, _ = read_transmissibility(transmissibility_nc, ("trans", "connection_kind", "porv"))
        trans_figures = transmissibility_figures(figures_vars, tattrs)
        del figures_vars
        face_trans = _face_trans(
            grid, read_transmissibility(transmissibility_nc, ("connection_cells", "trans"))[0]
        )
        del trans, variables
        extra |= deferred_connection_variables(transmissibility_nc)
    return _Gathered(
        grid,
        geo,
        units,
        fault_names,
        well_names,
        cell_data,
        var_attrs,
        rock,
        depth,
        blocks,
        trans_figures,
        nnc,
        extra,
        provenance,
        face_trans,
        orientation,
        quality,
    )


class _Read(Mapping):
    """The :class:`~gridlib.io.deferred.Deferred` arrays of ``arrays`` by name, each read when
    it is looked up."""

    def __init__(self, arrays: Mapping[str, Deferred]) -> None:
        self.arrays = arrays

    def __getitem__(self, name: str) -> np.ndarray:
        return np.asarray(self.arrays[name])

    def __iter__(self):
        return iter(self.arrays)

    def __len__(self) -> int:
        return len(self.arrays)


def _cell_data(
    stored: GridDataset,
    geo: Geometry,
    rock: dict[str, np.ndarray] | None,
    partition: np.ndarray | None,
    trans: tuple[dict[str, Any], dict[str, Any]] | None,
) -> tuple[dict[str, np.ndarray], dict[str, dict[str, Any]], np.ndarray | None]:
    """The per-cell arrays of the exports (the builder's, rock, pore volume, coarse block,
    porv and cell_flow_index, index_map, depth), their variable attributes and the depths."""
    grid = stored.grid
    cell_data: dict[str, np.ndarray] = dict(stored.cell_data)
    if rock is not None:
        cell_data |= rock
        cell_data["pore_volume"] = geo.cell_volumes * rock["poro"] * rock["ntg"]
    if partition is not None:
        cell_data["block"] = partition
    var_attrs: dict[str, dict[str, Any]] = {}
    if trans is not None:
        variables, _ = trans
        for name in ("porv", "cell_flow_index"):
            cell_data[name] = variables[name].values
            var_attrs[name] = dict(variables[name].attrs)
    if grid.cells.index_map is not None:
        cell_data["index_map"] = grid.cells.index_map
    depth = geo.cell_centroids[:, -1] if grid.dim == 3 else None
    if depth is not None:
        cell_data["depth"] = depth
    return cell_data, var_attrs, depth


def _write_files(outputs: dict[str, str], g: _Gathered) -> int:
    """``{case}.nc``, ``{case}.vtu`` (unless ``outputs`` has no "vtu": the case's
    ``outputs.vtu`` is false) and ``{case}_faults.vtp``; returns the number of fault faces."""
    grid, geo = g.grid, g.geo
    write_netcdf(
        outputs["nc"],
        grid,
        geometry=geo,
        cell_data=g.cell_data,
        extra=g.extra,
        attrs=g.provenance,
        var_attrs=g.var_attrs,
        face_vectors=False,
        units=g.units,
    )
    if "vtu" in outputs:
        vtu_data = {"volume": geo.cell_volumes, "centroid": geo.cell_centroids, **g.cell_data}
        if geo.cell_centroids.shape[1] == 3:  # the VTU's z is elevation: depth kept as cell data
            vtu_data["depth"] = geo.cell_centroids[:, 2]
        if grid.layering is not None:
            vtu_data |= {"layer": grid.layering.layer, "column": grid.layering.column}
        write_vtu(outputs["vtu"], grid, vtu_data)
    return write_fault_faces(Path(outputs["faults"]), grid, g.fault_names, g.face_trans)


def _summary(case: Case, g: _Gathered, n_fault_faces: int) -> dict[str, Any]:
    """The case's figures for ``summary.json``."""
    grid, geo, rock = g.grid, g.geo, g.rock
    summary: dict[str, Any] = {
        "case": case.name,
        "grid_type": case.grid_type,
        "griddim": grid.griddim,
        "cells": grid.num_cells,
        "faces": grid.num_faces,
        "nodes": grid.num_nodes,
        "unit_system": g.units.name,
        "total_volume": _figure(geo.cell_volumes.sum()),
        "min_cell_volume": _figure(geo.cell_volumes.min()),
        "max_cell_volume": _figure(geo.cell_volumes.max()),
        "total_face_area": _figure(geo.face_areas.sum()),
        "fault_faces": n_fault_faces,
        "faults": g.fault_names,
        "wells": g.well_names,
        "nnc": 0 if g.nnc is None else int(g.nnc.cells.shape[0]),
        "seed": case.seed,
        "case_sha256": case.sha256,
    }
    if "bulk_volume" in g.cell_data:
        summary["total_bulk_volume"] = _figure(g.cell_data["bulk_volume"].sum())
    if "degenerate" in g.cell_data:
        summary["degenerate_cells"] = degenerate_figures(grid, g.cell_data["degenerate"])
    if rock is not None:
        summary["pore_volume"] = _figure(g.cell_data["pore_volume"].sum())
        summary["mean_porosity"] = _figure(rock["poro"].mean())
        summary["mean_permx"] = _figure(rock["permx"].mean())
    if g.blocks is not None:
        summary["coarse_blocks"] = g.blocks
    if g.trans_figures is not None:
        summary |= g.trans_figures
    summary |= g.orientation
    if g.quality is not None:
        summary["quality"], summary["qc"] = g.quality
    return summary


def quality_figures(values: dict[str, np.ndarray]) -> dict[str, Any]:
    """The summary's figures of the cell-quality measures (:mod:`gridlib.quality`; degrees or
    1): per measure that is no flag, ``median``, ``p95`` and ``max`` over the cells where it is
    defined (none where it is defined on no cell), angles to 1e-6 degree, ratios to 12
    significant digits and 1e-9; ``flagged_cells``: per flag (collapsed,
    faulted, negative_thickness, concave_proj) the number of cells that have it, where defined."""
    out: dict[str, Any] = {}
    flagged: dict[str, int] = {}
    for name, v in values.items():
        finite = v[np.isfinite(v)]
        if not finite.size:
            continue
        if name in FLAGS:
            flagged[name] = int(np.count_nonzero(finite > 0))
            continue
        stats = {"median": np.median(finite), "p95": np.percentile(finite, 95), "max": finite.max()}
        # angles to 1e-6 degree (as the orientation figures), ratios to 12 digits and 1e-9: round-off
        # (a PEBI grid's 1e-10 degree, a plane face's 1e-15) reads 0 on every platform
        rounded = _degrees if MEASURE[name].unit == "angle" else (lambda x: round(_figure(x), 9) + 0.0)
        out[name] = {key: rounded(value) for key, value in stats.items()}
    if flagged:
        out["flagged_cells"] = flagged
    return out


def wells_summary(wells: Sequence[WellRecord]) -> dict[str, Any]:
    """``trajectory_wells``: per deviated well its number of connections, the length of its
    paths inside them (``completed_length``, the length unit) and the sum of its connection
    factors (``total_factor``, the transmissibility unit; absent without rock), in the case's
    unit system (:mod:`gridlib.io.quantities`); nothing for a case without such wells."""
    if not wells:
        return {}
    out = {}
    for r in wells:
        c = r.connections
        figures: dict[str, Any] = {
            "connections": int(c.cell.size),
            "completed_length": _figure(c.length.sum()),
        }
        if np.isfinite(c.factor).all():
            figures["total_factor"] = _figure(c.factor.sum())
        out[r.name] = figures
    return {"trajectory_wells": out}


def pick_residuals_summary(residuals: PickResiduals, names: Sequence[str]) -> dict[str, Any]:
    """``pick_residuals``: per horizon given by picks, their number (``picks``), the ``rms`` and
    largest magnitude (``max_abs``) of their residuals against the interpolated horizon (m, to
    12 digits; :mod:`gridlib.horizons.residuals`) and how many fall where it is undefined;
    nothing for a case without picks."""
    figures = residual_figures(residuals, names)
    if not figures:
        return {}
    rounded = {
        name: {key: _figure(v) if isinstance(v, float) else v for key, v in f.items()}
        for name, f in figures.items()
    }
    return {"pick_residuals": rounded}


def orientation_summary(
    grid: Grid, geo: Geometry, centres: np.ndarray | None, rock: dict[str, np.ndarray] | None
) -> dict[str, float]:
    """The orientation figures (:mod:`gridlib.orientation`, degrees) of the interior faces with
    the cell ``centres`` (None: the centroids): ``orientation_median``, ``_p95`` and ``_max``
    of the angle between face normal and centre line, and with ``rock`` the same of K n,
    ``k_orientation_*``, rounded to 1e-6 degree."""
    perm = None
    if rock is not None:
        perm = np.column_stack([rock["permx"], rock["permy"], rock["permz"]])[:, : grid.dim]
    del rock  # the caller's rock may go (the export's: read for this alone) while the angles are made
    angles = grid_face_angles(grid, geo, centres, perm)
    out = {f"orientation_{k}": _degrees(v) for k, v in orientation_figures(angles.angles).items()}
    if angles.k_angles is not None:
        out |= {f"k_orientation_{k}": _degrees(v) for k, v in orientation_figures(angles.k_angles).items()}
    return out


def _degrees(angle: float) -> float:
    """An angle rounded to 1e-6 degree: a face that is orthogonal up to round-off (a PEBI
    grid's, about 1e-10 degree) reads 0, the same on every platform."""
    return round(float(angle), 6) + 0.0  # + 0.0: no -0.0
