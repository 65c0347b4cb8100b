"""VTK PolyData files (``.vtp``): the fault faces of a grid as polygons (lines in 2-D) with
their fault id, the fault names as field data and, if given, each face's transmissibility."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..connectivity import offsets, ragged_arange
from ..grid import Grid
from .atomic import write_keeping_suffix


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
