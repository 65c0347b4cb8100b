"""ROFF grid and parameter files (RMS's exchange format, read by xtgeo and ResInsight) for a
corner-point :class:`Deck`, binary or ASCII; the tag/record layer is equinor's ``roffio``.

The layout of a ROFF grid (facts as xtgeo's ROFF grid code reads and writes them):

* ``dimensions``: ``nX, nY, nZ``;
* ``translate``/``scale``: float32 offsets and scales; a stored (local) value ``v`` means
  ``(v + offset) * scale``. z is elevation (``zscale = -1`` turns it into depth);
* ``cornerLines``: per pillar, i slowest then j (C order over (i, j)), the pillar's
  *bottom* point (x, y, z) then its *top* point, float32 local values;
* ``zvalues``: per node (i, j, k) in C order (i slowest, k fastest), where ROFF's k
  counts *upward* (k = 0 is the bottom of the grid, the reverse of ECLIPSE's), ``splitEnz``
  (one byte: 1, 2, 4 or 8) values of the z of the up to eight cells meeting at the node:
  1 = all the same; 2 = the cells below, then those above; 4 = sw, se, nw, ne (south = lower j,
  west = lower i), the same below and above; 8 = the four below then the four above;
* ``active``: one bool per cell, i slowest, ROFF's k (upward) fastest;
* ``subgrids``: ``nLayers``, the layer counts of the zones from the top down.

Parameter files have ``filedata.filetype = "parameter"``, the dimensions and a
``parameter`` tag with ``name`` and ``data`` (float32 or int32, cells in the order of
``active``; -999.0 and -999 mark undefined values, as xtgeo and RMS read them).

ROFF stores float32: :func:`write_roff_grid` picks whole-number offsets (the floor of the
smallest x, y and depth), so a deck whose coordinates less those offsets are float32 values
round-trips bit for bit; otherwise the values are rounded to float32.
"""

from __future__ import annotations

import os
import struct
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..cornerpoint.deck import Deck
from ..cornerpoint.layer_overlaps import without_layer_overlaps
from ..cornerpoint.map_axes import MapAxes
from ..errors import InputError

# The neighbour slot of a node value: v (0 below, 1 above) * 4 + s/n (0 south, 1 north) * 2
# + w/e (0 west, 1 east). Per split, the slot -> the index of the value among the node's.
_SLOT_VALUE = {
    1: np.zeros(8, np.int64),
    2: np.repeat([0, 1], 4),
    4: np.tile([0, 1, 2, 3], 2),
    8: np.arange(8),
}
_READ_ERRORS = (
    ValueError,
    OSError,
    EOFError,
    UnicodeDecodeError,
    IndexError,
    KeyError,
    TypeError,
    struct.error,
)


@dataclass(frozen=True, eq=False)
class RoffGrid:
    """A ROFF grid read: the deck (COORD, ZCORN, ACTNUM), the zones' layer counts (top down;
    None if none) and the parameters the grid file holds (name -> one value per cell, i
    fastest, ECLIPSE's k down; undefined values as the file has them)."""

    deck: Deck
    subgrids: NDArray[np.int64] | None
    parameters: dict[str, np.ndarray] = field(default_factory=dict)


def _offset(values: NDArray[np.float64]) -> float:
    """A whole-number float32 offset at or below the smallest value (0 for none)."""
    return float(np.float32(np.floor(values.min()))) if values.size else 0.0


