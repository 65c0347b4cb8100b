"""Files read once per run of a case's stages: inside :func:`shared_reads` (what
:func:`gridlib.stages.run_case` runs its stages in), a reader wrapped by :func:`read_once`
reads a file that it read before, unchanged since, from memory instead of from disk.

Every stage of a small case reads ``grid.nc`` again (geometry, petrophysics, transmissibility,
quality, export, the deck and the pictures: 7 reads of about 30 ms for a 5,000-cell PEBI grid,
more than some of those stages' own work). A file is the same when its path, device, inode,
size and modification time are: gridlib replaces an artifact by renaming a new file over it
(:mod:`gridlib.io.atomic`), which gives it a new inode, so a rewritten file is read again.
Outside :func:`shared_reads` (the workflow's per-stage jobs, the library's users) every call
reads the file.
"""

from __future__ import annotations

import contextlib
import functools
import os
from collections.abc import Callable, Iterator
from contextvars import ContextVar
from typing import Any, TypeVar

import numpy as np

_Result = TypeVar("_Result")

_cache: ContextVar[dict[tuple[Any, ...], Any] | None] = ContextVar("gridlib_shared_reads", default=None)


@contextlib.contextmanager
def shared_reads() -> Iterator[None]:
    """Within the block, the readers of :func:`read_once` read each unchanged file once (in
    this thread); what they read is let go at its end."""
    token = _cache.set({})
    try:
        yield
    finally:
        _cache.reset(token)


def read_once(
    private: Callable[[_Result], _Result],
) -> Callable[[Callable[[str | os.PathLike], _Result]], Callable[[str | os.PathLike], _Result]]:
    """A decorator of a reader ``read(path)``: inside :func:`shared_reads` its result is kept
    per file and each caller gets ``private(result)``, a copy of whatever in it a caller may
    change (the read-only arrays of a grid are shared)."""

    def wrap(read: Callable[[str | os.PathLike], _Result]) -> Callable[[str | os.PathLike], _Result]:
        @functools.wraps(read)
        def reader(path: str | os.PathLike) -> _Result:
            cache = _cache.get()
            if cache is None:
                return read(path)
            try:
                st = os.stat(path)
            except OSError:
                return read(path)  # the reader's own error names the file
            key = (read.__module__, read.__qualname__, os.path.abspath(path), st.st_dev, st.st_ino)
            key += (st.st_size, st.st_mtime_ns)
            if key not in cache:
                cache[key] = read(path)
            return private(cache[key])

        return reader

    return wrap


def shared(result: _Result) -> _Result:
    """The ``private`` of a reader whose result no caller can change (read-only arrays in a
    frozen dataclass)."""
    return result


def own_arrays(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The ``private`` of a reader of arrays by name: a copy of each."""
    return {name: values.copy() for name, values in arrays.items()}
