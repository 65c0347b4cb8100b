"""Lexing ECLIPSE keyword files: keywords, ``/``-terminated records, bulk numbers; and writing
arrays back as exact text (:func:`format_values`, for GRDECL files and Flow decks).

The syntax (ECLIPSE reference manual, "data file overview"), as OPM Flow 2022.10 reads it:

* a keyword (1-8 characters, starting with a letter) is the first word of its
  line; the rest of that line is ignored and its data start on the next line;
* data are records ended by ``/``, over as many lines as they need; the rest of
  the line after a record's ``/`` is a comment (a second record on the same line
  is not read); multi-record keywords end with an empty record (a ``/`` alone);
* ``--`` starts a comment that runs to the end of the line (not inside quotes);
* items are separated by blanks or commas; ``n*v`` is n copies of v, ``n*`` is
  n defaulted values;
* strings may be quoted with ``'``; a quoted string may contain blanks and ``/``.

Bulk numeric data (COORD, ZCORN, cell arrays: millions of numbers) take a fast
path with no Python loop per number: the text up to the ``/`` is cut out,
comments are dropped, whitespace becomes line breaks and pandas' C parser
turns it into float64 (correctly rounded: written values read back
bit-identical). Repeat counts become a second column. Anything the fast path
cannot read goes to a token-by-token path that reads what is valid (Fortran
``D`` exponents, ``nan``) and otherwise raises an error naming the file, the
line, the keyword and the offending token.

Writing: :func:`format_values` gives the text of an array in blocks, with the
shortest text that reads back to the same float64 (Python's ``repr``) and runs
of bit-identical values as ``n*v``, at most ``VALUES_PER_LINE`` values and
``MAX_LINE`` characters a line; :func:`text_table` is its table of the text of
each distinct value (fixed-width NUL-padded rows), formatted a block of values
at a time, so that neither the values' text nor the array's is ever one string.
"""

from __future__ import annotations

import csv
import io
import re
from collections.abc import Container, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError

_BLANK = re.compile(rb"(?:[\s,]+|--[^\n]*)*")
KEYWORD_NAME = re.compile(rb"[A-Za-z][A-Za-z0-9_+\-]*")  # a valid keyword name
_LINE_TOKEN = re.compile(rb"(?:[^\s,\-]|-(?!-))+")  # the first word of a line, up to a blank, ',' or '--'
_REST_OF_LINE_EMPTY = re.compile(rb"[ \t\r,]*(?:--[^\n]*)?(?:\n|$)")
# A record's tokens: a comment, a quoted string, the '/', a word (ends at a blank, ',', quote, '/'
# or '--'), separators, or an unpaired quote.
_TOKEN = re.compile(rb"(--[^\n]*)|'([^'\n]*)'|(/)|((?:[^\s,/'\-]|-(?!-))+)|([\s,]+)|(')")
_NUMBER = re.compile(rb"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?|[+-]?(?:nan|inf|NaN|Inf|NAN|INF)")
_REPEAT = re.compile(rb"(\d+)\*(.*)")
MAX_KEYWORD_LENGTH = 8
_MAX_RECORD_REPEAT = 10_000  # n* in a record (a few items) beyond this is a typo


class DeckError(InputError):
    """A keyword file is invalid; the message names the file, line and keyword."""


@dataclass
class Source:
    """The bytes of one file, with line numbers for messages.

    ``keywords``: the names that start a keyword; a record whose first item is one of them,
    alone on its line, is a keyword written where the previous keyword's '/' is missing.
    """

    path: Path
    data: bytes
    keywords: Container[str] = frozenset()
    _line_pos: int = 0
    _line_no: int = 1

    @classmethod
    def open(cls, path: Path, keywords: Container[str] = frozenset()) -> Source:
        return cls(path, path.read_bytes(), keywords)

    def line(self, pos: int) -> int:
        """1-based line number of byte ``pos`` (incremental: cheap when positions grow)."""
        if pos < self._line_pos:
            self._line_pos, self._line_no = 0, 1
        self._line_no += self.data.count(b"\n", self._line_pos, pos)
        self._line_pos = pos
        return self._line_no

    def error(self, pos: int, keyword: str | None, message: str) -> DeckError:
        where = f"{self.path}:{self.line(pos)}"
        return DeckError(f"{where}: {keyword}: {message}" if keyword else f"{where}: {message}")