def _node_values(deck: Deck) -> NDArray[np.float64]:
    """(nx+1, ny+1, nz+1, 8): per node (ROFF's upward k) the depths of its eight slots; slots
    outside the grid copy a neighbour's, so they never force a split."""
    nx, ny, nz = deck.cart_dims
    z = deck.zcorn_array().reshape(nz, 2, ny, 2, nx, 2)  # k, c, j, b, i, a
    nodes = np.full((nz + 1, 2, ny + 1, 2, nx + 1, 2), np.nan)  # deck level, v, J, sn, I, we
    for v in (0, 1):  # below: the cell under the level (its top, c=0); above: its bottom, c=1
        ks, c = (slice(0, nz), 0) if v == 0 else (slice(1, nz + 1), 1)
        for sn in (0, 1):  # south: cell row J-1 (its north side, b=1)
            js, b = (slice(1, ny + 1), 1) if sn == 0 else (slice(0, ny), 0)
            for we in (0, 1):
                is_, a = (slice(1, nx + 1), 1) if we == 0 else (slice(0, nx), 0)
                nodes[ks, v, js, sn, is_, we] = z[:, c, :, b, :, a]
    for axis in (5, 3, 1):  # fill missing slots from their partners: w/e, then s/n, then v
        first, second = np.take(nodes, 0, axis=axis), np.take(nodes, 1, axis=axis)
        first, second = np.where(np.isnan(first), second, first), np.where(np.isnan(second), first, second)
        nodes = np.stack([first, second], axis=axis)
    out = nodes.transpose(4, 2, 0, 1, 3, 5)[:, :, ::-1]  # I, J, ROFF k, v, sn, we
    return out.reshape(nx + 1, ny + 1, nz + 1, 8)


def _splits(nodes: NDArray[np.float64]) -> tuple[NDArray[np.uint8], NDArray[np.float64]]:
    """The smallest split of every node and its values in ROFF order."""
    n = nodes.reshape(-1, 8)
    vertical = np.any(n[:, :4] != n[:, 4:], axis=1)
    lateral = np.any(n[:, :4] != n[:, :1], axis=1) | np.any(n[:, 4:] != n[:, 4:5], axis=1)
    split = np.where(vertical & lateral, 8, np.where(lateral, 4, np.where(vertical, 2, 1))).astype(np.uint8)
    keep = np.zeros(n.shape, bool)
    keep[:, 0] = True
    keep[split == 2, 4] = True
    keep[split == 4, 1:4] = True
    keep[split == 8, 1:] = True
    return split, n[keep]


# A ROFF file's suffixes (RMS and xtgeo's), and those of its ASCII form.
ROFF_SUFFIXES = (".roff", ".roffasc", ".roffbin", ".roff_asc")
ROFF_ASCII_SUFFIXES = (".roffasc", ".roff_asc")


def map_coordinates(deck: Deck) -> Deck:
    """``deck`` with its COORD in map coordinates where it has MAPAXES (then dropped), as RMS
    exports a ROFF grid: ``origin + x ex + y ey``, the MAPAXES origin (its second point) and
    the unit vectors towards its x-axis point (the third) and y-axis point (the first), the
    convention xtgeo and ResInsight apply (a GRDECL export of an RMS model is local with a
    MAPAXES, its ROFF export in world coordinates). Axes along east and north, as RMS writes
    them, make it a translation, one rounding per value. Depths are unchanged."""
    if deck.mapaxes is None:
        return deck
    coord = deck.coord.reshape(-1, 3).copy()
    coord[:, :2] = MapAxes.of(deck.mapaxes).to_map(coord[:, :2])
    return replace(deck, coord=coord.ravel(), mapaxes=None)


def layer_gaps(deck: Deck) -> int:
    """How many cell corners of ``deck`` open a vertical gap: a layer's top above its
    neighbour's bottom on the same pillar. ROFF stores them (nodes of split 2 or 8); xtgeo 4's
    reader refuses such a grid."""
    nx, ny, nz = deck.cart_dims
    z = deck.zcorn_array().reshape(nz, 2, ny * 2 * nx * 2)
    return int(np.count_nonzero(z[1:, 0] != z[:-1, 1]))


