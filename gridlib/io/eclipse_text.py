"""Lexing ECLIPSE keyword files: keywords, ``/``-terminated records, bulk numbers.

The syntax (ECLIPSE reference manual, "data file overview"):

* a keyword (1-8 characters, starting with a letter) opens a block of data;
* data are records ended by ``/``; multi-record keywords end with an empty
  record (a ``/`` alone);
* ``--`` starts a comment that runs to the end of the line;
* ``n*v`` is n copies of v, ``n*`` is n defaulted values;
* strings may be quoted with ``'``; a quoted string may contain ``/``.

Bulk numeric data (COORD, ZCORN, cell arrays: millions of numbers) take a fast
path with no Python loop per number: the text up to the ``/`` is cut out,
comments are dropped, whitespace becomes line breaks and pandas' C parser
turns it into float64 (correctly rounded: written values read back
bit-identical). Repeat counts become a second column. Anything the fast path
cannot read goes to a token-by-token path that reads what is valid (Fortran
``D`` exponents, ``nan``) and otherwise raises an error naming the file, the
line, the keyword and the offending token.
"""

from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError

_BLANK = re.compile(rb"(?:\s+|--[^\n]*)*")
_KEYWORD = re.compile(rb"[A-Za-z][A-Za-z0-9_+\-]*")
_REST_OF_LINE_EMPTY = re.compile(rb"[ \t\r]*(?:--[^\n]*)?(?:\n|$)")
_TOKEN = re.compile(rb"(--[^\n]*)|'([^'\n]*)'|(/)|([^\s/']+)|(\s+)|(')")
_NUMBER = re.compile(rb"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?|[+-]?(?:nan|inf|NaN|Inf|NAN|INF)")
_REPEAT = re.compile(rb"(\d+)\*(.*)")
MAX_KEYWORD_LENGTH = 8
_MAX_RECORD_REPEAT = 10_000  # n* in a record (a few items) beyond this is a typo


class DeckError(InputError):
    """A keyword file is invalid; the message names the file, line and keyword."""


@dataclass
class Source:
    """The bytes of one file, with line numbers for messages."""

    path: Path
    data: bytes
    _line_pos: int = 0
    _line_no: int = 1

    @classmethod
    def open(cls, path: Path) -> Source:
        return cls(path, path.read_bytes())

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
    """Position of the next byte that is neither whitespace nor comment."""
    return _BLANK.match(data, pos).end()


def read_keyword(src: Source, pos: int) -> tuple[str, int] | None:
    """The keyword at ``pos`` (after blanks) and the position after it; None at the end."""
    pos = skip_blank(src.data, pos)
    if pos >= len(src.data):
        return None
    m = _KEYWORD.match(src.data, pos)
    end = m.end() if m else pos
    if m is None or end - pos > MAX_KEYWORD_LENGTH or (end < len(src.data) and src.data[end] in b"'/*"):
        token = re.match(rb"\S*", src.data[pos : pos + 200]).group()
        raise src.error(pos, None, f"expected a keyword, found {show(token)} (stray data or a missing '/')")
    return m.group().decode("ascii").upper(), end


def looks_like_keyword_line(data: bytes, pos: int) -> bool:
    """Is the next item a bare word alone on its line (how keywords are written)?"""
    pos = skip_blank(data, pos)
    if pos >= len(data):
        return True
    m = _KEYWORD.match(data, pos)
    if m is None or m.end() - pos > MAX_KEYWORD_LENGTH:
        return False
    return _REST_OF_LINE_EMPTY.match(data, m.end()) is not None


# --- records -----------------------------------------------------------------------------

Item = str | None  # a value as written (quotes removed), or None where defaulted


def read_record(src: Source, pos: int, keyword: str) -> tuple[list[Item], int, int]:
    """One record: its items, the position after its ``/``, and where it started.

    A line break does not end a record; ``n*`` expands to n defaulted items and
    ``n*v`` to n copies of v.
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
            return items, pos, start
        if stray_quote:
            raise src.error(m.start(), keyword, "a quoted string is not closed on its line")
        if quoted is not None:
            items.append(quoted.decode("latin-1").strip())
        elif word is not None:
            rep = _REPEAT.fullmatch(word)
            if rep:
                n = int(rep.group(1))
                if n < 1 or n > _MAX_RECORD_REPEAT:
                    raise src.error(m.start(), keyword, f"repeat count {n} in {show(word)} is out of range")
                value = rep.group(2)
                items.extend([value.decode("latin-1").strip("'") if value else None] * n)
            else:
                if _KEYWORD.fullmatch(word) and len(word) <= MAX_KEYWORD_LENGTH and items == []:
                    # A keyword where data should be: the previous keyword lacks its '/'.
                    line_start = data.rfind(b"\n", 0, m.start()) + 1
                    if line_start == m.start() and _REST_OF_LINE_EMPTY.match(data, m.end()):
                        raise src.error(
                            m.start(), keyword, f"found keyword {show(word)} before the '/' ending the data"
                        )
                items.append(word.decode("latin-1"))


def read_records(src: Source, pos: int, keyword: str) -> tuple[list[tuple[list[Item], int]], int]:
    """Records up to the empty record that ends a multi-record keyword; with their start positions."""
    records = []
    while True:
        items, pos, start = read_record(src, pos, keyword)
        if not items:
            return records, pos
        records.append((items, start))


def skip_unknown(src: Source, pos: int, keyword: str) -> int:
    """Skip the data of a keyword we do not know: records until a keyword-like line."""
    while not looks_like_keyword_line(src.data, pos):
        items, pos, _ = read_record(src, pos, keyword)
        if not items:
            break
    return pos


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
    """All numbers up to the next ``/``, and the position after the ``/``.

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
    return numbers, end + 1


class _CountMismatch(Exception):
    def __init__(self, total: float) -> None:
        self.total = total


def _fast_numbers(text: bytes, expected: int | None, at_most: int | None) -> Numbers | None:
    """Parse with pandas' C reader; None when something needs the careful path."""
    for ch in (b"\t", b"\r", b"\f", b"\v"):
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
    for m in re.finditer(rb"--[^\n]*|[^\s]+", data[pos:end]):
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
            if _KEYWORD.fullmatch(value) and len(value) <= MAX_KEYWORD_LENGTH:
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
