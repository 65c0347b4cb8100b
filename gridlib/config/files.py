"""Files a case names: where they are, and what a deck gives, read as cheaply as possible."""

from __future__ import annotations

import functools
import os
from pathlib import Path


def named_file(case_file: Path, name: str | os.PathLike) -> Path:
    """A file a case names: ``name`` relative to the case file's folder (or absolute), its ``..``
    resolved by the path's text, not by the file system: a study's variant is checked before its
    folder results/<study>/<variant>/ exists, and names its base case's files from there.

    >>> named_file(Path("results/sweep/fine_r0/fine_r0.yaml"), "../../../config/cases/top.csv").as_posix()
    'config/cases/top.csv'
    """
    return Path(os.path.normpath(Path(case_file).parent / name))


def deck_cell_keywords(path: Path, unknown_keywords: str = "error") -> frozenset[str]:
    """The cell keywords (PORO, PERMX, MULTZ, ...) the deck file ``path`` gives; a text deck is
    read with ``unknown_keywords`` (a deck case's ``grid.unknown_keywords``)."""
    p = path.resolve()
    stat = p.stat()
    return _deck_cell_keywords(p, stat.st_mtime_ns, stat.st_size, unknown_keywords)


@functools.lru_cache(maxsize=8)
def _deck_cell_keywords(path: Path, mtime_ns: int, size: int, unknown_keywords: str) -> frozenset[str]:
    # Cached per process on the file's identity: every stage and every variant of a study loads
    # the case again. (An INCLUDEd file edited in the same process is not seen: runs are new
    # processes.)
    from ..io.registry import find_format, read  # deferred: the workflow's parse imports config only

    options = {"unknown_keywords": unknown_keywords} if find_format(path, "deck").name == "grdecl" else {}
    return frozenset(read(path, kind="deck", **options).cell_data)
