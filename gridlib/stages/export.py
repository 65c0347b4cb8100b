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
* ``{case}.png``: the grid rendered off-screen, coloured by porosity (or
  depth), fault faces in red; ``{case}_histograms.png``: cell volumes, face
  areas, porosity (the MRST book's Fig. 3.33) and log10 T;
* ``summary.json``: the case's figures (the regression tests compare them).

``pore_volume`` (geometric cell volume x porosity x NTG, m3) predates the
transmissibility stage and is kept; ``porv`` is the simulator's pore volume (for
corner-point decks from ECLIPSE's bulk volumes) in the case's unit system.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..config import load_case
from ..connectivity import offsets, ragged_arange
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid
from ..io._atomic import atomic_path, write_keeping_suffix
from ..io.netcdf import read_netcdf
from ..io.vtu import write_vtu
from ..reproducible import log10
from .common import log, nnc_variables, read_attrs, read_extra, save_figure, write_grid_file
from .petrophysics import read_rock
from .transmissibility import CONNECTION_VARS, face_connections, read_transmissibility

NNC_VARS = ("nnc_cells", "nnc_global_cells", "nnc_kind", "nnc_face")


class _Stored:
    """An NNC list read back from a grid file (the fields nnc_variables writes)."""

    def __init__(self, extra: dict[str, np.ndarray]) -> None:
        self.cells = extra["nnc_cells"]
        self.global_cells = extra["nnc_global_cells"]
        self.kind = extra["nnc_kind"]
        self.face = extra["nnc_face"]


def write_fault_faces(path: Path, grid: Grid, names: list[str], face_trans: np.ndarray | None = None) -> int:
    """The fault faces of ``grid`` as a VTK PolyData file, with ``face_trans`` (per face of the
    grid) as cell data ``trans`` if given; returns how many."""
    import pyvista as pv

    faces = np.flatnonzero(grid.faces.tag > 0)
    counts = np.diff(grid.faces.node_pos)[faces]
    nodes = grid.faces.nodes[ragged_arange(grid.faces.node_pos[:-1][faces], counts)]
    used, local = np.unique(nodes, return_inverse=True)
    coords = grid.nodes.coords[used]
    if coords.shape[1] == 2:
        coords = np.column_stack([coords, np.zeros(coords.shape[0])])
    # VTK's cell arrays: [n, ids..., n, ids...]
    cells = np.insert(local.reshape(-1), offsets(counts)[:-1], counts)
    if grid.griddim == 2:
        mesh = pv.PolyData(coords, lines=cells.astype(np.int64))
    else:
        mesh = pv.PolyData(coords, faces=cells.astype(np.int64))
    mesh.cell_data["fault"] = grid.faces.tag[faces].astype(np.int32)
    if face_trans is not None:
        mesh.cell_data["trans"] = np.asarray(face_trans, dtype=np.float64)[faces]
    mesh.field_data["fault_names"] = np.array(names if names else [""])
    write_keeping_suffix(path, lambda p: mesh.save(p))
    return int(faces.size)


def _polydata(grid: Grid, values: np.ndarray, name: str):
    """What a picture shows, as VTK PolyData with ``values`` as cell data: the outer boundary
    faces of a 3-D grid (coloured by the cell inside; far smaller than the polyhedra), or the
    cells of a 2-D grid as polygons."""
    import pyvista as pv

    if grid.griddim == 3:
        nb = grid.faces.neighbors
        faces = np.flatnonzero((nb < 0).any(axis=1))
        owner = nb[faces].max(axis=1)
        counts = np.diff(grid.faces.node_pos)[faces]
        nodes = grid.faces.nodes[ragged_arange(grid.faces.node_pos[:-1][faces], counts)]
    else:
        from ..connectivity import cell_node_cycles_2d

        pos, nodes = cell_node_cycles_2d(grid)
        counts, owner = np.diff(pos), np.arange(grid.num_cells)
    used, local = np.unique(nodes, return_inverse=True)
    coords = grid.nodes.coords[used]
    if coords.shape[1] == 2:
        coords = np.column_stack([coords, np.zeros(coords.shape[0])])
    cells = np.insert(local.reshape(-1), offsets(counts)[:-1], counts).astype(np.int64)
    mesh = pv.PolyData(coords, faces=cells)
    mesh.cell_data[name] = np.asarray(values)[owner]
    return mesh


def _render(path: Path, grid: Grid, values: np.ndarray, faults_vtp: Path, scalar: str, title: str) -> None:
    """An off-screen picture of the grid coloured by ``scalar``, fault faces in red."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkLogger

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)  # no X server here: VTK falls back, noisily
    pv.OFF_SCREEN = True
    griddim = grid.griddim
    mesh = _polydata(grid, values, scalar)
    faults = pv.read(faults_vtp)
    span = np.ptp(mesh.points, axis=0)
    lateral = max(span[0], span[1], 1e-12)
    # z is depth: flip it for the picture, and exaggerate thin reservoirs to a third of their width.
    exaggeration = 1.0 if griddim == 2 or span[2] == 0 else max(1.0, 0.3 * lateral / span[2])
    scale = (1.0, 1.0, -exaggeration)
    plotter = pv.Plotter(off_screen=True, window_size=(1200, 800))
    plotter.add_mesh(
        mesh.scale(scale, inplace=False),
        scalars=scalar,
        show_edges=grid.num_cells < 60_000,
        cmap="viridis",
        scalar_bar_args={"title": scalar},
    )
    if faults.n_cells:
        plotter.add_mesh(faults.scale(scale, inplace=False), color="red", line_width=3, opacity=0.8)
    plotter.add_text(title, font_size=12)
    if griddim == 2 or span[2] == 0:
        plotter.view_xy()
    else:
        plotter.view_isometric()
    write_keeping_suffix(path, lambda p: plotter.screenshot(str(p)))
    plotter.close()


def _histograms(
    path: Path,
    geo: Geometry,
    poro: np.ndarray | None,
    griddim: int,
    title: str,
    trans: tuple[np.ndarray, str] | None = None,
) -> None:
    """Histograms of cell volumes, face areas, porosity and, with ``trans`` (T and its unit),
    log10 T; logarithmic axes where values span more than two decades."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [("cell volumes (m3)" if griddim == 3 else "cell areas (m2)", geo.cell_volumes)]
    panels.append(("face areas (m2)" if griddim == 3 else "face lengths (m)", geo.face_areas))
    if poro is not None:
        panels.append(("porosity", poro))
    if trans is not None:
        t, unit = trans
        panels.append((f"log10 T, T in {unit}", log10(t[t > 0])))
    linear = ("poro", "log10")
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 3.6))
    for ax, (label, values) in zip(np.atleast_1d(axes), panels, strict=True):
        plain = label.startswith(linear)
        v = values if plain else values[np.isfinite(values) & (values > 0)]
        if v.size and not plain and v.max() > 100 * v.min():
            ax.hist(v, bins=np.geomspace(v.min(), v.max(), 50))
            ax.set_xscale("log")
        elif v.size and np.ptp(v) > 1e-9 * np.abs(v).max():
            ax.hist(v, bins=50)
        else:  # one value (a regular grid): one bar
            ax.bar(
                [float(v[0]) if v.size else 0.0],
                [v.size],
                width=1.0 if not v.size else 0.1 * abs(float(v[0])) or 1.0,
            )
        ax.set_xlabel(label)
        ax.set_ylabel("count")
    fig.suptitle(title)
    fig.tight_layout()
    save_figure(fig, path)