def write_roff_grid(
    path: str | os.PathLike,
    deck: Deck,
    *,
    subgrids: Any = None,
    binary: bool | None = None,
    parameters: Mapping[str, Any] | None = None,
) -> None:
    """Write ``deck``'s COORD, ZCORN and ACTNUM as a ROFF grid (binary, or ASCII if not
    ``binary``; None: ASCII for a ``.roffasc`` file); ``subgrids``: the zones' layer counts
    from the top down, summing to nz; ``parameters``: name -> one value per cell (i fastest,
    ECLIPSE's k down), written after the grid in the same file as ROFF parameter tags (as RMS
    exports a grid with its parameters; xtgeo reads each by its name).

    z is depth in the deck (positive down); the file stores elevation with zscale -1."""
    nx, ny, nz = deck.cart_dims
    if subgrids is not None:
        subgrids = np.asarray(subgrids, dtype=np.int32).ravel()
        if subgrids.sum() != nz or np.any(subgrids < 1):
            raise InputError(
                f"{path}: subgrids {subgrids.tolist()} must be positive layer counts summing to nz={nz}"
            )
    lines = deck.pillars().reshape(ny + 1, nx + 1, 2, 3).transpose(1, 0, 2, 3)[:, :, ::-1]  # I, J, bottom/top
    nodes = _node_values(deck)
    xo, yo = _offset(lines[..., 0].ravel()), _offset(lines[..., 1].ravel())
    depth_min = min(lines[..., 2].min(), nodes.min())
    zo = -_offset(np.array([depth_min]))
    local = lines - np.array([xo, yo, 0.0])
    local[..., 2] = -lines[..., 2] - zo
    split, zvals = _splits(-nodes - zo)
    active = deck.active.reshape(nz, ny, nx).transpose(2, 1, 0)[:, :, ::-1]
    data: dict[str, dict[str, Any]] = {
        "filedata": {"filetype": "grid"},
        "dimensions": {"nX": nx, "nY": ny, "nZ": nz},
        "translate": {"xoffset": np.float32(xo), "yoffset": np.float32(yo), "zoffset": np.float32(zo)},
        "scale": {"xscale": np.float32(1.0), "yscale": np.float32(1.0), "zscale": np.float32(-1.0)},
        "cornerLines": {"data": local.ravel().astype(np.float32)},
        "zvalues": {"splitEnz": split.tobytes(), "data": zvals.astype(np.float32)},
        "active": {"data": np.ascontiguousarray(active).ravel().astype(np.bool_)},
    }
    if subgrids is not None:
        data["subgrids"] = {"nLayers": subgrids}
    tags = list(data.items())
    for name, values in (parameters or {}).items():
        tags.append(("parameter", _parameter_tag(path, name, values, deck.cart_dims)))
    _write(path, tags, binary)


def _write(path: str | os.PathLike, tags: Any, binary: bool | None) -> None:
    """Write ``tags`` (a dict, or (tag, dict) pairs: a tag given more than once) with roffio
    (``binary`` None: ASCII if the suffix is ``.roffasc`` or ``.roff_asc``); in ASCII, bool array values
    become 1/0 (roffio 1.1 writes numpy bools as True/False, which no ROFF reader, roffio's
    included, accepts)."""
    import io

    import roffio

    if binary is None:
        binary = Path(path).suffix.lower() not in ROFF_ASCII_SUFFIXES
    tags = list(tags.items()) if hasattr(tags, "items") else list(tags)
    tags.insert(0, ("filedata", {"creationDate": _creation_date()}))
    if binary:
        roffio.write(str(path), tags, roff_format=roffio.Format.BINARY)
        return
    buffer = io.StringIO()
    roffio.write(buffer, tags, roff_format=roffio.Format.ASCII)
    Path(path).write_text(_bools(buffer.getvalue()), encoding="ascii")


def _creation_date() -> str:
    """The ``filedata.creationDate`` written: the time of ``SOURCE_DATE_EPOCH`` (the
    reproducible-builds convention; 0, 1970-01-01, where unset) rather than roffio's clock, so
    that the same grid gives the same bytes."""
    import time

    epoch = int(os.environ.get("SOURCE_DATE_EPOCH", "0") or 0)
    return time.strftime("%d/%m/%Y %H:%M:%S", time.gmtime(epoch))


