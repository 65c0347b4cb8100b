"""A well's path: points along the hole with their measured depths (MD).

Placeholder of the shared interface (issue 26); the "paths" helper's module replaces it.
Coordinates in the case's length unit, x east, y north, z depth (positive down).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import frozen_array
from ..errors import InputError
from ..grid import FloatArray


@dataclass(frozen=True, eq=False)
class WellPath:
    """``xyz`` (n, 3) points (z depth), n >= 2, consecutive points distinct; ``md`` (n,)
    measured depth, strictly increasing."""

    xyz: FloatArray
    md: FloatArray
    name: str = ""

    def __post_init__(self) -> None:
        xyz = frozen_array(self.xyz, np.float64, "path.xyz", 2, error=InputError)
        md = frozen_array(self.md, np.float64, "path.md", 1, error=InputError)
        if xyz.shape[1] != 3 or xyz.shape[0] < 2 or md.size != xyz.shape[0]:
            raise InputError(f"well {self.name!r}: a path needs n >= 2 points (n, 3) and n MDs")
        if not (np.isfinite(xyz).all() and np.isfinite(md).all()) or np.any(np.diff(md) <= 0):
            raise InputError(f"well {self.name!r}: MDs must be finite and strictly increasing")
        object.__setattr__(self, "xyz", xyz)
        object.__setattr__(self, "md", md)

    @classmethod
    def from_points(
        cls, xyz: ArrayLike, md: ArrayLike | None = None, *, name: str = "", start_md: float = 0.0
    ) -> WellPath:
        """A path through ``xyz``; ``md`` is ``start_md`` + the cumulative length if not given."""
        p = np.asarray(xyz, dtype=np.float64)
        if md is None:
            step = np.sqrt(np.einsum("ij,ij->i", np.diff(p, axis=0), np.diff(p, axis=0)))
            md = start_md + np.concatenate([[0.0], np.cumsum(step)])
        return cls(p, np.asarray(md, dtype=np.float64), name)

    def at(self, md: ArrayLike) -> FloatArray:
        """(k, 3) points at the given MDs, linear along the segments."""
        m = np.atleast_1d(np.asarray(md, dtype=np.float64))
        return np.stack([np.interp(m, self.md, self.xyz[:, i]) for i in range(3)], axis=1)

    def between(self, md_from: float, md_to: float) -> WellPath:
        """The part of the path with MD in [md_from, md_to]."""
        inner = (self.md > md_from) & (self.md < md_to)
        md = np.concatenate([[md_from], self.md[inner], [md_to]])
        return WellPath(self.at(md), md, self.name)

    @property
    def length(self) -> float:
        return float(self.md[-1] - self.md[0])
