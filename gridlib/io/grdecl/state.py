"""What the GRDECL reader has read so far, across INCLUDEd files (:class:`ReaderState`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...cornerpoint.connection_keywords import GridOptions, MultregtRecord, TranEdit
from ...cornerpoint.deck import PINCH_DEFAULTS, Deck, FaultSegment

__all__ = ["ReaderState"]


@dataclass
class ReaderState:
    """Everything read so far, across INCLUDEd files."""

    main: Path
    unknown_keywords: str = "error"  # or "skip": see read_grdecl
    dims: tuple[int, int, int] | None = None
    arrays: dict[str, np.ndarray] = field(default_factory=dict)
    coord: np.ndarray | None = None
    zcorn: np.ndarray | None = None
    vectors: dict[str, np.ndarray] = field(default_factory=dict)  # DXV, DYV, DZV, DEPTHZ
    box: tuple[int, int, int, int, int, int] | None = None  # 0-based inclusive
    faults: list[FaultSegment] = field(default_factory=list)
    multflt: dict[str, float] = field(default_factory=dict)
    mapaxes: np.ndarray | None = None
    mapunits: str | None = None
    gridunit: str | None = None
    units: str | None = None
    pinch: tuple[float, ...] | None = None
    pinch_options: tuple[str, ...] = PINCH_DEFAULTS
    minpv: float | None = None
    porv_multpv: np.ndarray | None = None  # MULTPV when EDIT first set PORV (then x its MULTIPLYs)
    multregt: list[MultregtRecord] = field(default_factory=list)
    gridopts: GridOptions | None = None
    tran_edits: list[TranEdit] = field(default_factory=list)
    cell_pairs: dict[str, list[tuple[int, int, float, str]]] = field(default_factory=dict)  # NNC, EDITNNC
    multflt_sources: dict[str, str] = field(default_factory=dict)  # fault -> where its MULTFLT was set
    multregp: dict[int, tuple[str, float, str]] = field(
        default_factory=dict
    )  # region -> (set, multiplier, where)
    gdfile: Deck | None = None
    paths: dict[str, str] = field(default_factory=dict)
    section: str | None = None
    stopped: bool = False
    notes: list[str] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)  # keyword -> where first seen
    unknown: dict[str, str] = field(default_factory=dict)  # keywords nobody knows -> where first seen
    size_records: dict[str, list] = field(default_factory=dict)  # TABDIMS etc.: first record's items

    @property
    def num_cells(self) -> int:
        assert self.dims is not None
        return self.dims[0] * self.dims[1] * self.dims[2]
