"""Deck keywords that change connections after the grid is built: what they say, as read.

A simulator computes transmissibilities from the grid (NEWTRAN), then modifies them
with these keywords; :mod:`gridlib.transmissibility.deck_connections` replays them in OPM Flow's
order. Here they are only records, as the deck gives them, validated:

* :class:`MultregtRecord`: one MULTREGT record (GRID or EDIT section), a multiplier
  for the connections between two regions of FLUXNUM, MULTNUM or OPERNUM;
* :class:`GridOptions`: GRIDOPTS (RUNSPEC): TRANMULT, NRMULT, NRPINC;
* :class:`TranEdit`: one operation of the EDIT section on TRANX, TRANY or TRANZ, the
  transmissibility of each cell's connection to its +i, +j or +k neighbour (values the
  simulator computes, so the operations are kept to be replayed in deck order);
* :class:`CellPairs`: the records of NNC (two cells and a transmissibility) or of
  EDITNNC (two cells and a multiplier).

Indices are 0-based: cells are linear indices ``i + nx (j + ny k)``; boxes are
``(i1, i2, j1, j2, k1, k2)``, inclusive. Transmissibilities are in the deck's unit
(METRIC cP m3/(day bar), FIELD cP rb/(day psi), ...; see :mod:`gridlib.units`).
``source`` is where a record was read, ``file:line``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError

REGION_SETS = {"F": "FLUXNUM", "M": "MULTNUM", "O": "OPERNUM"}  # MULTREGT item 6
MULTREGT_DIRECTIONS = ("X", "Y", "Z", "XY", "XZ", "YZ", "XYZ")  # the spellings Flow accepts
MULTREGT_NNC_OPTIONS = ("ALL", "NNC", "NONNC", "NOAQUNNC")
TRAN_KEYWORDS = ("TRANX", "TRANY", "TRANZ")
TRAN_OPERATIONS = ("SET", "EQUALS", "MULTIPLY", "ADD", "MINVALUE", "MAXVALUE")

Box = tuple[int, int, int, int, int, int]


@dataclass(frozen=True)
class MultregtRecord:
    """One MULTREGT record: connections between ``region1`` and ``region2`` (either order)
    are multiplied by ``multiplier``.

    ``region1``/``region2``: region numbers; None for every region (the item defaulted
    or negative). ``directions``: the axes it applies to (X, Y, Z, XY, XZ, YZ, XYZ;
    default XYZ). ``nnc_option``: ALL (default), NNC (only connections that are not
    between side-by-side columns), NONNC (only those), NOAQUNNC. ``region_set``: "F"
    FLUXNUM, "M" MULTNUM, "O" OPERNUM, or None where defaulted (resolved when applied).
    """

    region1: int | None
    region2: int | None
    multiplier: float
    directions: str = "XYZ"
    nnc_option: str = "ALL"
    region_set: str | None = None
    source: str = ""

    def __post_init__(self) -> None:
        where = f"{self.source}: MULTREGT" if self.source else "MULTREGT"
        if not np.isfinite(self.multiplier) or self.multiplier < 0:
            raise InputError(f"{where}: the multiplier must be a finite number >= 0, got {self.multiplier!r}")
        if self.directions not in MULTREGT_DIRECTIONS:
            raise InputError(
                f"{where}: directions {self.directions!r} are not one of {', '.join(MULTREGT_DIRECTIONS)}"
            )
        if self.nnc_option not in MULTREGT_NNC_OPTIONS:
            raise InputError(
                f"{where}: NNC option {self.nnc_option!r} is not one of {', '.join(MULTREGT_NNC_OPTIONS)}"
            )
        if self.region_set is not None and self.region_set not in REGION_SETS:
            raise InputError(f"{where}: region set {self.region_set!r} is not one of M, F, O")
        for name in ("region1", "region2"):
            value = getattr(self, name)
            if value is not None and value < 1:
                raise InputError(f"{where}: {name} must be a positive region number or defaulted")


@dataclass(frozen=True)
class GridOptions:
    """GRIDOPTS: ``tranmult`` (item 1, YES: negative-direction multipliers MULTX- etc.
    are allowed), ``nrmult`` (item 2, number of MULTNUM regions; > 0 makes MULTNUM the
    default region set of MULTREGT in OPM Flow), ``nrpinc`` (item 3, PINCHNUM regions)."""

    tranmult: bool = False
    nrmult: int = 0
    nrpinc: int = 0


@dataclass(frozen=True, eq=False)
class TranEdit:
    """One EDIT-section operation on TRANX, TRANY or TRANZ over a box of cells.

    ``operation``: SET (the keyword itself with one value per cell of the box:
    ``values``, NaN where defaulted with ``n*``, which leaves the value as it was),
    or EQUALS, MULTIPLY, ADD, MINVALUE, MAXVALUE with one ``value``. A cell's TRANX
    is its connection to the cell at i+1 (TRANY j+1, TRANZ k+1).
    """

    keyword: str
    operation: str
    box: Box
    value: float | None = None
    values: NDArray[np.float64] | None = None
    source: str = ""

    def __post_init__(self) -> None:
        where = f"{self.source}: {self.keyword}" if self.source else self.keyword
        if self.keyword not in TRAN_KEYWORDS:
            raise InputError(f"{where}: not one of {', '.join(TRAN_KEYWORDS)}")
        if self.operation not in TRAN_OPERATIONS:
            known = ", ".join(TRAN_OPERATIONS)
            raise InputError(f"{where}: operation {self.operation!r} is not one of {known}")
        box = tuple(int(b) for b in self.box)
        if len(box) != 6 or min(box) < 0 or box[0] > box[1] or box[2] > box[3] or box[4] > box[5]:
            raise InputError(f"{where}: box {box} is not a 0-based inclusive (i1, i2, j1, j2, k1, k2)")
        object.__setattr__(self, "box", box)
        if self.operation == "SET":
            if self.values is None or self.value is not None:
                raise InputError(f"{where}: the keyword itself gives one value per cell (values), no scalar")
            values = np.array(self.values, dtype=np.float64).ravel()
            if values.size != self.num_cells:
                raise InputError(f"{where}: has {values.size} values, expected {self.num_cells} for its box")
            values.flags.writeable = False
            object.__setattr__(self, "values", values)
        elif self.value is None or self.values is not None or not np.isfinite(self.value):
            raise InputError(f"{where}: {self.operation} needs one finite value")

    @property
    def num_cells(self) -> int:
        i1, i2, j1, j2, k1, k2 = self.box
        return (i2 - i1 + 1) * (j2 - j1 + 1) * (k2 - k1 + 1)

    def cells(self, dims: tuple[int, int, int]) -> NDArray[np.int64]:
        """Linear indices (i fastest) of the box's cells, in the order of ``values``."""
        nx, ny, _ = dims
        i1, i2, j1, j2, k1, k2 = self.box
        k, j, i = np.meshgrid(
            np.arange(k1, k2 + 1), np.arange(j1, j2 + 1), np.arange(i1, i2 + 1), indexing="ij"
        )
        return (i + nx * (j + ny * k)).ravel()


@dataclass(frozen=True, eq=False)
class CellPairs:
    """Records of NNC or EDITNNC in deck order: two cells and one value each.

    ``cells`` (n, 2): 0-based linear indices as the records give them (not reordered);
    ``values`` (n,): NNC's transmissibility (deck units) or EDITNNC's multiplier;
    ``sources``: where each record was read.
    """

    cells: NDArray[np.int64]
    values: NDArray[np.float64]
    sources: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        cells = np.array(self.cells, dtype=np.int64).reshape(-1, 2)
        values = np.array(self.values, dtype=np.float64).ravel()
        if values.size != cells.shape[0] or (self.sources and len(self.sources) != values.size):
            raise InputError("CellPairs: cells (n, 2), values (n,) and sources (n or none) must agree")
        if not np.isfinite(values).all():
            raise InputError("CellPairs: values must be finite")
        cells.flags.writeable = False
        values.flags.writeable = False
        object.__setattr__(self, "cells", cells)
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "sources", tuple(self.sources))

    @property
    def num(self) -> int:
        return int(self.values.size)
