"""The ridges of an unclipped Voronoi diagram: the type that :mod:`.lattice` computes, :mod:`.degenerate`
reads and :mod:`.bounded` clips."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Ridges:
    """The ridges of the Voronoi diagram of a set of sites (local frame, m).

    ``coords`` (nv, 2): the Voronoi vertices (circumcentres of Delaunay triangles); ridge k
    runs from vertex ``va[k]`` to vertex ``vb[k]`` and separates sites ``cp[k]`` and ``cq[k]``
    (a Delaunay edge). Vertices may be listed that no ridge uses.
    """

    coords: np.ndarray
    va: np.ndarray
    vb: np.ndarray
    cp: np.ndarray
    cq: np.ndarray

    def where(self, mask: np.ndarray) -> Ridges:
        """The ridges selected by ``mask`` (or indices), over the same vertices."""
        return Ridges(self.coords, self.va[mask], self.vb[mask], self.cp[mask], self.cq[mask])

    def lengths(self) -> np.ndarray:
        """The length of every ridge (m)."""
        return np.linalg.norm(self.coords[self.va] - self.coords[self.vb], axis=1)
