"""VTK XML unstructured grid (.vtu) output, readable by ParaView, VTK and pyvista.

3-D cells are written as ``VTK_POLYHEDRON`` (type 42) in the legacy XML layout
that every VTK since 8 reads: ``connectivity``/``offsets`` list each cell's
points, ``faces`` holds per cell ``[nF, n1, ids..., n2, ids...]`` with every
face oriented outwards from that cell, and ``faceoffsets`` the end offsets.
2-D grids are written as ``VTK_POLYGON`` (type 7) cells with their node
cycles (z = 0 for planar grids). Arrays are little-endian binary in an appended
block (UInt64 headers), compressed with VTK's zlib compressor (``vtkZLibDataCompressor``:
each array in blocks of 1 MiB, each block deflated at level 1), which every VTK reader,
ParaView and pyvista decompress to the exact values; ``compress=False`` writes them raw.
Cell data: every array with one row per cell, scalar or vector.

Note that z is depth: in ParaView, flip the z axis (scale z by -1) to see the
model the right way up.
"""

from __future__ import annotations

import os
import zlib
from functools import partial
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..connectivity import cell_node_cycles_2d, half_face_cells, offsets, ragged_arange
from ..errors import GridError
from ..grid import Grid
from ..threads import concurrently
from ._atomic import atomic_path

VTK_POLYGON = 7
VTK_POLYHEDRON = 42
BLOCK_BYTES = 1 << 20  # uncompressed bytes per zlib block (VTK's own writer uses 32 KiB)
ZLIB_LEVEL = 1

_VTK_TYPES = {
    np.dtype(np.float64): "Float64",
    np.dtype(np.float32): "Float32",
    np.dtype(np.int64): "Int64",
    np.dtype(np.int32): "Int32",
    np.dtype(np.int16): "Int16",
    np.dtype(np.int8): "Int8",
    np.dtype(np.uint8): "UInt8",
    np.dtype(np.uint32): "UInt32",
    np.dtype(np.uint64): "UInt64",
}


def polyhedron_streams(grid: Grid) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(connectivity, offsets, faces, faceoffsets) of the legacy VTK polyhedron layout."""
    cf = grid.cells.faces
    hc = half_face_cells(grid)
    npos = grid.faces.node_pos
    n = np.diff(npos)[cf]  # nodes per half-face
    outward = grid.faces.neighbors[cf, 0] == hc
    # Face stream: per cell 1 + sum(1 + n) entries.
    cell_len = 1 + np.bincount(hc, 1 + n, grid.num_cells).astype(np.int64)
    cell_start = offsets(cell_len)
    hf_len = 1 + n
    # Offset of each half-face inside its cell block: 1 + lengths of earlier half-faces.
    cum = offsets(hf_len)
    hf_off = 1 + cum[:-1] - cum[grid.cells.face_pos[hc]]
    stream = np.empty(int(cell_start[-1]), dtype=np.int64)
    stream[cell_start[:-1]] = grid.cells.num_faces
    count_at = cell_start[hc] + hf_off
    stream[count_at] = n
    local = ragged_arange(np.zeros(cf.size, dtype=np.int64), n)
    hf_rep = np.repeat(np.arange(cf.size), n)
    fwd = np.repeat(outward, n)
    src = npos[cf][hf_rep] + np.where(fwd, local, n[hf_rep] - 1 - local)
    stream[np.repeat(count_at + 1, n) + local] = grid.faces.nodes[src]
    conn, conn_off = _cell_points(grid.faces.nodes[src], np.bincount(hc, n, grid.num_cells).astype(np.int64))
    return conn, conn_off, stream, cell_start[1:]


def _cell_points(entries: np.ndarray, per_cell: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct nodes of each cell, ascending, from its face-node ``entries`` (grouped by
    cell, ``per_cell`` each), and their end offsets. Cells with the same number of entries
    are sorted together as one (cells, m) table: no global sort of all entries."""
    start = offsets(per_cell)[:-1]
    distinct = np.zeros(per_cell.size, dtype=np.int64)
    tables = []
    for m in np.unique(per_cell[per_cell > 0]):
        cells = np.flatnonzero(per_cell == m)
        rows = np.sort(entries[start[cells][:, None] + np.arange(m)], axis=1)
        keep = np.ones(rows.shape, dtype=bool)
        keep[:, 1:] = rows[:, 1:] != rows[:, :-1]
        distinct[cells] = keep.sum(axis=1)
        tables.append((cells, rows, keep))
    end = np.cumsum(distinct)
    conn = np.empty(int(end[-1]) if end.size else 0, dtype=entries.dtype)
    for cells, rows, keep in tables:
        slot = np.cumsum(keep, axis=1) - 1 + (end[cells] - distinct[cells])[:, None]
        conn[slot[keep]] = rows[keep]
    return conn, end


