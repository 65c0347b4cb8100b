"""What a deck's values may be: the checks the reader makes as it stores each keyword's values, so
that a refusal names the file, the line, the keyword and the cells (i, j, k), 1-based.

The rule is OPM Flow 2022.10's reading, no stricter (each case run through Flow's dry run), except
where Flow reads a value and computes nothing meaningful from it; those are errors here:

* any value written as ``nan`` or ``inf`` (Flow reads them and writes NaN or infinite pore volumes
  and transmissibilities, or aborts: ``MINPV inf``, ``DX nan``);
* negative cell sizes DX, DY, DZ, DXV, DYV, DZV (Flow builds inverted or collapsed cells);
* lengths (COORD, ZCORN, DX ..., TOPS, DEPTHZ) beyond 1e100 in size: cell volumes overflow;
* negative multipliers MULTX ... MULTZ-, MULTPV and MULTFLT (Flow writes negative
  transmissibilities and pore volumes);
* ACTNUM values that are not integers (Flow: "Malformed integer").

Read as Flow reads them, with a note: ACTNUM above 1 (active) or below 0 (inactive), a negative
PINCH threshold (no gap is thin enough to be pinched out) and a negative MINPV (no cell is
removed). PORO, NTG and permeabilities are checked on the active cells once the grid is known
(:mod:`gridlib.petrophysics.ranges`): an inactive cell may carry any value.
"""

from __future__ import annotations

import numpy as np

from ...cell_names import cell_names
from ..eclipse_text import Source
from .state import ReaderState

__all__ = ["MAX_LENGTH", "check_cell_values", "check_finite", "check_not_negative", "normalised_actnum"]

SIZE_KEYWORDS = frozenset({"DX", "DY", "DZ"})
# Lengths (COORD, ZCORN, DX, TOPS, ...) beyond this make cell volumes overflow float64 (1e300).
MAX_LENGTH = 1e100
MULTIPLIER_KEYWORDS = frozenset({f"MULT{d}{s}" for d in "XYZ" for s in ("", "-")} | {"MULTPV"})


def check_cell_values(
    state: ReaderState,
    src: Source,
    at: int,
    name: str,
    values: np.ndarray,
    cells: np.ndarray | slice,
    given: np.ndarray | None = None,
    operation: str | None = None,
) -> None:
    """Check the ``values`` keyword ``name`` (at ``at`` in ``src``) sets in ``cells`` (linear
    indices, or all cells); ``given``: where the deck wrote a value (not ``n*``), default all;
    ``operation``: the keyword that set them (EQUALS, MULTIPLY, ...), if not ``name`` itself."""
    where = name if operation is None else f"{operation}: {name}"
    literal = values if given is None else values[given]
    if not np.isfinite(literal).all():
        bad = ~np.isfinite(values) if given is None else ~np.isfinite(values) & given
        _refuse(state, src, at, where, values, cells, bad, "not finite numbers")
    if name in SIZE_KEYWORDS or name == "TOPS":
        huge = np.abs(values) > MAX_LENGTH
        _refuse(
            state, src, at, where, values, cells, huge, f"beyond +-{MAX_LENGTH:g}", "volumes would overflow"
        )
    if name in SIZE_KEYWORDS:
        _refuse(state, src, at, where, values, cells, values < 0, "negative", "a cell size cannot be")
    elif name in MULTIPLIER_KEYWORDS:
        _refuse(
            state, src, at, where, values, cells, values < 0, "negative",
            "OPM Flow would compute negative transmissibilities or pore volumes from them",
        )  # fmt: skip
    elif name == "ACTNUM":
        _refuse(
            state, src, at, where, values, cells, (values != np.floor(values)) & ~np.isnan(values),
            "not integers", "ACTNUM is 1 for active cells, 0 for inactive ones",
        )  # fmt: skip
        for bad, what in ((values > 1, "above 1: active"), (values < 0, "below 0: inactive")):
            if bad.any():
                state.notes.append(
                    f"{src.path.name}:{src.line(at)}: {where}: {int(bad.sum())} cells {what}, as OPM Flow "
                    f"reads them: {_cells(state, cells, bad)}"
                )


def check_finite(src: Source, at: int, name: str, value: float | None, what: str) -> None:
    """A single value of a record (a threshold, a multiplier) must be a finite number."""
    if value is not None and not np.isfinite(value):
        raise src.error(at, name, f"{what} {value} is not a finite number")


def check_not_negative(src: Source, at: int, name: str, value: float | None, what: str) -> None:
    check_finite(src, at, name, value, what)
    if value is not None and value < 0:
        raise src.error(at, name, f"{what} {value:g} is negative")


def normalised_actnum(actnum: np.ndarray) -> np.ndarray:
    """ACTNUM as OPM Flow reads it: active (1) where above 0, inactive (0) elsewhere; undefined
    (NaN: no value given) active."""
    return np.where(np.isnan(actnum) | (actnum > 0), 1, 0).astype(np.int32)


def _refuse(state, src, at, where, values, cells, bad, what, why="") -> None:
    if not bad.any():
        return
    first = float(values[np.flatnonzero(bad)[0]])
    why = f"; {why}" if why else ""
    raise src.error(
        at,
        where,
        f"{int(bad.sum())} values are {what} (first {first:g}): cells {_cells(state, cells, bad)}{why}",
    )


def _cells(state: ReaderState, cells: np.ndarray | slice, bad: np.ndarray) -> str:
    linear = np.arange(state.num_cells)[cells] if isinstance(cells, slice) else np.asarray(cells)
    return cell_names(np.flatnonzero(bad), index_map=linear, cart_dims=state.dims)
