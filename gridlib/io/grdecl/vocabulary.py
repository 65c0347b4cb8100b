"""The ECLIPSE / OPM Flow keywords: each keyword's sections and the shape of its data
(:class:`Shape`), read from ``vocabulary.txt`` (derived from OPM opm-common 2022.10's keyword
definitions by :mod:`~gridlib.io.grdecl.make_vocabulary`; its header explains the codes).

The deck reader uses it to skip exactly the keywords it does not use (by their shape, not by
how their lines look) and to tell a keyword ECLIPSE and Flow know from a misspelt one.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from importlib import resources

__all__ = ["SECTION_NAMES", "KeywordInfo", "Shape", "Vocabulary", "vocabulary"]

SECTION_NAMES = {
    "R": "RUNSPEC",
    "G": "GRID",
    "E": "EDIT",
    "P": "PROPS",
    "N": "REGIONS",
    "S": "SOLUTION",
    "U": "SUMMARY",
    "H": "SCHEDULE",
    "X": "SPECIAL",
}


@dataclass(frozen=True)
class Shape:
    """How a keyword's data end.

    ``kind``: ``none`` (no data), ``data`` (one record of values), ``records`` (``count``
    records; after ``min_count`` of them a keyword on the next line ends it), ``list`` (records
    up to an empty record), ``sized`` (``count_from`` gives the number of records), ``tables``
    (``count_from`` tables, each ended by an empty record), ``open`` (records up to a line that
    starts with a keyword), ``sets`` (records up to two empty records in a row) or ``code`` (raw
    text up to the word ``end``).
    """

    kind: str
    count: int = 0
    min_count: int | None = None
    count_from: tuple[str, int, int | None, int, int] | None = None  # keyword, item, default, shift, factor
    end: str | None = None

    @classmethod
    def parse(cls, code: str) -> Shape:
        """>>> Shape.parse("sized:TABDIMS:1:1:0:1").count_from
        ('TABDIMS', 1, 1, 0, 1)
        """
        kind, *args = code.split(":")
        if kind == "records":
            return cls(kind, int(args[0]), int(args[1]) if len(args) > 1 else None)
        if kind in ("sized", "tables"):
            keyword, item, default, *rest = args
            shift, factor = (int(rest[0]), int(rest[1])) if rest else (0, 1)
            count_default = None if default == "-" else int(default)
            return cls(kind, count_from=(keyword, int(item), count_default, shift, factor))
        if kind == "code":
            return cls(kind, end=args[0])
        return cls(kind)


@dataclass(frozen=True)
class KeywordInfo:
    """One keyword: its deck name, the shape of its data and the sections it may appear in."""

    name: str
    shape: Shape
    sections: frozenset[str]


@dataclass(frozen=True)
class Vocabulary:
    """Keywords by deck name, and the name patterns (e.g. ``TVDP.+``) of families of keywords."""

    names: dict[str, KeywordInfo]
    patterns: tuple[tuple[re.Pattern[str], KeywordInfo], ...]

    def get(self, name: str) -> KeywordInfo | None:
        """The keyword ``name`` (upper case), or None if neither ECLIPSE nor OPM Flow knows it.

        >>> vocabulary().get("GDORIENT").shape
        Shape(kind='records', count=1, min_count=None, count_from=None, end=None)
        >>> vocabulary().get("TVDPSALT").name, vocabulary().get("ACTNUMX")
        ('TVDPSALT', None)
        """
        info = self.names.get(name)
        if info is not None:
            return info
        for pattern, info in self.patterns:
            if pattern.fullmatch(name):
                return KeywordInfo(name, info.shape, info.sections)
        return None

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and self.get(name) is not None


@cache
def vocabulary() -> Vocabulary:
    """The vocabulary shipped with gridlib (``gridlib/io/grdecl/vocabulary.txt``)."""
    text = resources.files(__package__).joinpath("vocabulary.txt").read_text(encoding="ascii")
    names: dict[str, KeywordInfo] = {}
    patterns = []
    for line in text.splitlines():
        if not line or line.startswith("#"):
            continue
        name, code, letters = line.split()
        sections = frozenset(SECTION_NAMES[c] for c in letters)
        if name.startswith("~"):
            info = KeywordInfo(name[1:], Shape.parse(code), sections)
            patterns.append((re.compile(name[1:]), info))
        else:
            names[name] = KeywordInfo(name, Shape.parse(code), sections)
    return Vocabulary(names, tuple(patterns))