def _roffio_errors() -> tuple[type[Exception], ...]:
    """roffio's exceptions for damaged files (its private modules, so looked up softly)."""
    from _roffio import endianess_handler, parser
    from _roffio.tokenizer import errors

    return (
        parser.RoffSyntaxError,
        parser.RoffTypeError,
        errors.TokenizationError,
        endianess_handler.RoffFormatError,
    )


def _bools(text: str) -> str:
    """ASCII ROFF with the bool values True/False that roffio 1.1 writes (and xtgeo with it)
    as the 1/0 the format has."""
    return "\n".join({"True": "1", "False": "0"}.get(line, line) for line in text.split("\n"))


def _readable(path: Path) -> Any:
    """``path``, or an ASCII file's text with its bools mended (see :func:`_bools`)."""
    import io

    with open(path, "rb") as stream:
        head = stream.read(8)
    if head != b"roff-asc":
        return str(path)
    return io.StringIO(_bools(path.read_text(encoding="latin-1")))


def _read(path: str | os.PathLike, filetype: str | None) -> dict[str, Any]:
    import roffio

    if not Path(path).is_file():
        raise InputError(f"{path}: no such file")
    try:
        tags = roffio.read(_readable(Path(path)))
    except (*_READ_ERRORS, *_roffio_errors()) as exc:
        raise InputError(f"{path}: not a readable ROFF file ({exc})") from None
    filedata = tags.get("filedata")
    found = filedata.get("filetype") if isinstance(filedata, dict) else None
    if found is None:
        raise InputError(f"{path}: not a ROFF {filetype or 'grid or parameter'} file (no filedata.filetype)")
    if filetype is not None and found != filetype:
        raise InputError(f"{path}: a ROFF {found} file, not a {filetype} file")
    return tags


def _need(tags: dict[str, Any], path: str | os.PathLike, tag: str, key: str) -> Any:
    try:
        value = tags[tag][key]
    except (KeyError, TypeError):
        raise InputError(f"{path}: ROFF tag {tag}.{key} is missing") from None
    if isinstance(value, list):
        raise InputError(f"{path}: ROFF tag {tag}.{key} is given more than once")
    return value


def _dims(tags: dict[str, Any], path: str | os.PathLike) -> tuple[int, int, int]:
    dims = tuple(int(_need(tags, path, "dimensions", k)) for k in ("nX", "nY", "nZ"))
    if min(dims) < 1:
        raise InputError(f"{path}: ROFF dimensions must be positive, got {dims}")
    return dims  # type: ignore[return-value]


def _sized(values: Any, n: int, path: str | os.PathLike, what: str, dtype: Any) -> np.ndarray:
    arr = np.frombuffer(values, np.uint8) if isinstance(values, bytes) else np.asarray(values)
    arr = arr.ravel().astype(dtype)
    if arr.size != n:
        raise InputError(f"{path}: ROFF {what} has {arr.size} values, expected {n}")
    return arr