def show(token: bytes, limit: int = 40) -> str:
    """A token as text for a message, safe for binary junk."""
    text = token[:limit].decode("latin-1")
    text = "".join(ch if ch.isprintable() and ord(ch) < 127 else f"\\x{ord(ch):02x}" for ch in text)
    return "'" + text.replace("'", "\\'") + ("..." if len(token) > limit else "") + "'"


def skip_blank(data: bytes, pos: int) -> int:
    """Position of the next byte that is neither whitespace, ',' nor comment."""
    return _BLANK.match(data, pos).end()


def next_line(data: bytes, pos: int) -> int:
    """Position of the start of the line after the one holding ``pos`` (or the end of the data)."""
    end = data.find(b"\n", pos)
    return len(data) if end < 0 else end + 1


def line_word(data: bytes, pos: int) -> bytes | None:
    """The first word of the next line that is not blank or comment (None at the end)."""
    pos = skip_blank(data, pos)
    if pos >= len(data):
        return None
    m = _LINE_TOKEN.match(data, pos)
    return m.group() if m else data[pos : pos + 1]


@dataclass(frozen=True)
class KeywordLine:
    """A keyword's line: its name (upper case), where it starts, and where its data start: at
    the end of its line (the rest of a keyword's line is ignored, as ECLIPSE and OPM Flow do;
    the data are on the lines below, and messages about them name the keyword's line)."""

    name: str
    at: int
    data_start: int
    ignored: bytes  # text after the name on its line (comments removed)


def read_keyword(src: Source, pos: int) -> KeywordLine | None:
    """The keyword of the next line that is not blank or comment; None at the end of the file.

    The keyword is the line's first word; it must be a valid keyword name (a letter, then
    letters, digits, ``_``, ``-``, ``+``), otherwise an error names the line and the word. A
    ``/`` alone where a keyword is expected is returned as the name ``"/"`` (OPM Flow ignores it).
    """
    data = src.data
    at = skip_blank(data, pos)
    if at >= len(data):
        return None
    m = _LINE_TOKEN.match(data, at)
    word = m.group() if m else data[at : at + 1]
    if not KEYWORD_NAME.fullmatch(word) and word != b"/":
        hint = " (stray data or a missing '/')" if re.match(rb"[\d+\-.*']", word) else ""
        raise src.error(at, None, f"expected a keyword, found {show(word)}{hint}")
    end = data.find(b"\n", at)
    end = len(data) if end < 0 else end
    rest = re.sub(rb"--[^\n]*", b"", data[at + len(word) : end]).strip(b" \t\r,")
    return KeywordLine(word.decode("ascii").upper(), at, end, rest)


# --- records -----------------------------------------------------------------------------

Item = str | None  # a value as written (quotes removed), or None where defaulted


def read_record(src: Source, pos: int, keyword: str) -> tuple[list[Item], int, int]:
    """One record: its items, the position after its line's end, and where it started.

    A record runs over lines up to its ``/``; the rest of the line after the ``/`` is ignored
    (a comment, as in ECLIPSE and OPM Flow: a second record on the same line is not read).
    Items are separated by blanks or commas; ``'...'`` quotes a string (blanks, ``/`` and
    ``--`` inside it are kept); ``n*`` expands to n defaulted items and ``n*v`` to n copies of v;
    a lone ``*`` is one defaulted item.
    """
    data = src.data
    items: list[Item] = []
    start = skip_blank(data, pos)
    while True:
        m = _TOKEN.match(data, pos)
        if m is None:  # end of the file
            raise src.error(start, keyword, "the data has no terminating '/'")
        pos = m.end()
        _comment, quoted, slash, word, _space, stray_quote = m.groups()
        if slash:
            return items, next_line(data, pos), start
        if stray_quote:
            raise src.error(m.start(), keyword, "a quoted string is not closed on its line")
        if quoted is not None:
            items.append(quoted.decode("latin-1").strip())
        elif word is not None:
            rep = _REPEAT.fullmatch(word)
            if word == b"*":  # a lone '*' is one defaulted item, as '1*' (OPM Flow reads it so)
                items.append(None)
            elif rep:
                n = int(rep.group(1))
                if n < 1 or n > _MAX_RECORD_REPEAT:
                    raise src.error(m.start(), keyword, f"repeat count {n} in {show(word)} is out of range")
                value = rep.group(2)
                items.extend([value.decode("latin-1").strip("'") if value else None] * n)
            else:
                if not items and word.decode("latin-1").upper() in src.keywords:
                    # A keyword alone on its line where data should be: the previous keyword lacks its '/'.
                    line_start = data.rfind(b"\n", 0, m.start()) + 1
                    if not data[line_start : m.start()].strip() and _REST_OF_LINE_EMPTY.match(data, m.end()):
                        raise src.error(
                            m.start(), keyword, f"found keyword {show(word)} before the '/' ending the data"
                        )
                items.append(word.decode("latin-1"))