def _zlib_blocks(raw: bytes) -> bytes:
    """``raw`` as VTK's zlib compressor stores it: the UInt64 header (number of blocks,
    block size, size of the last block, compressed size of each block), then the blocks."""
    view = memoryview(raw)
    blocks = (view[i : i + BLOCK_BYTES] for i in range(0, len(raw), BLOCK_BYTES))
    # zlib releases the GIL and every block is deflated on its own: the same bytes on any thread count
    chunks = concurrently(*(partial(zlib.compress, block, ZLIB_LEVEL) for block in blocks))
    last = len(raw) - (len(chunks) - 1) * BLOCK_BYTES if chunks else 0
    header = np.array([len(chunks), BLOCK_BYTES, last, *map(len, chunks)], dtype="<u8")
    return header.tobytes() + b"".join(chunks)


def write_vtu(
    path: str | os.PathLike,
    grid: Grid,
    cell_data: dict[str, np.ndarray] | None = None,
    *,
    compress: bool = True,
) -> Path:
    """Write ``grid`` with its cell data to a .vtu file (atomically), zlib-compressed unless
    ``compress`` is False."""
    coords = grid.nodes.coords
    points = coords if coords.shape[1] == 3 else np.column_stack([coords, np.zeros(len(coords))])
    arrays: list[tuple[str, str, np.ndarray, int]] = []  # (section, name, data, ncomp)
    arrays.append(("Points", "Points", points, 3))
    if grid.griddim == 3:
        conn, off, faces, faceoff = polyhedron_streams(grid)
        types = np.full(grid.num_cells, VTK_POLYHEDRON, dtype=np.uint8)
        cells = [
            ("connectivity", conn),
            ("offsets", off),
            ("types", types),
            ("faces", faces),
            ("faceoffsets", faceoff),
        ]
    else:
        pos, cyc = cell_node_cycles_2d(grid)
        types = np.full(grid.num_cells, VTK_POLYGON, dtype=np.uint8)
        cells = [("connectivity", cyc), ("offsets", pos[1:]), ("types", types)]
    for name, data in cells:
        arrays.append(("Cells", name, np.ascontiguousarray(data), 1))
    for name, values in (cell_data or {}).items():
        arr = np.asarray(values)
        if arr.dtype == bool:
            arr = arr.astype(np.uint8)
        if arr.shape[:1] != (grid.num_cells,) or arr.ndim > 2:
            raise GridError(f"write_vtu: cell data '{name}' must have shape ({grid.num_cells},) or (nc, k)")
        if arr.dtype not in _VTK_TYPES:
            raise GridError(f"write_vtu: cell data '{name}' has unsupported type {arr.dtype}")
        arrays.append(("CellData", name, np.ascontiguousarray(arr), 1 if arr.ndim == 1 else arr.shape[1]))

    header, blobs, offset = [], [], 0
    for section, name, data, ncomp in arrays:
        raw = np.ascontiguousarray(data, dtype=data.dtype.newbyteorder("<")).tobytes()
        blob = _zlib_blocks(raw) if compress else np.uint64(len(raw)).tobytes() + raw
        blobs.append(blob)
        header.append((section, name, _VTK_TYPES[np.dtype(data.dtype)], ncomp, offset))
        offset += len(blob)

    def tags(section: str) -> str:
        return "\n".join(
            f'<DataArray type="{t}" Name={quoteattr(n)} NumberOfComponents="{c}" '
            f'format="appended" offset="{o}"/>'
            for s, n, t, c, o in header
            if s == section
        )

    compressor = ' compressor="vtkZLibDataCompressor"' if compress else ""
    xml = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        f'header_type="UInt64"{compressor}>\n'
        "<UnstructuredGrid>\n"
        f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{grid.num_cells}">\n'
        f"<Points>\n{tags('Points')}\n</Points>\n"
        f"<Cells>\n{tags('Cells')}\n</Cells>\n"
        f"<CellData>\n{tags('CellData')}\n</CellData>\n"
        "</Piece>\n</UnstructuredGrid>\n"
        '<AppendedData encoding="raw">\n_'
    )
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(xml.encode())
        for blob in blobs:
            fh.write(blob)
        fh.write(b"\n</AppendedData>\n</VTKFile>\n")
    return Path(path)
