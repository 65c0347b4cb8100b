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

The readers not wrapped (those of a few variables of a file, a file's length) still open the
file: :func:`kept_open` keeps a small file's handle open for the rest of the block, so that
each file is opened (and its digest verified) once per run of a case's stages: 6 openings
instead of 19 for a 5,000-cell PEBI variant, about 2.4 ms each.
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
_Handle = TypeVar("_Handle")

_cache: ContextVar[dict[tuple[Any, ...], Any] | None] = ContextVar("gridlib_shared_reads", default=None)
_closers: ContextVar[list[Callable[[], None]] | None] = ContextVar("gridlib_shared_closers", default=None)


@contextlib.contextmanager
def shared_reads() -> Iterator[None]:
    """Within the block, the readers of :func:`read_once` read each unchanged file once (in
    this thread); what they read is let go at its end, and the handles of :func:`kept_open`
    are closed."""
    closers: list[Callable[[], None]] = []
    token, closers_token = _cache.set({}), _closers.set(closers)
    try:
        yield
    finally:
        _closers.reset(closers_token)
        _cache.reset(token)
        for close in reversed(closers):
            close()


def _file_key(path: str | os.PathLike) -> tuple[Any, ...] | None:
    """What identifies the file at ``path`` as unchanged: its path, device, inode, size and
    modification time (None where it cannot be read)."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return (os.path.abspath(path), st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def kept_open(
    path: str | os.PathLike,
    open_file: Callable[[str | os.PathLike], _Handle],
    close: Callable[[_Handle], None],
    max_bytes: int,
) -> _Handle | None:
    """Inside :func:`shared_reads`: the handle ``open_file(path)`` of the unchanged file
    ``path``, opened on the first call and kept open until the block ends (then ``close``-d),
    for files of at most ``max_bytes`` (a handle keeps its library's caches); None outside the
    block or for a larger file (the caller opens it itself). A caller must leave the handle
    as it found it (e.g. read from a shallow copy)."""
    cache = _cache.get()
    key = _file_key(path)
    if cache is None or key is None or key[3] > max_bytes:
        return None
    key = ("kept_open", open_file.__module__, open_file.__qualname__, *key)
    if key not in cache:
        handle = open_file(path)
        cache[key] = handle
        closers = _closers.get()
        assert closers is not None  # set with the cache
        closers.append(lambda: close(handle))
    return cache[key]


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
            key = _file_key(path)
            if key is None:
                return read(path)  # the reader's own error names the file
            key = (read.__module__, read.__qualname__, *key)
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