def _transmissibility(path: str | os.PathLike, num_cells: int):
    """The variables and attributes of ``transmissibility.nc``, checked against the grid."""
    variables, attrs = read_transmissibility(path)
    if variables["porv"].size != num_cells:
        raise InputError(f"{path}: porv has {variables['porv'].size} cells, but the grid has {num_cells}")
    return variables, attrs


def _face_trans(grid: Grid, variables) -> np.ndarray:
    """Per face of the grid, the T of the connection of its two cells (0 where none)."""
    conn = face_connections(grid.faces.neighbors, variables["connection_cells"].values)
    t = variables["trans"].values
    return np.where(conn >= 0, t[np.maximum(conn, 0)] if t.size else 0.0, 0.0)


def cell_geometry(geometry_nc: str | os.PathLike) -> Geometry:
    """What the exports use of ``geometry.nc``: cell volumes and centroids and face areas,
    read alone; the face normals and centroids (most of the file) are left empty: they are
    not written to ``{case}.nc`` (its readers recompute them from the grid)."""
    arrays = read_extra(geometry_nc, ("cell_volume", "cell_centroid", "face_area", "cell_normal"))
    missing = [n for n in ("cell_volume", "cell_centroid", "face_area") if n not in arrays]
    if missing:
        raise InputError(f"{geometry_nc}: not a gridlib geometry file (missing {', '.join(missing)})")
    d = arrays["cell_centroid"].shape[1]
    empty = np.zeros((0, d))
    return Geometry(
        arrays["cell_volume"],
        arrays["cell_centroid"],
        arrays["face_area"],
        empty,
        empty,
        arrays.get("cell_normal"),
    )


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


def _figure(value: float) -> float:
    """Round to 12 significant digits: summaries stay stable across platforms' last bits."""
    return float(f"{value:.12g}")


