"""How many threads gridlib's blocked numpy loops may use (geometry, random fields,
transmissibilities), and :func:`concurrently` to run independent steps on them.

numpy releases the GIL inside its loops and products, so gridlib runs independent
blocks of work on a few threads; every block writes its own rows, so results do
not depend on the number of threads. By default that number is the count of CPUs
this process may run on; ``GRIDLIB_NUM_THREADS`` (an integer >= 1) overrides it,
and the workflow sets it to each rule's ``threads`` so that Snakemake's core
accounting holds (``snakemake --set-threads geometry=2 petrophysics=2`` gives the
big stages of a large case two cores each).

>>> import os
>>> os.environ["GRIDLIB_NUM_THREADS"] = "3"
>>> num_threads(8), num_threads(2)
(3, 2)
>>> del os.environ["GRIDLIB_NUM_THREADS"]
"""

from __future__ import annotations

import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from typing import TypeVar

from .errors import InputError

T = TypeVar("T")

ENV = "GRIDLIB_NUM_THREADS"


def num_threads(cap: int) -> int:
    """Threads to use, at most ``cap``: ``GRIDLIB_NUM_THREADS`` if set, else the usable CPUs."""
    value = os.environ.get(ENV, "").strip()
    if value:
        try:
            n = int(value)
        except ValueError:
            n = 0
        if n < 1:
            raise InputError(f"environment variable {ENV}: expected an integer >= 1, got {value!r}")
    elif hasattr(os, "sched_getaffinity"):
        n = len(os.sched_getaffinity(0))
    else:  # pragma: no cover - macOS and Windows
        n = os.cpu_count() or 1
    return max(1, min(n, cap))


def concurrently(*calls: Callable[[], T]) -> list[T]:
    """The results of the zero-argument ``calls``, in order, computed on up to
    :func:`num_threads` threads (numpy releases the GIL in its loops). Each call must
    write only its own outputs, so the results never depend on the number of threads.

    >>> concurrently(lambda: 1 + 1, lambda: "two")
    [2, 'two']
    """
    workers = num_threads(len(calls))
    if workers == 1:
        return [call() for call in calls]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(workers) as pool:
        futures = [pool.submit(call) for call in calls]
        return [future.result() for future in futures]


def in_slices(fn: Callable[[slice], object], n: int, count: int = 8) -> None:
    """``fn(rows)`` for ``count`` consecutive slices ``rows`` covering ``range(n)``, on up to
    :func:`num_threads` threads: elementwise work that writes rows ``rows`` of its outputs,
    the same bits for any number of threads.

    >>> out = [0] * 5
    >>> in_slices(lambda rows: out.__setitem__(rows, [2 * i for i in range(5)][rows]), 5, 2)
    >>> out
    [0, 2, 4, 6, 8]
    """
    size = max(1, -(-n // count))
    concurrently(*(lambda s=s: fn(slice(s, min(s + size, n))) for s in range(0, n, size)))


def in_order(fn: Callable[..., T], blocks: Iterable[tuple], max_threads: int) -> Iterator[T]:
    """``fn(*b)`` for every ``b`` of ``blocks``, yielded in the blocks' order; computed on up
    to ``num_threads(max_threads)`` threads, a few blocks ahead of the consumer, so that
    memory stays bounded however many blocks there are. Each call must write only its own
    outputs, so the results never depend on the number of threads.

    >>> list(in_order(lambda a, b: a * b, [(1, 2), (3, 4), (5, 6)], 2))
    [2, 12, 30]
    """
    workers = num_threads(max_threads)
    if workers <= 1:
        for b in blocks:
            yield fn(*b)
        return
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(workers) as pool:
        pending: deque = deque()
        for b in blocks:
            pending.append(pool.submit(fn, *b))
            if len(pending) > 2 * workers:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()