def read_roff_grid(path: str | os.PathLike) -> RoffGrid:
    """Read a ROFF grid (binary or ASCII) into a :class:`Deck` (z depth) and its subgrids."""
    tags = _read(path, "grid")
    nx, ny, nz = _dims(tags, path)
    tr, sc = (
        tags.get(t, {}) if isinstance(tags.get(t, {}), dict) else {"": None} for t in ("translate", "scale")
    )
    if "" in tr or "" in sc:
        raise InputError(f"{path}: ROFF tag translate or scale is given more than once")
    off = np.array([float(tr.get(k, 0.0)) for k in ("xoffset", "yoffset", "zoffset")])
    scale = np.array([float(sc.get(k, 1.0)) for k in ("xscale", "yscale", "zscale")])
    nodes = (nx + 1) * (ny + 1) * (nz + 1)
    lines = _sized(
        _need(tags, path, "cornerLines", "data"), 6 * (nx + 1) * (ny + 1), path, "cornerLines", np.float64
    )
    lines = ((lines.reshape(nx + 1, ny + 1, 2, 3) + off) * scale)[:, :, ::-1].transpose(1, 0, 2, 3)
    split = _sized(_need(tags, path, "zvalues", "splitEnz"), nodes, path, "splitEnz", np.int64)
    if not np.isin(split, (1, 2, 4, 8)).all():
        raise InputError(f"{path}: ROFF splitEnz values must be 1, 2, 4 or 8")
    zvals = _sized(_need(tags, path, "zvalues", "data"), int(split.sum()), path, "zvalues", np.float64)
    start = np.cumsum(split) - split
    slot = np.stack([_SLOT_VALUE[s] for s in (1, 2, 4, 8)])[np.searchsorted([1, 2, 4, 8], split)]
    depth = ((zvals[start[:, None] + slot] + off[2]) * scale[2]).reshape(nx + 1, ny + 1, nz + 1, 2, 2, 2)
    depth = depth[:, :, ::-1].transpose(2, 3, 1, 4, 0, 5)  # deck level, v, J, sn, I, we
    z = np.empty((nz, 2, ny, 2, nx, 2))
    for v, ks, c in ((0, slice(0, nz), 0), (1, slice(1, nz + 1), 1)):
        for sn, js, b in ((0, slice(1, ny + 1), 1), (1, slice(0, ny), 0)):
            for we, is_, a in ((0, slice(1, nx + 1), 1), (1, slice(0, nx), 0)):
                z[:, c, :, b, :, a] = depth[ks, v, js, sn, is_, we]
    active = np.ones(nx * ny * nz, np.int32)
    if "active" in tags:
        act = _sized(_need(tags, path, "active", "data"), nx * ny * nz, path, "active", np.int32)
        active = act.reshape(nx, ny, nz)[:, :, ::-1].transpose(2, 1, 0).ravel()
    subgrids = None
    if "subgrids" in tags:
        subgrids = np.asarray(_need(tags, path, "subgrids", "nLayers"), dtype=np.int64).ravel()
        if subgrids.sum() != nz:
            raise InputError(f"{path}: ROFF subgrids {subgrids.tolist()} do not sum to nZ={nz}")
    deck = Deck((nx, ny, nz), lines.ravel(), z.ravel(), active, source=str(path))
    return RoffGrid(deck, subgrids, _parameters(tags, path))


def read_roff_subgrids(path: str | os.PathLike) -> NDArray[np.int64] | None:
    """The zones' layer counts (top down) of a ROFF grid file, None if it has none: the
    ``subgrids`` tag alone, the arrays left unread."""
    import roffio

    try:
        with roffio.lazy_read(_readable(Path(path))) as tags:
            for name, keys in tags:
                if name == "subgrids":
                    for key, value in keys:
                        if key == "nLayers":
                            return np.asarray(value, dtype=np.int64).ravel()
    except (*_READ_ERRORS, *_roffio_errors()) as exc:
        raise InputError(f"{path}: not a readable ROFF file ({exc})") from None
    return None


def read_roff_deck(path: str | os.PathLike) -> Deck:
    """The :class:`Deck` of a ROFF grid file (the registry's reader): its parameters named as
    GRID-section keywords (PORO, PERMX, PERMY, PERMZ, NTG, MULTX, FLUXNUM, ...; any case) are
    the deck's cell arrays (:func:`with_parameters`); subgrids dropped. Layers that overlap on
    a pillar are moved apart as OPM Flow reads the deck the case writes from it
    (:func:`~gridlib.cornerpoint.layer_overlaps.without_layer_overlaps`, noted)."""
    grid = read_roff_grid(path)
    return without_layer_overlaps(with_parameters(grid.deck, grid.parameters, str(path)))


