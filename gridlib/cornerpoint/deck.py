"""The corner-point deck: what the GRID section of an ECLIPSE deck describes.

Layout (ECLIPSE's, kept as in the file so that a written deck round-trips):

* ``coord``: 6 numbers per pillar, ``(nx+1) * (ny+1)`` pillars with i fastest:
  the pillar's top point (x, y, z) then its bottom point (x, y, z);
* ``zcorn``: ``8 * nx * ny * nz`` corner depths, the array of shape
  ``(2nz, 2ny, 2nx)`` in C order (i fastest): cell (i, j, k) owns the entries
  ``[2k:2k+2, 2j:2j+2, 2i:2i+2]``, and the corner in column ``2i + a``, row
  ``2j + b`` lies on pillar ``(i + a, j + b)``;
* ``actnum``: 1 for active cells, 0 for inactive ones (None = all active);
* ``cell_data``: every other numeric cell keyword (PORO, NTG, PERMX, ...), one
  float64 value per cell, i fastest.

Depths are z values along the pillars; in most decks z is depth (positive
down), but z-up and left-handed decks exist and are normalised by
``process_grdecl``. Units are those of the deck (``units``: METRIC, FIELD,
LAB or PVT-M; lengths in m, ft, cm, m; None where the file does not say, as
in a GRDECL include file; ECLIPSE's default is METRIC).

Fault segments are stored 0-based and inclusive (i1 <= i <= i2), with the face
as in the FAULTS keyword: X, Y, Z (the +i, +j, +k face of the cells in the box)
or X-, Y-, Z- (the -i, -j, -k face); I/J/K are read as X/Y/Z.

Connections, two kinds of records (0-based linear cell indices, i fastest):

* ``nnc``: the non-neighbour connections a *simulator wrote* into an EGRID (NNC1/NNC2),
  pairs only (``read_egrid``); None for a text deck;
* ``nnc_keyword``: the NNC keyword's records, pairs with the transmissibility the deck
  gives (deck units), which a simulator adds to what it computes; ``editnnc``: the
  EDITNNC records, pairs with a multiplier (:class:`CellPairs`).

Multipliers and edits a simulator applies to the transmissibilities it computes, as
read (:mod:`gridlib.cornerpoint.connection_keywords`): MULTX/MULTX-/... are cell
keywords in ``cell_data`` (the EDIT section's arrays already multiplied in), MULTFLT
in ``multflt`` (the last value given for each fault, GRID then EDIT), ``multregt``
(MULTREGT records in deck order), ``gridopts`` (GRIDOPTS) and ``tran_edits`` (the EDIT
section's operations on TRANX/TRANY/TRANZ in deck order).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .connection_keywords import CellPairs, GridOptions, MultregtRecord, TranEdit
from .map_axes import MapAxes

FAULT_FACES = ("X", "X-", "Y", "Y-", "Z", "Z-")
# PINCH items 2, 4 and 5, ECLIPSE's defaults: the gap mode (GAP: a pinch-out may join cells
# across a removed gap; NOGAP: only across thin cells), how pinch-outs are made (TOPBOT or
# ALL) and which MULTZ a pinch-out connection takes (TOP: the upper cell's; ALL: the
# smallest along the column between the two cells).
PINCH_DEFAULTS = ("GAP", "TOPBOT", "TOP")


def shown(value: object) -> str:
    """``value`` for a message as Python writes it: NumPy scalars and arrays as plain numbers and
    lists (``[3, 2]``, not ``array([3, 2])`` or ``np.int64(3)``).

    >>> shown(np.array([3, 2])), shown((np.int64(3), 2.5)), shown("x")
    ('[3, 2]', '(3, 2.5)', "'x'")
    """
    if isinstance(value, np.ndarray | np.generic):
        return repr(value.tolist())
    if isinstance(value, tuple | list):
        inner = ", ".join(shown(v) for v in value)
        return f"({inner}{',' if len(value) == 1 else ''})" if isinstance(value, tuple) else f"[{inner}]"
    return repr(value)


@dataclass(frozen=True)
class FaultSegment:
    """One line of the FAULTS keyword: a box of cells and the face they fault."""

    name: str
    i1: int
    i2: int
    j1: int
    j2: int
    k1: int
    k2: int
    face: str  # one of FAULT_FACES

    def __post_init__(self) -> None:
        if self.face not in FAULT_FACES:
            raise InputError(
                f"fault '{self.name}': face '{self.face}' is not one of {', '.join(FAULT_FACES)}"
            )


def runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The runs of True along the last axis of a 2-D mask, (row, first, last) row-major, 0-based
    and inclusive: the boxes of FaultSegments along a row of cell faces.

    >>> [v.tolist() for v in runs(np.array([[True, True, False, True], [False, True, True, True]]))]
    [[0, 0, 1], [0, 3, 1], [1, 3, 3]]
    """
    padded = np.pad(mask.astype(np.int8), ((0, 0), (1, 1)))
    step = np.diff(padded, axis=1)
    r0, c0 = np.nonzero(step == 1)
    _, c1 = np.nonzero(step == -1)
    return r0, c0, c1 - 1


