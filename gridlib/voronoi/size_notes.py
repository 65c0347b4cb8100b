"""Notes on cells and faces smaller than their target size, for ``PebiGrid.notes``.

``pebi_grid`` aims at cells of at least ``AREA_RATIO_MIN`` (0.1) h² and faces of at
least ``FACE_RATIO_MIN`` (0.01) h, h being each cell's target size (``PebiGrid.site_size``;
for a face the smaller of its two cells'). Some layouts force less: a fault meeting the
boundary or another fault at an angle of a few degrees makes a wedge whose first cell is
a sliver, however it is cut. Every such cell and face is counted in one note, with the
smallest of them and what made it, so that nothing small goes unreported:

``"2 cell(s) smaller than 0.1 h^2 (the smallest 0.0777 h^2 near (x, y), in the wedge where
fault 'F1' (faults[0]) meets the boundary at 0.55 degrees)"``.

Lengths in metres, areas in m².
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

AREA_RATIO_MIN = 0.1  # cells smaller than this x h^2 are noted
FACE_RATIO_MIN = 0.01  # faces shorter than this x h are noted
# PebiGrid.site_kind
KIND_NAMES = ("background", "padding", "fault", "fault tip", "well", "added", "well side row")


def size_notes(
    areas: np.ndarray,
    face_length: np.ndarray,
    neighbors: np.ndarray,
    face_mid: Callable[[int], np.ndarray],
    sites: np.ndarray,
    site_size: np.ndarray,
    why: Callable[[int], str],
    fmt: Callable[[np.ndarray], str],
) -> list[str]:
    """The notes (zero to two) on cells and faces below the bounds.

    ``areas`` (nc,) m²; ``face_length`` (nf,) m; ``neighbors`` (nf, 2) (-1 outside);
    ``face_mid(f)`` and ``sites`` (nc, 2) points for the messages (local frame);
    ``site_size`` (nc,) m; ``why(c)`` what made cell c (its kind, the wedge it is in);
    ``fmt`` writes a local point in the caller's coordinates.
    """
    notes = []
    area_ratio = areas / site_size**2
    small = np.flatnonzero(area_ratio < AREA_RATIO_MIN)
    if small.size:
        c = int(small[np.argmin(area_ratio[small])])
        notes.append(
            f"{small.size} cell(s) smaller than {AREA_RATIO_MIN:g} h^2 (the smallest {area_ratio[c]:.3g} h^2 "
            f"near {fmt(sites[c])}, {why(c)})"
        )
    other = np.where(neighbors[:, 1] >= 0, site_size[np.maximum(neighbors[:, 1], 0)], np.inf)
    face_ratio = face_length / np.minimum(site_size[neighbors[:, 0]], other)
    short = np.flatnonzero(face_ratio < FACE_RATIO_MIN)
    if short.size:
        f = int(short[np.argmin(face_ratio[short])])
        c = int(neighbors[f, 0])
        notes.append(
            f"{short.size} face(s) shorter than {FACE_RATIO_MIN:g} h (the shortest {face_ratio[f]:.3g} h "
            f"near {fmt(face_mid(f))}, of a cell {why(c)})"
        )
    return notes