def int_item(src: Source, at: int, keyword: str, value: Item, what: str) -> int | None:
    """The integer of a record's item (None where defaulted); an error names ``what`` otherwise.

    >>> src = Source(Path("deck.grdecl"), b"BOX\\n 1 x /\\n")
    >>> int_item(src, 4, "BOX", "3", "box"), int_item(src, 4, "BOX", None, "box")
    (3, None)
    """
    if value is None:
        return None
    try:
        return int(value)
    except ValueError:
        raise src.error(at, keyword, f"{what}: {value!r} is not an integer") from None


def float_item(src: Source, at: int, keyword: str, value: Item, what: str) -> float | None:
    """The number of a record's item (Fortran ``D`` exponents too; None where defaulted).

    >>> float_item(Source(Path("deck.grdecl"), b""), 0, "MINPV", "1.5D3", "minimum pore volume")
    1500.0
    """
    if value is None:
        return None
    try:
        return float(value.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise src.error(at, keyword, f"{what}: {value!r} is not a number") from None


def read_records(src: Source, pos: int, keyword: str) -> tuple[list[tuple[list[Item], int]], int]:
    """Records up to the empty record that ends a multi-record keyword; with their start positions."""
    records = []
    while True:
        items, pos, start = read_record(src, pos, keyword)
        if not items:
            return records, pos
        records.append((items, start))


def skip_array(src: Source, pos: int, keyword: str) -> int:
    """The position after the data of an array keyword (one record of values) without reading it."""
    return next_line(src.data, _data_end(src, pos, keyword))


# --- bulk numbers ----------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Numbers:
    """Numeric data of one keyword: values (NaN where defaulted) and the defaulted mask."""

    values: np.ndarray
    defaulted: np.ndarray | None  # None when nothing is defaulted


def _data_end(src: Source, pos: int, keyword: str) -> int:
    """Position of the '/' that ends the numeric data starting at ``pos`` (not in a comment)."""
    data = src.data
    search = pos
    while True:
        slash = data.find(b"/", search)
        if slash < 0:
            raise src.error(pos, keyword, "the data has no terminating '/'")
        line_start = data.rfind(b"\n", 0, slash) + 1
        comment = data.find(b"--", max(line_start, pos), slash)
        if comment < 0:
            return slash
        nl = data.find(b"\n", slash)
        if nl < 0:
            raise src.error(pos, keyword, "the data has no terminating '/'")
        search = nl


def read_numbers(
    src: Source, pos: int, keyword: str, expected: int | None = None, at_most: int | None = None
) -> tuple[Numbers, int]:
    """All numbers up to the next ``/``, and the position of the line after it (the rest of the
    ``/``'s line is ignored).

    ``expected`` (exact) and ``at_most`` counts are checked before repeat
    counts are expanded, so ``10000000000*1`` fails cleanly.
    """
    end = _data_end(src, pos, keyword)
    text = src.data[pos:end]
    if b"--" in text:
        text = re.sub(rb"--[^\n]*", b"", text)
    try:
        numbers = _fast_numbers(text, expected, at_most)
    except _CountMismatch as exc:
        wanted = f"expected {expected}" if expected is not None else f"at most {at_most} are allowed here"
        raise src.error(pos, keyword, f"has {exc.total:.0f} values, {wanted}") from None
    except (ValueError, pd.errors.ParserError):
        numbers = None
    if numbers is None:
        numbers = _slow_numbers(src, pos, end, keyword, expected if expected is not None else at_most)
    if expected is not None and numbers.values.size != expected:
        raise src.error(pos, keyword, f"has {numbers.values.size} values, expected {expected}")
    if at_most is not None and numbers.values.size > at_most:
        raise src.error(pos, keyword, f"has {numbers.values.size} values, at most {at_most} are allowed here")
    return numbers, next_line(src.data, end)


class _CountMismatch(Exception):
    def __init__(self, total: float) -> None:
        self.total = total


_PARSE_BLOCK = 1 << 24  # bytes of text parsed at a time: the C reader's tables stay small


def _fast_numbers(text: bytes, expected: int | None, at_most: int | None) -> Numbers | None:
    """Parse with pandas' C reader, a block of ``_PARSE_BLOCK`` bytes at a time (cut between
    tokens); None when something needs the careful path."""
    if len(text) <= _PARSE_BLOCK:
        return _fast_block(text, expected, at_most)
    cap = expected if expected is not None else at_most
    parts: list[Numbers] = []
    start = 0
    while start < len(text):
        stop = min(start + _PARSE_BLOCK, len(text))
        while stop < len(text) and not text[stop : stop + 1].isspace():
            stop += 1
        try:
            part = _fast_block(text[start:stop], None, cap)  # no block may hold more than all
        except _CountMismatch:
            return _fast_block(text, expected, at_most)  # the whole text: the exact count in the message
        if part is None:
            return None
        parts.append(part)
        start = stop
    values = np.concatenate([p.values for p in parts])
    if expected is not None and values.size != expected:
        raise _CountMismatch(values.size)
    defaulted = None
    if any(p.defaulted is not None for p in parts):
        defaulted = np.concatenate(
            [p.defaulted if p.defaulted is not None else np.zeros(p.values.size, bool) for p in parts]
        )
    return Numbers(values, defaulted)


def _fast_block(text: bytes, expected: int | None, at_most: int | None) -> Numbers | None:
    """One piece of :func:`_fast_numbers`."""
    for ch in (b"\t", b"\r", b"\f", b"\v", b","):
        if ch in text:
            text = text.replace(ch, b" ")
    text = text.replace(b" ", b"\n")
    if b"*" in text:
        return _repeated_numbers(text, expected, at_most)
    if not text.strip():
        return Numbers(np.zeros(0), None)
    values = pd.read_csv(
        io.BytesIO(text),
        header=None,
        names=["a"],
        dtype=np.float64,
        engine="c",
        na_filter=False,
        quoting=csv.QUOTE_NONE,
    )["a"].to_numpy()
    return Numbers(np.ascontiguousarray(values), None)


def _repeated_numbers(text: bytes, expected: int | None, at_most: int | None) -> Numbers | None:
    """Tokens one per line, some of them ``n*v`` (or ``n*``, n defaulted values)."""
    csv_options = dict(
        header=None,
        dtype=np.float64,
        engine="c",
        keep_default_na=False,
        na_values=[""],
        quoting=csv.QUOTE_NONE,
    )
    if b"*\n" in text or text.endswith(b"*"):
        # Defaulted values: "n*v" -> "n,1,v" (count, flag, value); "n*" -> "n,1,"; "v" -> "v".
        table = pd.read_csv(io.BytesIO(text.replace(b"*", b",1,")), names=["a", "flag", "b"], **csv_options)
        a, flag, b = (table[c].to_numpy() for c in ("a", "flag", "b"))
        rep = flag == 1
        if np.any(np.isnan(flag) != ~rep):
            return None  # a stray ',' somewhere
    else:  # "n*v" -> (n, v); "v" -> (v, NaN)
        table = pd.read_csv(io.BytesIO(text), names=["a", "b"], sep="*", **csv_options)
        a, b = table["a"].to_numpy(), table["b"].to_numpy()
        rep = ~np.isnan(b)
    if np.isnan(a).any():
        return None  # an empty count or value ("*5", ",")
    counts = np.where(rep, a, 1.0)
    if np.any(counts < 1) or np.any(counts != np.floor(counts)):
        return None
    total = float(counts.sum())
    if (expected is not None and total != expected) or (at_most is not None and total > at_most):
        raise _CountMismatch(total)  # before np.repeat: "1e12*0" must not allocate
    counts = counts.astype(np.int64)
    values = np.where(rep, b, a)
    defaulted = rep & np.isnan(b)
    out = np.repeat(values, counts)
    return Numbers(out, np.repeat(defaulted, counts) if defaulted.any() else None)


def _slow_numbers(src: Source, pos: int, end: int, keyword: str, limit: int | None) -> Numbers:
    """Token by token: exact messages (line, token) for what the fast path refused."""
    data = src.data
    values: list[float] = []
    counts: list[int] = []
    defaulted: list[bool] = []
    total = 0
    for m in re.finditer(rb"--[^\n]*|[^\s,]+", data[pos:end]):
        token = m.group()
        if token.startswith(b"--"):
            continue
        at = pos + m.start()
        rep = _REPEAT.fullmatch(token)
        n, value = (int(rep.group(1)), rep.group(2)) if rep else (1, token)
        if n < 1:
            raise src.error(at, keyword, f"repeat count in {show(token)} must be positive")
        if value == b"":
            values.append(np.nan)
            defaulted.append(True)
        elif _NUMBER.fullmatch(value):
            values.append(float(value.replace(b"d", b"e").replace(b"D", b"e")))
            defaulted.append(False)
        else:
            hint = ""
            if KEYWORD_NAME.fullmatch(value) and len(value) <= MAX_KEYWORD_LENGTH:
                hint = f" (is the '/' ending {keyword} missing before keyword {show(value)}?)"
            raise src.error(at, keyword, f"{show(token)} is not a number{hint}")
        counts.append(n)
        total += n
        if limit is not None and total > limit:
            raise src.error(at, keyword, f"has more than the {limit} values expected")
    c = np.array(counts, dtype=np.int64)
    d = np.array(defaulted, dtype=bool)
    out = np.repeat(np.array(values, dtype=np.float64), c)
    return Numbers(out, np.repeat(d, c) if d.any() else None)


# --------------------------------------------------------------------------- writing

VALUES_PER_LINE = 6
MAX_LINE = 131  # ECLIPSE reads 132 characters a line; stay below
_CHUNK_RUNS = 1 << 16  # runs formatted per block: a few MiB of scratch, whatever the array size
_TABLE_BLOCK = 1 << 16  # distinct values formatted per block (a bounded string at a time)
_DIRECT_COUNTS = 1 << 16  # runs up to this long index the prefix table by their length
_SPACE, _NEWLINE = ord(" "), ord("\n")


def text_table(values: list, integer: bool) -> np.ndarray:
    """Fixed-width ASCII table (one row per value, NUL-padded) of ``repr`` (or ``%d``) of each value.

    ``repr`` of a float is the shortest text that reads back to the same
    float64. One ``%`` formatting of all values, then a vectorised split,
    costs less than a Python string per value.
    """
    if not values:
        return np.zeros((0, 1), np.uint8)
    text = np.frombuffer(
        (("%d\n" if integer else "%r\n") * len(values) % tuple(values)).encode("ascii"), np.uint8
    )
    ends = np.flatnonzero(text == _NEWLINE)
    lengths = np.diff(ends, prepend=-1) - 1
    table = np.zeros((len(values), int(lengths.max())), np.uint8)
    table[np.arange(table.shape[1]) < lengths[:, None]] = text[text != _NEWLINE]
    return table


def _value_table(distinct: np.ndarray, integer: bool) -> np.ndarray:
    """:func:`text_table` of ``distinct``, formatted ``_TABLE_BLOCK`` values at a time (the same rows:
    each block's rows are NUL-padded to the widest text of all)."""
    blocks = [
        text_table(distinct[lo : lo + _TABLE_BLOCK].tolist(), integer)
        for lo in range(0, distinct.size, _TABLE_BLOCK)
    ]
    if len(blocks) == 1:
        return blocks[0]
    table = np.zeros((distinct.size, max(b.shape[1] for b in blocks)), np.uint8)
    for i, b in enumerate(blocks):
        table[i * _TABLE_BLOCK : i * _TABLE_BLOCK + b.shape[0], : b.shape[1]] = b
    return table


def format_values(values: np.ndarray, integer: bool = False, undefined: bool = False) -> Iterator[bytes]:
    """Round-trip exact ASCII text of an array, in blocks: runs of equal values as ``n*v``.

    Runs are of bit-identical values (so ``-0.0`` next to ``0.0`` stays itself; with ``integer``
    they are equal values), and a NaN is never repeated; with ``undefined``, NaN is a value the
    array leaves undefined and a run of them is written defaulted, ``n*`` (``1*`` for one), which
    leaves them undefined when read (by OPM Flow, ECLIPSE and ``read_grdecl``). Each distinct value
    and each distinct repeat count is formatted once; the tokens are gathered from those tables as
    fixed-width byte rows, with a space or line break after each, and the NUL padding dropped. At
    most ``VALUES_PER_LINE`` tokens go on a line, fewer when the longest token would make a line
    longer than ``MAX_LINE``. The text ends with a line break.
    """
    v = np.ascontiguousarray(values).ravel()
    if v.size == 0:
        yield b"\n"
        return
    floating = v.dtype.kind == "f"
    undefined = undefined and floating and bool(np.isnan(v).any())
    if floating:
        v = v.astype(np.float64, copy=False)
        if undefined:
            v = np.where(np.isnan(v), np.nan, v)  # one NaN bit pattern: one run per stretch
        key = (v + 0.0 if integer else v).view(np.uint64)  # integer: -0.0 is 0
    else:
        key = v.astype(np.int64, copy=False)
    same = key[1:] == key[:-1]
    if floating and not integer and not undefined:
        same &= ~np.isnan(v[1:])  # the reader does not take "n*nan"
    starts = np.flatnonzero(np.concatenate([[True], ~same]))
    counts = np.diff(starts, append=v.size)
    codes, distinct = pd.factorize(key[starts], sort=False)
    distinct = np.asarray(distinct)
    shown = distinct.view(np.float64) if floating else distinct
    if undefined:
        shown = np.where(np.isnan(shown), 0.0, shown)  # a placeholder: NaN runs have no value text
    value_table = _value_table(shown, integer)
    if counts.max() <= _DIRECT_COUNTS:  # the usual case: a prefix for every count up to the longest run
        count_codes, distinct_counts = counts, range(int(counts.max()) + 1)
    else:
        count_codes, distinct_counts = pd.factorize(counts, sort=False)
    prefixes = [f"{n}*" if n > 1 else "" for n in list(distinct_counts)]
    if undefined:  # NaN runs: "n*" and an empty value, whatever n
        count_codes = np.where(np.isnan(v[starts]), count_codes + len(prefixes), count_codes)
        prefixes += [f"{n}*" for n in list(distinct_counts)]
        value_table[np.isnan(distinct.view(np.float64))] = 0
    width = max(1, *map(len, prefixes))
    prefix_table = np.array(prefixes, dtype=f"S{width}").view(np.uint8).reshape(len(prefixes), width)
    widest = int(((prefix_table != 0).sum(1)[count_codes] + (value_table != 0).sum(1)[codes]).max())
    per_line = max(1, min(VALUES_PER_LINE, (MAX_LINE + 1) // (widest + 1)))
    wp, wv = prefix_table.shape[1], value_table.shape[1]
    chunk = _CHUNK_RUNS - _CHUNK_RUNS % per_line  # whole lines per block
    block = np.empty((chunk, wp + wv + 1), np.uint8)
    for lo in range(0, starts.size, chunk):
        hi = min(lo + chunk, starts.size)
        rows = block[: hi - lo]
        # The codes are in range; mode="clip" lets take write into the strided columns unbuffered.
        np.take(prefix_table, count_codes[lo:hi], axis=0, out=rows[:, :wp], mode="clip")
        np.take(value_table, codes[lo:hi], axis=0, out=rows[:, wp:-1], mode="clip")
        rows[:, -1] = _SPACE
        rows[per_line - 1 :: per_line, -1] = _NEWLINE
        if hi == starts.size:
            rows[-1, -1] = _NEWLINE
        yield rows[rows != 0].tobytes()


def keyword_text(
    name: str, values: np.ndarray, comment: str = "", integer: bool = False, undefined: bool = False
) -> Iterator[bytes]:
    """A keyword with an array, in blocks: the keyword's line, an optional ``--`` comment line,
    :func:`format_values` of ``values`` (``undefined``: NaN written ``n*``) and the ``/`` ending it,
    then a blank line.

    >>> b"".join(keyword_text("PORO", np.array([0.2, 0.2, 0.25]), "fraction"))
    b'PORO\\n-- fraction\\n2*0.2 0.25\\n/\\n\\n'
    """
    yield (f"{name}\n" + (f"-- {comment}\n" if comment else "")).encode("ascii")
    yield from format_values(values, integer, undefined)
    yield b"/\n\n"