def with_parameters(deck: Deck, parameters: Mapping[str, np.ndarray], source: str) -> Deck:
    """``deck`` with those of ``parameters`` whose upper-case names are GRID-section keywords
    as its cell arrays (float64, under the keyword); the others are named in its notes.

    RMS marks undefined values -999 (inactive cells): there they become 0, which the deck's
    inactive cells never use; in active cells they stay, and the rock checks name the cells."""
    from .grdecl.vocabulary import vocabulary

    known = vocabulary()
    taken, other = {}, []
    inactive = ~deck.active
    for name, values in parameters.items():
        info = known.get(name.upper())
        if info is None or not info.sections & {"GRID", "EDIT"}:
            other.append(name)
            continue
        values = values.astype(np.float64)
        taken[name.upper()] = np.where(inactive & (values == -999.0), 0.0, values)
    notes = (f"{source}: ROFF parameters not used as deck keywords: {', '.join(other)}",) if other else ()
    if not taken and not notes:
        return deck
    return replace(deck, cell_data={**deck.cell_data, **taken}, notes=(*deck.notes, *notes))


def _parameter_tag(
    path: str | os.PathLike, name: str, values: Any, cart_dims: tuple[int, int, int]
) -> dict[str, Any]:
    """The ``parameter`` tag of one value per cell (i fastest, ECLIPSE's k down): float32 for
    floating values, int32 for integers."""
    nx, ny, nz = (int(d) for d in cart_dims)
    arr = np.asarray(values).ravel()
    if arr.size != nx * ny * nz:
        raise InputError(f"{path}: parameter {name!r} has {arr.size} values, expected {nx * ny * nz}")
    dtype = np.int32 if np.issubdtype(arr.dtype, np.integer) or arr.dtype == bool else np.float32
    data = arr.reshape(nz, ny, nx).transpose(2, 1, 0)[:, :, ::-1].ravel().astype(dtype)
    return {"name": name, "data": data}


def write_roff_parameter(
    path: str | os.PathLike,
    name: str,
    values: Any,
    cart_dims: tuple[int, int, int],
    *,
    binary: bool | None = None,
) -> None:
    """Write one value per cell (i fastest, ECLIPSE's k down) as a ROFF parameter file of the
    parameter ``name``: float32 for floating values, int32 for integers."""
    nx, ny, nz = (int(d) for d in cart_dims)
    tags = {
        "filedata": {"filetype": "parameter"},
        "dimensions": {"nX": nx, "nY": ny, "nZ": nz},
        "parameter": _parameter_tag(path, name, values, cart_dims),
    }
    _write(path, tags, binary)


def read_roff_parameter(path: str | os.PathLike) -> tuple[str, np.ndarray]:
    """The name and values (i fastest, k down; float64 or int32) of a ROFF parameter file's
    (first) parameter; undefined values stay -999.0 / -999 (255 for bytes)."""
    params = read_roff_parameters(path, "parameter")
    if not params:
        raise InputError(f"{path}: ROFF tag parameter is missing")
    return next(iter(params.items()))


def read_roff_parameters(
    path: str | os.PathLike, filetype: str | None = "parameter"
) -> dict[str, np.ndarray]:
    """Every parameter of a ROFF ``filetype`` file (``"parameter"``; ``"grid"``: a grid file
    with its parameters, as RMS exports them; None: either), by name in the file's order: values i
    fastest, k down (float64 or int32); undefined values stay -999.0 / -999 (255 for bytes)."""
    return _parameters(_read(path, filetype), path)


def _parameters(tags: dict[str, Any], path: str | os.PathLike) -> dict[str, np.ndarray]:
    found = tags.get("parameter", [])
    found = found if isinstance(found, list) else [found]
    if not found:
        return {}
    nx, ny, nz = _dims(tags, path)
    out: dict[str, np.ndarray] = {}
    for tag in found:
        name = str(_need({"parameter": tag}, path, "parameter", "name"))
        raw = _need({"parameter": tag}, path, "parameter", "data")
        arr = np.frombuffer(raw, np.uint8) if isinstance(raw, bytes) else np.asarray(raw)
        dtype = np.float64 if np.issubdtype(arr.dtype, np.floating) else np.int32
        arr = _sized(arr, nx * ny * nz, path, f"parameter {name!r}", dtype)
        out.setdefault(name, arr.reshape(nx, ny, nz)[:, :, ::-1].transpose(2, 1, 0).ravel())
    return out
