"""Arrays read only when a writer writes them: :class:`Deferred`.

A 1e7-cell export holds a few dozen per-cell and per-connection arrays of about 80 MB each. Given
as :class:`Deferred`, :func:`gridlib.io.netcdf.write_netcdf` and :func:`gridlib.io.vtu.write_vtu`
read each one when they write it and let it go afterwards, so that one of them is in memory at
a time instead of all.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

# A file's arrays up to this many bytes in all are read at once, in one opening of the file:
# deferring them saves memory on large grids only, and each deferred read opens the file again
# (a 5,000-cell case's export opened quality.nc 60 times, 0.3 s of its 0.8 s).
EAGER_BYTES = 64 << 20


def deferring(nbytes: int) -> bool:
    """Whether arrays of ``nbytes`` bytes in all are better :class:`Deferred` than read at once
    (:data:`EAGER_BYTES`)."""
    return nbytes > EAGER_BYTES


@dataclass(frozen=True, eq=False)
class Deferred:
    """An array of ``shape`` and ``dtype`` that ``load()`` returns when it is needed (each time:
    nothing is kept). ``np.asarray`` of it loads it; a load of another shape or dtype is a
    ValueError naming ``what``."""

    shape: tuple[int, ...]
    dtype: np.dtype
    load: Callable[[], np.ndarray]
    what: str = "deferred array"

    @property
    def ndim(self) -> int:
        return len(self.shape)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape, dtype=np.int64))

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        values = np.asarray(self.load())
        if values.shape != tuple(self.shape) or values.dtype != self.dtype:
            raise ValueError(
                f"{self.what}: read {values.dtype} {values.shape}, expected {self.dtype} {tuple(self.shape)}"
            )
        return values if dtype is None else values.astype(dtype, copy=False)
