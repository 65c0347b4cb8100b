"""ZCORN as OPM Flow reads it: layers that overlap on a pillar moved apart.

Down every pillar, corner by corner, Flow (and ECLIPSE) make the depths of a column's cells
non-decreasing: a cell's top corner above the bottom corner of the cell above is moved down to
it, and a cell's bottom corner above its own top corner is moved down to the top (a corner of no
thickness). Exports from geomodelling tools carry such overlaps (rounding of the layers' depths,
or a zone cut by an erosion surface), and Flow runs those decks; gridlib's readers of ECLIPSE
files (GRDECL, binary GRDECL, EGRID) and ``read_roff_deck`` (a deck case's ROFF grid, whose
GRDECL Flow reads) apply the same rule with a note, and
:func:`~gridlib.cornerpoint.process.process_grdecl` then finds a consistent deck (a deck built
in memory with overlaps stays an error there, naming the cells).

One difference from Flow, deliberate: the rule joins each active cell to the nearest *active*
cell above it on the pillar, and leaves inactive cells as they are. Flow applies it to every
cell, so an inactive cell whose corners hold junk (a huge depth, as some exports write for
cells without geometry) moves every cell below it; gridlib ignores inactive cells' corners
throughout. Where an inactive cell between two active ones overlaps the lower one, Flow moves
that cell's top a little further down than gridlib does.

>>> z = np.array([0.0, 2.0, 1.5, 3.0]).repeat(4).reshape(4, 2, 2)  # two cells; the second's top
>>> fixed, moved = flow_zcorn(z, np.ones((2, 1, 1), bool), 1)     # above the first's bottom
>>> fixed[:, 0, 0].tolist(), moved
([0.0, 2.0, 2.0, 3.0], 4)
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from .corners import majority_depth_sign
from .deck import Deck

__all__ = ["flow_zcorn", "without_layer_overlaps"]


def flow_zcorn(zc: NDArray[np.float64], active: np.ndarray, sign: int) -> tuple[NDArray[np.float64], int]:
    """ZCORN ``zc`` (2nz, 2ny, 2nx) with overlapping layers moved apart (module docstring), and
    how many corner depths moved; ``active`` (nz, ny, nx); ``sign`` 1 for z down (depth), -1
    for z up. A new array where something moved, else ``zc`` itself. One pass down the layers,
    vectorised over each layer's corners."""
    nz = active.shape[0]
    depth = sign * zc if sign < 0 else zc
    above = np.full(zc.shape[1:], np.nan)  # the bottom of the nearest active cell above, per corner
    out = None
    moved = 0
    with np.errstate(invalid="ignore"):  # NaN: no active cell above yet (or junk)
        for k in range(nz):
            act = np.repeat(np.repeat(active[k], 2, axis=0), 2, axis=1)
            top, bottom = depth[2 * k], depth[2 * k + 1]
            raise_top = act & (top < above)
            new_top = np.where(raise_top, above, top)
            lower_bottom = act & (bottom < new_top)
            if raise_top.any() or lower_bottom.any():
                if out is None:
                    out = depth.copy()
                out[2 * k] = new_top
                out[2 * k + 1] = np.where(lower_bottom, new_top, bottom)
                moved += int(np.count_nonzero(raise_top)) + int(np.count_nonzero(lower_bottom))
                bottom = out[2 * k + 1]
            above = np.where(act, bottom, above)
    if out is None:
        return zc, 0
    return (sign * out if sign < 0 else out), moved


def without_layer_overlaps(deck: Deck) -> Deck:
    """``deck`` with its ZCORN as Flow reads it (:func:`flow_zcorn`, the deck's depth sign taken
    from most of its active cells) and a note saying how many corner depths moved; ``deck``
    itself where none did."""
    nx, ny, nz = deck.cart_dims
    active = deck.active.reshape(nz, ny, nx)
    zc = deck.zcorn_array()
    sign, _ = majority_depth_sign(zc, active)
    fixed, moved = flow_zcorn(zc, active, sign)
    if not moved:
        return deck
    note = (
        f"{moved} corner depths of active cells moved down to remove overlapping layers (a top above "
        "the bottom of the active cell above, or a bottom above its own top), as OPM Flow reads ZCORN"
    )
    return replace(deck, zcorn=fixed.ravel(), notes=(*deck.notes, note))
