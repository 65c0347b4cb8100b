"""Cells named the way a user finds them: ``(i, j, k)``, 1-based, as ECLIPSE and OPM Flow print
them, for cells with a logical index (``index_map`` in ``cart_dims``); the 0-based cell number
otherwise."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

MAX_NAMED = 5  # cells named in a message; the rest are counted


def ijk(linear: ArrayLike, cart_dims: Sequence[int]) -> np.ndarray:
    """1-based logical indices (n, len(cart_dims)) of linear indices (0-based, i fastest).

    >>> ijk([0, 5, 13], (2, 3, 4)).tolist()
    [[1, 1, 1], [2, 3, 1], [2, 1, 3]]
    """
    g = np.asarray(linear, dtype=np.int64).ravel()
    return np.column_stack(np.unravel_index(g, tuple(cart_dims)[::-1], order="C")[::-1]) + 1


def ijk_text(linear: int, cart_dims: Sequence[int]) -> str:
    """'(i, j, k)', 1-based, of one linear cell index (0-based, i fastest), as messages name cells.

    >>> ijk_text(13, (2, 3, 4))
    '(2, 1, 3)'
    """
    return "(" + ", ".join(str(int(v)) for v in ijk([linear], cart_dims)[0]) + ")"


def cell_names(
    cells: ArrayLike,
    index_map: ArrayLike | None = None,
    cart_dims: Sequence[int] | None = None,
    limit: int = MAX_NAMED,
) -> str:
    """The first ``limit`` of ``cells`` (0-based cell numbers) named, the rest counted: ``(i, j, k)``
    where ``index_map`` and ``cart_dims`` are given, else the numbers themselves.

    >>> cell_names([0, 1, 2], index_map=[7, 8, 9], cart_dims=(4, 2, 2), limit=2)
    '(4, 2, 1), (1, 1, 2) and 1 more'
    >>> cell_names([3])
    'cell 3'
    """
    c = np.asarray(cells, dtype=np.int64).ravel()
    shown = c[:limit]
    if index_map is not None and cart_dims is not None:
        rows = ijk(np.asarray(index_map, dtype=np.int64)[shown], cart_dims)
        text = ", ".join("(" + ", ".join(str(int(v)) for v in row) + ")" for row in rows)
    else:
        text = ("cell " if c.size == 1 else "cells ") + ", ".join(str(int(v)) for v in shown)
    return text + (f" and {c.size - limit} more" if c.size > limit else "")
