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

Orientation: gridlib's z is depth (positive down); every VTK file gridlib writes (this
module's grids, :mod:`.vtp`'s faults and well paths) stores elevation instead,
``z_vtk = -depth`` (:func:`vtk_points`, the one place of that transform), so ParaView shows the
model the right way up. The reflection turns each face's cycle around, so the faces of
``VTK_POLYHEDRON`` cells are written in the reverse order of gridlib's to stay outward.
"""

from __future__ import annotations

import os
import tempfile
import zlib
from collections.abc import Mapping
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from ..connectivity import cell_node_cycles_2d, offsets, ragged_arange
from ..errors import GridError
from ..grid import Grid
from ..threads import concurrently
from .atomic import atomic_path
from .deferred import Deferred

VTK_POLYGON = 7
VTK_POLYHEDRON = 42
BLOCK_BYTES = 1 << 20  # uncompressed bytes per zlib block (VTK's own writer uses 32 KiB)
ZLIB_LEVEL = 1
BLOCK_CELLS = 1 << 17  # cells laid out at a time: bounds the temporaries of the polyhedron streams

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


def vtk_points(coords: np.ndarray) -> np.ndarray:
    """VTK points (n, 3) of gridlib coordinates (n, 2) or (n, 3) (z depth, positive down):
    x, y kept, z the elevation ``-depth`` (z = 0 for planar coordinates)."""
    coords = np.asarray(coords, dtype=np.float64)
    points = np.zeros((len(coords), 3))
    points[:, : coords.shape[1]] = coords
    points[:, 2] = -points[:, 2]
    return points


def polyhedron_block(
    grid: Grid, first: int, stop: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The polyhedron streams of cells ``first`` to ``stop - 1`` alone: (connectivity, its end
    offsets, faces, their end offsets), the offsets counted from the block's start."""
    fp = grid.cells.face_pos
    h0, h1 = int(fp[first]), int(fp[stop])
    cf = grid.cells.faces[h0:h1]
    count = stop - first
    hc = np.repeat(np.arange(count, dtype=np.int64), np.diff(fp[first : stop + 1]))  # block-local cell
    npos = grid.faces.node_pos
    n = npos[cf + 1] - npos[cf]  # nodes per half-face
    outward = grid.faces.neighbors[cf, 0] == hc + first
    # Face stream: per cell 1 + sum(1 + n) entries.
    cell_len = 1 + np.bincount(hc, 1 + n, count).astype(np.int64)
    cell_start = offsets(cell_len)
    # Offset of each half-face inside its cell block: 1 + lengths of earlier half-faces.
    cum = offsets(1 + n)
    hf_off = 1 + cum[:-1] - cum[fp[first:stop][hc] - h0]
    stream = np.empty(int(cell_start[-1]), dtype=np.int64)
    stream[cell_start[:-1]] = np.diff(fp[first : stop + 1])
    count_at = cell_start[hc] + hf_off
    stream[count_at] = n
    local = ragged_arange(np.zeros(cf.size, dtype=np.int64), n)
    hf_rep = np.repeat(np.arange(cf.size), n)
    fwd = np.repeat(~outward, n)  # reversed: vtk_points reflects z (see the module's docstring)
    src = npos[cf][hf_rep] + np.where(fwd, local, n[hf_rep] - 1 - local)
    nodes = grid.faces.nodes[src]
    stream[np.repeat(count_at + 1, n) + local] = nodes
    conn, conn_off = _cell_points(nodes, np.bincount(hc, n, count).astype(np.int64))
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


@dataclass(frozen=True)
class _Stored:
    """Bytes of the appended block set aside in a scratch file: ``size`` bytes from ``start``."""

    scratch: Any
    start: int
    size: int

    def __len__(self) -> int:
        return self.size


class _AppendedArray:
    """One DataArray of the appended block, fed in pieces: raw (UInt64 byte count, then the
    bytes) or as VTK's zlib compressor stores it (UInt64 header: number of blocks, block size,
    size of the last block, compressed size of each block; then the blocks). Only the
    compressed blocks are kept (in memory, or in the binary file ``scratch`` where given:
    :class:`_Stored` parts); each 1 MiB block is deflated on its own, on gridlib's threads, so
    the bytes never depend on the number of threads or on the pieces."""

    def __init__(self, compress: bool, scratch: Any = None) -> None:
        self.compress = compress
        self.scratch = scratch
        self.parts: list[bytes | _Stored] = []
        self.pending = b""
        self.nbytes = 0

    def add(self, values: np.ndarray) -> None:
        raw = np.ascontiguousarray(values, dtype=values.dtype.newbyteorder("<")).tobytes()
        self.nbytes += len(raw)
        if not self.compress:
            self._keep([raw])
            return
        data = self.pending + raw if self.pending else raw
        full = len(data) // BLOCK_BYTES * BLOCK_BYTES
        self._deflate(memoryview(data)[:full])
        self.pending = data[full:]

    def _deflate(self, data: memoryview) -> None:
        blocks = [data[i : i + BLOCK_BYTES] for i in range(0, len(data), BLOCK_BYTES)]
        self._keep(concurrently(*(partial(zlib.compress, block, ZLIB_LEVEL) for block in blocks)))

    def _keep(self, parts: list[bytes]) -> None:
        if self.scratch is None:
            self.parts += parts
            return
        for part in parts:
            self.parts.append(_Stored(self.scratch, self.scratch.tell(), len(part)))
            self.scratch.write(part)

    def finish(self) -> list[bytes]:
        """The array's bytes in the appended block (header first)."""
        if not self.compress:
            return [np.uint64(self.nbytes).tobytes(), *self.parts]
        if self.pending:
            self._deflate(memoryview(self.pending))
        last = self.nbytes - (len(self.parts) - 1) * BLOCK_BYTES if self.parts else 0
        header = np.array([len(self.parts), BLOCK_BYTES, last, *map(len, self.parts)], dtype="<u8")
        return [header.tobytes(), *self.parts]


