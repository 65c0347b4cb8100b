"""VTK PolyData files (``.vtp``): the fault faces of a grid as polygons (lines in 2-D) with
their fault id, the fault names as field data and, if given, each face's transmissibility; the
paths of a case's deviated wells as polylines with their MD. The files' z is the elevation
``-depth`` (:func:`.vtu.vtk_points`), as in the VTU grids."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..connectivity import offsets, ragged_arange
from ..grid import Grid
from .atomic import write_keeping_suffix
from .vtu import vtk_points

if TYPE_CHECKING:
    from ..wells.path import WellPath


def write_fault_faces(path: Path, grid: Grid, names: list[str], face_trans: np.ndarray | None = None) -> int:
    """The fault faces of ``grid`` as a VTK PolyData file (z elevation), with ``face_trans`` (per face of the
    grid) as cell data ``trans`` if given; returns how many."""
    import pyvista as pv

    faces = np.flatnonzero(grid.faces.tag > 0)
    counts = np.diff(grid.faces.node_pos)[faces]
    nodes = grid.faces.nodes[ragged_arange(grid.faces.node_pos[:-1][faces], counts)]
    used, local = np.unique(nodes, return_inverse=True)
    coords = vtk_points(grid.nodes.coords[used])
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


def write_well_paths(path: Path, wells: Sequence[tuple[str, Sequence[WellPath]]]) -> int:
    """The paths of ``wells`` ((name, paths) each: the main path, then its branches) as a VTK
    PolyData file of polylines, one per path, with the point data ``md`` (measured depth) and
    ``depth`` (down; the file's z is the elevation ``-depth``, :func:`.vtu.vtk_points`), the
    cell data ``well`` (0-based, names in the field data ``well_names``) and ``branch`` (0 the
    main path, k the k-th branch), and the paths' names in the field data ``path_names``;
    returns the number of polylines."""
    import pyvista as pv

    paths = [(w, b, p) for w, (_, own) in enumerate(wells) for b, p in enumerate(own)]
    counts = np.array([p.md.size for _, _, p in paths], dtype=np.int64)
    xyz = np.concatenate([p.xyz for _, _, p in paths]) if paths else np.zeros((0, 3))
    coords = vtk_points(xyz)
    lines = np.insert(np.arange(int(counts.sum()), dtype=np.int64), offsets(counts)[:-1], counts)
    mesh = pv.PolyData(coords, lines=lines) if paths else pv.PolyData()
    if paths:
        mesh.point_data["md"] = np.concatenate([p.md for _, _, p in paths])
        mesh.point_data["depth"] = xyz[:, 2].copy()
        mesh.cell_data["well"] = np.array([w for w, _, _ in paths], dtype=np.int32)
        mesh.cell_data["branch"] = np.array([b for _, b, _ in paths], dtype=np.int32)
    mesh.field_data["well_names"] = np.array([name for name, _ in wells] or [""])
    mesh.field_data["path_names"] = np.array([p.name for _, _, p in paths] or [""])
    write_keeping_suffix(path, lambda p: mesh.save(p))
    return len(paths)