@dataclass(frozen=True, eq=False)
class Deck:
    """A corner-point grid deck (GRID section), arrays read-only, ECLIPSE layout."""

    cart_dims: tuple[int, int, int]
    coord: NDArray[np.float64]
    zcorn: NDArray[np.float64]
    actnum: NDArray[np.int32] | None = None
    cell_data: dict[str, NDArray[np.float64]] = field(default_factory=dict)
    faults: tuple[FaultSegment, ...] = ()
    multflt: dict[str, float] = field(default_factory=dict)
    mapaxes: NDArray[np.float64] | None = None
    mapunits: str | None = None
    gridunit: str | None = None
    units: str | None = None
    pinch: tuple[float, ...] | None = None  # PINCH threshold thickness and maximum gap, if given
    minpv: float | None = None
    source: str = "<memory>"
    notes: tuple[str, ...] = ()  # what the reader skipped or assumed
    nnc: NDArray[np.int64] | None = None  # (n, 2) NNC pairs an EGRID lists, 0-based linear cell indices
    pinch_options: tuple[str, str, str] = PINCH_DEFAULTS  # PINCH items 2, 4, 5 (see PINCH_DEFAULTS)
    nnc_keyword: CellPairs | None = None  # NNC keyword: pairs and transmissibilities (deck units)
    editnnc: CellPairs | None = None  # EDITNNC: pairs and multipliers
    multregt: tuple[MultregtRecord, ...] = ()  # MULTREGT records in deck order
    gridopts: GridOptions | None = None  # GRIDOPTS, if given
    tran_edits: tuple[TranEdit, ...] = ()  # EDIT operations on TRANX/TRANY/TRANZ in deck order

    def __post_init__(self) -> None:
        nx, ny, nz = (int(d) for d in self.cart_dims)
        if min(nx, ny, nz) < 1:
            raise InputError(f"{self.source}: grid dimensions must be positive, got {self.cart_dims}")
        object.__setattr__(self, "cart_dims", (nx, ny, nz))
        nc = nx * ny * nz
        checks = (
            ("COORD", "coord", 6 * (nx + 1) * (ny + 1), np.float64),
            ("ZCORN", "zcorn", 8 * nc, np.float64),
        )
        for keyword, attr, n, dtype in checks:
            arr = np.asarray(getattr(self, attr), dtype=dtype).ravel()
            if arr.size != n:
                raise InputError(
                    f"{self.source}: {keyword} has {arr.size} values, expected {n} for a {nx}x{ny}x{nz} grid"
                )
            arr.flags.writeable = False
            object.__setattr__(self, attr, arr)
        if self.actnum is not None:
            act = np.asarray(self.actnum).ravel()
            if act.size != nc:
                raise InputError(f"{self.source}: ACTNUM has {act.size} values, expected {nc}")
            act = (act != 0).astype(np.int32)
            act.flags.writeable = False
            object.__setattr__(self, "actnum", act)
        data = {}
        for name, values in self.cell_data.items():
            arr = np.asarray(values, dtype=np.float64).ravel()
            if arr.size != nc:
                raise InputError(f"{self.source}: {name} has {arr.size} values, expected {nc}")
            arr.flags.writeable = False
            data[name.upper()] = arr
        object.__setattr__(self, "cell_data", data)
        if self.nnc is not None:
            pairs = np.asarray(self.nnc, dtype=np.int64).reshape(-1, 2)
            if pairs.size and (pairs.min() < 0 or pairs.max() >= nc):
                raise InputError(f"{self.source}: NNC cell indices must lie in [0, {nc})")
            pairs.flags.writeable = False
            object.__setattr__(self, "nnc", pairs)
        self._check_connection_keywords(nc)
        if self.mapaxes is not None:
            m = np.asarray(self.mapaxes, dtype=np.float64).ravel()
            try:
                MapAxes.of(m)  # six finite numbers making a frame
            except ValueError as exc:
                raise InputError(f"{self.source}: {exc}") from None
            object.__setattr__(self, "mapaxes", m)

    def _check_connection_keywords(self, nc: int) -> None:
        for keyword, records in (("NNC", self.nnc_keyword), ("EDITNNC", self.editnnc)):
            if records is not None:
                if not isinstance(records, CellPairs):
                    raise InputError(f"{self.source}: {keyword} records must be CellPairs")
                if records.num and (records.cells.min() < 0 or records.cells.max() >= nc):
                    raise InputError(f"{self.source}: {keyword} cell indices must lie in [0, {nc})")
        object.__setattr__(self, "multregt", tuple(self.multregt))
        object.__setattr__(self, "tran_edits", tuple(self.tran_edits))
        for edit in self.tran_edits:
            if any(edit.box[2 * a + 1] >= self.cart_dims[a] for a in range(3)):
                raise InputError(f"{self.source}: {edit.keyword}: box {edit.box} is not inside the grid")

    @property
    def map_axes(self) -> MapAxes | None:
        """Where the grid lies on the map (its MAPAXES; None: the grid's frame is the map's)."""
        return None if self.mapaxes is None else MapAxes.of(self.mapaxes)

    @property
    def num_cells(self) -> int:
        nx, ny, nz = self.cart_dims
        return nx * ny * nz

    @property
    def active(self) -> NDArray[np.bool_]:
        """Boolean active mask per cell (all True without ACTNUM)."""
        if self.actnum is None:
            return np.ones(self.num_cells, dtype=bool)
        return self.actnum.astype(bool)

    def pillars(self) -> NDArray[np.float64]:
        """COORD as a (ny+1, nx+1, 2, 3) view: [j, i, top/bottom, xyz]."""
        nx, ny, _ = self.cart_dims
        return self.coord.reshape(ny + 1, nx + 1, 2, 3)

    def zcorn_array(self) -> NDArray[np.float64]:
        """ZCORN as a (2nz, 2ny, 2nx) view."""
        nx, ny, nz = self.cart_dims
        return self.zcorn.reshape(2 * nz, 2 * ny, 2 * nx)
