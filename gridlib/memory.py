"""How much memory an input needs against how much the machine has: one rule for every size guard.

A guard estimates the bytes a step will allocate from the input's size alone (before allocating
anything) and asks :func:`memory_shortfall`; the answer is the sentence a message ends with
("1e10 cells need about 1.49e+03 GiB to read; this machine has 23 GiB"), or None when the estimate fits.
The machine's memory is its physical memory (``os.sysconf``), not what is free at the moment: a
guard refuses what cannot work, not what might be slow.
"""

from __future__ import annotations

import math
import os

__all__ = ["GIB", "count_text", "gib_text", "machine_memory", "memory_shortfall"]

GIB = float(1 << 30)


def machine_memory() -> int | None:
    """Physical memory of this machine in bytes; None where the system does not say."""
    try:
        pages, page_size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None
    return pages * page_size if pages > 0 and page_size > 0 else None


def count_text(n: float) -> str:
    """A count for a message: every digit with thousands separators below 1e15, else 3
    significant digits.

    >>> count_text(10**10), count_text(12), count_text(2e30), count_text(float("inf"))
    ('10,000,000,000', '12', '2e+30', 'more than 1e308')
    """
    if not math.isfinite(n):
        return "more than 1e308"
    return f"{int(n):,}" if n < 1e15 else f"{n:.3g}"


def gib_text(n_bytes: float) -> str:
    """A byte count in GiB for a message: whole GiB from 10 GiB, one decimal below, 3
    significant digits from 1e6 GiB, 2 significant digits below 0.1 GiB.

    >>> gib_text(8e12), gib_text(3 << 30), gib_text(1e6), gib_text(1e18)
    ('7,451 GiB', '3.0 GiB', '0.00093 GiB', '9.31e+08 GiB')
    """
    if not math.isfinite(n_bytes):
        return "more memory than any machine has"
    gib = n_bytes / GIB
    if gib >= 1e6:
        return f"{gib:.3g} GiB"
    if gib >= 10:
        return f"{gib:,.0f} GiB"
    return f"{gib:.1f} GiB" if gib >= 0.1 else f"{gib:.2g} GiB"


def memory_shortfall(needed: float, what: str, purpose: str = "", available: int | None = None) -> str | None:
    """None if ``needed`` bytes fit in the machine's memory (or ``available`` bytes), else the
    end of a message: ``"{what} need about N GiB {purpose}; this machine has M GiB"``.

    >>> memory_shortfall(2e12, "1e10 cells", "to read", available=16 << 30)
    '1e10 cells need about 1,863 GiB to read; this machine has 16 GiB'
    >>> memory_shortfall(1e6, "10 cells", available=16 << 30) is None
    True
    """
    have = machine_memory() if available is None else available
    if have is None or needed <= have:
        return None
    purpose = f" {purpose}" if purpose else ""
    return f"{what} need about {gib_text(needed)}{purpose}; this machine has {gib_text(have)}"