def stage_export(
    case_file: str | os.PathLike,
    grid_nc: str | os.PathLike,
    geometry_nc: str | os.PathLike,
    outputs: dict[str, str],
    petrophysics_nc: str | os.PathLike | None = None,
    coarse_nc: str | os.PathLike | None = None,
    transmissibility_nc: str | os.PathLike | None = None,
) -> None:
    """Write the case's exports; ``outputs`` maps nc, vtu, faults, png, histograms, summary to paths."""
    case = load_case(case_file)
    stored = read_netcdf(grid_nc)
    grid, attrs = stored.grid, read_attrs(grid_nc)
    geo = cell_geometry(geometry_nc)
    if geo.cell_volumes.size != grid.num_cells:
        raise InputError(f"{geometry_nc}: {geo.cell_volumes.size} cells, but {grid_nc} has {grid.num_cells}")
    fault_names = list(attrs.get("fault_names", []))
    well_names = list(attrs.get("well_names", []))
    cell_data: dict[str, np.ndarray] = dict(stored.cell_data)
    rock = read_rock(petrophysics_nc) if petrophysics_nc else None
    if rock is not None:
        cell_data |= rock
        cell_data["pore_volume"] = geo.cell_volumes * rock["poro"] * rock["ntg"]
    blocks = None
    if coarse_nc:
        partition = read_extra(coarse_nc, ("partition",))["partition"]
        cell_data["block"] = partition
        blocks = int(partition.max()) + 1
    trans = _transmissibility(transmissibility_nc, grid.num_cells) if transmissibility_nc else None
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
    extra = read_extra(grid_nc, NNC_VARS)
    nnc = _Stored(extra) if len(extra) == len(NNC_VARS) else None
    provenance = {**case.provenance(), "fault_names": fault_names, "well_names": well_names}
    extra = nnc_variables(nnc)
    face_trans = None
    if trans is not None:
        variables, tattrs = trans
        extra |= {name: variables[name] for name in CONNECTION_VARS}
        provenance |= {k: tattrs[k] for k in ("unit_system", "trans_units", "porv_units", "flow_dims")}
        face_trans = _face_trans(grid, variables)

    write_grid_file(
        outputs["nc"],
        grid,
        geometry=geo,
        cell_data=cell_data,
        extra=extra,
        attrs=provenance,
        var_attrs=var_attrs,
        face_vectors=False,
    )
    vtu_data = {"volume": geo.cell_volumes, "centroid": geo.cell_centroids, **cell_data}
    if grid.layering is not None:
        vtu_data |= {"layer": grid.layering.layer, "column": grid.layering.column}
    write_vtu(outputs["vtu"], grid, vtu_data)
    n_fault_faces = write_fault_faces(Path(outputs["faults"]), grid, fault_names, face_trans)
    scalar = "poro" if rock is not None else ("depth" if depth is not None else "volume")
    title = f"{case.name}: {grid.num_cells:,d} cells"
    values = rock[scalar] if rock is not None else (depth if depth is not None else geo.cell_volumes)
    _render(Path(outputs["png"]), grid, values, Path(outputs["faults"]), scalar, title)
    t_panel = None if trans is None else (trans[0]["trans"].values, str(trans[1]["trans_units"]))
    poro = None if rock is None else rock["poro"]
    _histograms(Path(outputs["histograms"]), geo, poro, grid.griddim, title, t_panel)

    summary: dict[str, Any] = {
        "case": case.name,
        "grid_type": case.data["grid"]["type"],
        "griddim": grid.griddim,
        "cells": grid.num_cells,
        "faces": grid.num_faces,
        "nodes": grid.num_nodes,
        "total_volume": _figure(geo.cell_volumes.sum()),
        "min_cell_volume": _figure(geo.cell_volumes.min()),
        "max_cell_volume": _figure(geo.cell_volumes.max()),
        "total_face_area": _figure(geo.face_areas.sum()),
        "fault_faces": n_fault_faces,
        "faults": fault_names,
        "wells": well_names,
        "nnc": 0 if nnc is None else int(nnc.cells.shape[0]),
        "seed": case.seed,
        "case_sha256": case.sha256,
    }
    if "bulk_volume" in cell_data:
        summary["total_bulk_volume"] = _figure(cell_data["bulk_volume"].sum())
    if rock is not None:
        summary["pore_volume"] = _figure(cell_data["pore_volume"].sum())
        summary["mean_porosity"] = _figure(rock["poro"].mean())
        summary["mean_permx"] = _figure(rock["permx"].mean())
    if blocks is not None:
        summary["coarse_blocks"] = blocks
    if trans is not None:
        summary |= transmissibility_figures(*trans)
    with atomic_path(outputs["summary"]) as tmp:
        tmp.write_text(json.dumps(summary, indent=2) + "\n")
    log.info("wrote the exports of %s (%d cells)", case.name, grid.num_cells)
