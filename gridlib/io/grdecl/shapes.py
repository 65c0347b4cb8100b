"""Skipping the data of a keyword the reader does not use, by the shape the vocabulary gives it
(:class:`~gridlib.io.grdecl.vocabulary.Shape`), as OPM Flow's parser delimits it: so that a
record whose words look like keywords (``GDORIENT`` / ``INC INC INC DOWN RIGHT /``) or a table
without a closing empty record is skipped exactly.
"""

from __future__ import annotations

from ..eclipse_text import Item, Source, line_word, next_line, read_record, skip_array, skip_blank
from .state import ReaderState
from .vocabulary import KeywordInfo

__all__ = ["record_count", "skip_data"]


def skip_data(state: ReaderState, src: Source, pos: int, info: KeywordInfo) -> int:
    """The position after the data of keyword ``info`` that start at ``pos``.

    The first record of a keyword that sizes others (TABDIMS, EQLDIMS, ...) is kept in
    ``state.size_records``.
    """
    shape, name = info.shape, info.name
    kind = shape.kind
    if kind == "none":
        return pos
    if kind == "data":
        return skip_array(src, pos, name)
    if kind == "code":
        assert shape.end is not None
        end = src.data.find(shape.end.encode("ascii"), pos)
        if end < 0:
            raise src.error(pos, name, f"no {shape.end} ends it")
        return next_line(src.data, end)
    if kind == "list":
        return _until_empty(src, pos, name, 1)
    if kind == "sets":
        return _until_empty(src, pos, name, 2)
    if kind == "tables":
        for _ in range(record_count(state, src, pos, info)):
            pos = _until_empty(src, pos, name, 1)
        return pos
    if kind == "open":
        while not _keyword_next(src, pos):
            _, pos, _ = read_record(src, pos, name)
        return pos
    count = shape.count if kind == "records" else record_count(state, src, pos, info)
    for n in range(count):
        if shape.min_count is not None and n >= shape.min_count and _keyword_next(src, pos):
            break
        items, pos, _ = read_record(src, pos, name)
        if n == 0:
            state.size_records[name] = items
    return pos


def record_count(state: ReaderState, src: Source, pos: int, info: KeywordInfo) -> int:
    """How many records (or tables) a ``sized``/``tables`` keyword has: an item of an earlier
    keyword (e.g. TABDIMS item 1 for SWOF), or that item's default when the keyword is absent."""
    assert info.shape.count_from is not None
    keyword, item, default, shift, factor = info.shape.count_from
    items: list[Item] = state.size_records.get(keyword, [])
    value = items[item - 1] if 0 < item <= len(items) else None
    if value is None:
        value = default
    if value is None:
        raise src.error(
            pos, info.name, f"its number of records is item {item} of {keyword}, which the deck lacks"
        )
    try:
        count = int(value)
    except ValueError:
        raise src.error(pos, keyword, f"item {item}: {value!r} is not an integer") from None
    return (count + shift) * factor


def _until_empty(src: Source, pos: int, name: str, empties: int) -> int:
    """Records up to ``empties`` empty records in a row."""
    run = 0
    while run < empties:
        items, pos, _ = read_record(src, pos, name)
        run = 0 if items else run + 1
    return pos


def _keyword_next(src: Source, pos: int) -> bool:
    """Does the next line that is not blank start with a keyword (or is it the end of the file)?"""
    word = line_word(src.data, skip_blank(src.data, pos))
    return word is None or word.decode("latin-1").upper() in src.keywords