@dataclass(frozen=True, eq=False)
class VtuGeometry:
    """A grid's points and cells as :func:`write_vtu` stores them (compressed or not), laid
    out once for many files of one grid (a time series: :mod:`gridlib.io.pvd`)."""

    num_points: int
    num_cells: int
    compress: bool
    arrays: tuple[tuple[str, str, str, int, list[bytes]], ...]  # (section, name, VTK type, components, bytes)


def vtu_geometry(grid: Grid, *, compress: bool = True, scratch: Any = None) -> VtuGeometry:
    """The Points and Cells arrays of ``grid``'s VTU, z as elevation (:func:`vtk_points`); their
    bytes in memory, or in the binary file ``scratch`` where given (valid while it is open)."""
    points = vtk_points(grid.nodes.coords)
    arrays = [
        _array("Points", "Points", np.float64, 3, _row_blocks(points, BLOCK_CELLS * 8), compress, scratch)
    ]
    del points
    if grid.griddim == 3:
        arrays += _polyhedra(grid, compress, scratch)
    else:
        pos, cyc = cell_node_cycles_2d(grid)
        arrays.append(_array("Cells", "connectivity", np.int64, 1, [cyc], compress, scratch))
        arrays.append(_array("Cells", "offsets", np.int64, 1, [pos[1:]], compress, scratch))
        types = np.full(grid.num_cells, VTK_POLYGON, dtype=np.uint8)
        arrays.append(_array("Cells", "types", np.uint8, 1, [types], compress, scratch))
    return VtuGeometry(grid.num_nodes, grid.num_cells, compress, tuple(arrays))


def _array(section: str, name: str, dtype: type, ncomp: int, pieces, compress: bool, scratch: Any = None):
    """One DataArray of the appended block: (section, name, VTK type, components, bytes)."""
    appended = _AppendedArray(compress, scratch)
    for piece in pieces:
        appended.add(np.asarray(piece, dtype=dtype))
    return (section, name, _VTK_TYPES[np.dtype(dtype)], ncomp, appended.finish())


def write_vtu(
    path: str | os.PathLike,
    grid: Grid,
    cell_data: Mapping[str, np.ndarray | Deferred] | None = None,
    *,
    compress: bool = True,
    geometry: VtuGeometry | None = None,
) -> Path:
    """Write ``grid`` with its cell data to a .vtu file (atomically), z as elevation
    (:func:`vtk_points`), zlib-compressed unless ``compress`` is False. ``cell_data``: arrays,
    or :class:`~gridlib.io.deferred.Deferred` ones (read when written, then let go: one of them
    in memory at a time). Polyhedra are laid out block of cells by block of cells, and the compressed
    arrays wait in a scratch file beside ``path`` until the header (which gives their offsets)
    is written: the memory beyond the grid and the arrays given is a block's.
    ``geometry``: the grid's :func:`vtu_geometry` (same ``compress``), laid out before."""
    data = {
        name: values if isinstance(values, Deferred) else _cell_array(grid, name, values)
        for name, values in (cell_data or {}).items()
    }
    if geometry is not None and (geometry.num_cells, geometry.compress) != (grid.num_cells, compress):
        raise GridError("write_vtu: the geometry given is another grid's or compressed otherwise")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryFile(dir=Path(path).parent) as scratch:
        if geometry is None:
            geometry = vtu_geometry(grid, compress=compress, scratch=scratch)
        arrays = list(geometry.arrays)
        for name, values in data.items():
            arr = _cell_array(grid, name, np.asarray(values)) if isinstance(values, Deferred) else values
            ncomp = 1 if arr.ndim == 1 else arr.shape[1]
            blocks = _row_blocks(arr, BLOCK_CELLS)
            arrays.append(_array("CellData", name, arr.dtype.type, ncomp, blocks, compress, scratch))
            del arr, blocks
        _write_file(path, _xml_header(grid.num_cells, geometry.num_points, arrays, compress), arrays)
    return Path(path)


