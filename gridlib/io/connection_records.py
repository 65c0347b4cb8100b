"""Reading the records of MULTREGT, GRIDOPTS, NNC and EDITNNC (for :mod:`gridlib.io.grdecl`).

Each function turns the items of one ``/``-terminated record (as
:func:`~gridlib.io.eclipse_text.read_record` gives them: text, None where defaulted)
into a record of :mod:`gridlib.cornerpoint.connection_keywords`, or raises a
:class:`~gridlib.io.eclipse_text.DeckError` naming the file, line and keyword. Cell
indices are read 1-based and stored 0-based (linear, i fastest).
"""

from __future__ import annotations

from ..cornerpoint.connection_keywords import GridOptions, MultregtRecord
from ..errors import InputError
from .eclipse_text import DeckError, Item, Source, float_item, int_item

MULTREGT_ITEMS = "region1 region2 multiplier directions NNC-option region-set"
NNC_ITEMS = 17  # I1 J1 K1 I2 J2 K2 TRAN, then ten items gridlib does not use (tables, diffusivity, ...)
EDITNNC_ITEMS = 14  # I1 J1 K1 I2 J2 K2 multiplier, then seven items gridlib does not use


def _where(src: Source, at: int) -> str:
    return f"{src.path.name}:{src.line(at)}"


def _too_many(src: Source, at: int, keyword: str, items: list[Item], limit: int, layout: str) -> None:
    if len(items) > limit:
        raise src.error(at, keyword, f"a record has {len(items)} items, at most {limit} ({layout})")


def multregt_record(src: Source, at: int, keyword: str, items: list[Item]) -> MultregtRecord:
    """One MULTREGT record: region1 region2 multiplier [directions [NNC-option [region-set]]]."""
    _too_many(src, at, keyword, items, 6, MULTREGT_ITEMS)
    items = items + [None] * (6 - len(items))
    r1 = int_item(src, at, keyword, items[0], "region 1")
    r2 = int_item(src, at, keyword, items[1], "region 2")
    multiplier = float_item(src, at, keyword, items[2], "multiplier")
    if multiplier is None:
        raise src.error(at, keyword, f"a record needs a multiplier (items: {MULTREGT_ITEMS})")
    text = [None if v is None else v.upper() for v in items[3:6]]
    try:
        return MultregtRecord(
            None if r1 is None or r1 < 0 else r1,  # negative or defaulted: every region
            None if r2 is None or r2 < 0 else r2,
            multiplier,
            text[0] or "XYZ",
            text[1] or "ALL",
            text[2],
            _where(src, at),
        )
    except InputError as exc:
        raise src.error(at, keyword, str(exc).split("MULTREGT: ", 1)[-1]) from None


def gridopts_record(src: Source, at: int, keyword: str, items: list[Item]) -> GridOptions:
    """GRIDOPTS: TRANMULT (YES/NO) NRMULT NRPINC, any defaulted."""
    _too_many(src, at, keyword, items, 3, "TRANMULT NRMULT NRPINC")
    items = items + [None] * (3 - len(items))
    tranmult = (items[0] or "NO").upper()
    if tranmult not in ("YES", "NO"):
        raise src.error(at, keyword, f"TRANMULT must be YES or NO, got {items[0]!r}")
    counts = [int_item(src, at, keyword, items[n], what) for n, what in ((1, "NRMULT"), (2, "NRPINC"))]
    if any(c is not None and c < 0 for c in counts):
        raise src.error(at, keyword, f"NRMULT and NRPINC must be >= 0, got {items[1:]}")
    return GridOptions(tranmult == "YES", counts[0] or 0, counts[1] or 0)


def cell_pair_record(
    src: Source, at: int, keyword: str, items: list[Item], dims: tuple[int, int, int]
) -> tuple[int, int, float | None, bool]:
    """NNC or EDITNNC: the two cells (0-based linear), the value (item 7, None where
    defaulted) and whether any later item is given (they are not used)."""
    limit = NNC_ITEMS if keyword == "NNC" else EDITNNC_ITEMS
    what = "transmissibility" if keyword == "NNC" else "multiplier"
    _too_many(src, at, keyword, items, limit, f"I1 J1 K1 I2 J2 K2 {what} ...")
    ijk = [int_item(src, at, keyword, v, "cell index") for v in items[:6]]
    if len(ijk) < 6 or any(v is None for v in ijk):
        raise src.error(at, keyword, f"a record needs six cell indices I1 J1 K1 I2 J2 K2, got {items[:6]}")
    nx, ny, nz = dims
    cells = []
    for i, j, k in (ijk[:3], ijk[3:]):
        if not (1 <= i <= nx and 1 <= j <= ny and 1 <= k <= nz):
            raise src.error(at, keyword, f"cell ({i}, {j}, {k}) is not inside the {nx}x{ny}x{nz} grid")
        cells.append(i - 1 + nx * (j - 1 + ny * (k - 1)))
    if cells[0] == cells[1]:
        raise src.error(at, keyword, f"cell ({ijk[0]}, {ijk[1]}, {ijk[2]}) is joined to itself")
    value = float_item(src, at, keyword, items[6] if len(items) > 6 else None, what)
    if value is not None and (value != value or abs(value) == float("inf")):
        raise src.error(at, keyword, f"{what} must be finite, got {items[6]!r}")
    if keyword == "EDITNNC" and value is not None and value < 0:
        raise src.error(at, keyword, f"multiplier must be >= 0, got {items[6]!r}")
    return cells[0], cells[1], value, any(v is not None for v in items[7:])


__all__ = ["DeckError", "cell_pair_record", "gridopts_record", "multregt_record"]
