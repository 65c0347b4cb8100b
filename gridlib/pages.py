"""Large temporaries on ordinary pages: :func:`without_huge_pages`.

numpy advises the kernel to back each array of 4 MiB or more with transparent huge pages
(``madvise``). Where the kernel's THP defrag setting is "madvise" (as on many Linux
machines), the first touch of such a page may first compact memory to find 2 MiB of
contiguous RAM, and on a host whose memory is fragmented (a large page cache, other busy
processes) that costs more than the huge page saves. Measured on the 2-core VM of
bench/transmissibility.py, in the bench's interpreter: the first ``deck_transmissibility``
of a 1e6-cell deck took 0.74-0.80 s of system time with numpy's advice and 0.18-0.23 s
without it (the same 0.39-0.40 s of user time), warm calls 0.05-0.4 s against 0.05-0.13 s.

Values never depend on this: it decides only how the kernel backs the pages.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

_lock = threading.Lock()
_depth = 0  # calls inside without_huge_pages, in any thread
_saved = True  # numpy's setting when the first of them entered


def _advice_setter():
    """numpy's switch of its huge-page advice (``_set_madvise_hugepage``: set, return the old
    value), or None where this numpy has none."""
    core = getattr(np, "_core", None) or getattr(np, "core", None)
    return getattr(getattr(core, "multiarray", None), "_set_madvise_hugepage", None)


@contextmanager
def without_huge_pages() -> Iterator[None]:
    """numpy's huge-page advice off while the block runs (in every thread: numpy has one
    switch), back to what it was when the last block running leaves."""
    global _depth, _saved
    setter = _advice_setter()
    if setter is None:
        yield
        return
    with _lock:
        if _depth == 0:
            _saved = bool(setter(False))
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                setter(_saved)