def _cell_array(grid: Grid, name: str, values: np.ndarray) -> np.ndarray:
    """``values`` as a VTU cell array of ``grid`` (booleans as UInt8), or a GridError naming it."""
    arr = np.asarray(values)
    if arr.dtype == bool:
        arr = arr.astype(np.uint8)
    if arr.shape[:1] != (grid.num_cells,) or arr.ndim > 2:
        raise GridError(f"write_vtu: cell data '{name}' must have shape ({grid.num_cells},) or (nc, k)")
    if arr.dtype not in _VTK_TYPES:
        raise GridError(f"write_vtu: cell data '{name}' has unsupported type {arr.dtype}")
    return arr


def _xml_header(num_cells: int, num_points: int, arrays: list, compress: bool) -> bytes:
    """The XML of the file up to its appended block, with every array's offset in that block."""
    header, offset = [], 0
    for section, name, vtk_type, ncomp, parts in arrays:
        header.append((section, name, vtk_type, ncomp, offset))
        offset += sum(map(len, parts))

    def tags(section: str) -> str:
        return "\n".join(
            f'<DataArray type="{t}" Name={quoteattr(n)} NumberOfComponents="{c}" '
            f'format="appended" offset="{o}"/>'
            for s, n, t, c, o in header
            if s == section
        )

    compressor = ' compressor="vtkZLibDataCompressor"' if compress else ""
    return (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        f'header_type="UInt64"{compressor}>\n'
        "<UnstructuredGrid>\n"
        f'<Piece NumberOfPoints="{num_points}" NumberOfCells="{num_cells}">\n'
        f"<Points>\n{tags('Points')}\n</Points>\n"
        f"<Cells>\n{tags('Cells')}\n</Cells>\n"
        f"<CellData>\n{tags('CellData')}\n</CellData>\n"
        "</Piece>\n</UnstructuredGrid>\n"
        '<AppendedData encoding="raw">\n_'
    ).encode()


def _write_file(path: str | os.PathLike, xml: bytes, arrays: list) -> None:
    """The file: ``xml``, the parts of every array (copied from the scratch file where they
    wait there, a run of consecutive parts at a time), the end of the appended block."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(xml)
        for *_, parts in arrays:
            run: _Stored | None = None
            for part in parts:
                if isinstance(part, _Stored) and run is not None and run.start + run.size == part.start:
                    run = _Stored(run.scratch, run.start, run.size + part.size)
                    continue
                _copy(fh, run)
                run = part if isinstance(part, _Stored) else None
                if run is None:
                    fh.write(part)
            _copy(fh, run)
        fh.write(b"\n</AppendedData>\n</VTKFile>\n")


def _copy(fh: Any, run: _Stored | None, piece: int = 1 << 24) -> None:
    """Copy ``run`` from its scratch file to ``fh`` (nothing for None), 16 MiB at a time."""
    if run is None:
        return
    run.scratch.seek(run.start)
    left = run.size
    while left:
        chunk = run.scratch.read(min(left, piece))
        fh.write(chunk)
        left -= len(chunk)


def _polyhedra(grid: Grid, compress: bool, scratch: Any = None) -> list[tuple[str, str, str, int, list]]:
    """The Cells arrays of a 3-D grid's polyhedra (connectivity, offsets, types, faces,
    faceoffsets), built and compressed block of cells by block of cells."""
    streams = {
        key: _AppendedArray(compress, scratch) for key in ("connectivity", "offsets", "faces", "faceoffsets")
    }
    index = _index_type(grid)
    ends = np.zeros(2, dtype=np.int64)  # connectivity and faces written so far
    for first in range(0, grid.num_cells, BLOCK_CELLS):
        stop = min(first + BLOCK_CELLS, grid.num_cells)
        conn, conn_end, faces, face_end = polyhedron_block(grid, first, stop)
        for key, values in (
            ("connectivity", conn),
            ("offsets", conn_end + ends[0]),
            ("faces", faces),
            ("faceoffsets", face_end + ends[1]),
        ):
            streams[key].add(values.astype(index, copy=False))
        ends += (conn.size, faces.size)
    types = _AppendedArray(compress, scratch)
    types.add(np.full(grid.num_cells, VTK_POLYHEDRON, dtype=np.uint8))
    label = _VTK_TYPES[np.dtype(index)]
    return [
        ("Cells", "connectivity", label, 1, streams["connectivity"].finish()),
        ("Cells", "offsets", label, 1, streams["offsets"].finish()),
        ("Cells", "types", "UInt8", 1, types.finish()),
        ("Cells", "faces", label, 1, streams["faces"].finish()),
        ("Cells", "faceoffsets", label, 1, streams["faceoffsets"].finish()),
    ]


def _index_type(grid: Grid) -> type:
    """Int32 for the polyhedra's index streams (half the bytes; VTK reads either) where every
    index and offset fits, else Int64: the faces stream holds, per cell, its face count and
    per face its node count and nodes."""
    nodes_per_face = np.diff(grid.faces.node_pos)
    faces_stream = grid.num_cells + grid.cells.faces.size + int(nodes_per_face[grid.cells.faces].sum())
    return np.int32 if max(faces_stream, grid.num_nodes) < 2**31 else np.int64


def _row_blocks(values: np.ndarray, rows: int):
    """``values`` in blocks of ``rows`` rows (views, no copies)."""
    for first in range(0, max(len(values), 1), rows):
        yield values[first : first + rows]
