"""Corner-point test models (MRST book §3.5): ``simple_grdecl``, ``make_model3``, ``cut_grdecl``.

Both generators follow MRST's constructions: nodes on a tensor lattice,
deformed, turned into pillars (COORD) through the top and bottom nodes of each
lattice column and into ZCORN by repeating interior node depths for the two
cells that share them; faults then shift the corner depths of one block.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..errors import InputError
from .deck import Deck, FaultSegment, shown


def _dims(dims: Sequence[int], what: str) -> tuple[int, int, int]:
    d = tuple(int(v) for v in dims)
    if len(d) != 3 or min(d) < 1 or any(v != w for v, w in zip(d, dims, strict=True)):
        raise InputError(f"{what}: dims must be three positive integers, got {shown(dims)}")
    return d  # type: ignore[return-value]


def _lattice(dims, phys):
    nx, ny, nz = dims
    return np.meshgrid(
        np.linspace(0, phys[0], nx + 1),
        np.linspace(0, phys[1], ny + 1),
        np.linspace(0, phys[2], nz + 1),
        indexing="ij",
    )


def _coord(X, Y, Z) -> np.ndarray:
    """COORD: per pillar (i fastest) the top and bottom lattice nodes."""
    top = np.stack([X[:, :, 0], Y[:, :, 0], Z[:, :, 0]], axis=-1)
    bot = np.stack([X[:, :, -1], Y[:, :, -1], Z[:, :, -1]], axis=-1)
    return np.concatenate([top, bot], axis=-1).transpose(1, 0, 2).reshape(-1)


def _corner_index(n: int) -> np.ndarray:
    """Lattice node of each of the 2n corner positions: 0, 1, 1, 2, 2, ..., n."""
    return np.arange(1, 2 * n + 1) // 2


def simple_grdecl(
    dims: Sequence[int],
    drop: float | Callable[[np.ndarray], np.ndarray] = 0.0,
    *,
    flat: bool = False,
    undisturbed: bool = False,
    phys_dims: Sequence[float] = (1.0, 1.0, 0.5),
) -> Deck:
    """MRST's ``simpleGrdecl``: a two-block model with one fault near x = 0.5.

    The box [0, 1] x [0, 1] x [0, 0.5] (``phys_dims``, m) gets skewed pillars
    (unless ``undisturbed``) and sine-perturbed layers (unless ``flat``), both
    scaled with the box. The corners with x index in the second half are
    displaced downwards by ``drop`` (m), a number or a function of y (m) along
    the fault.

    >>> deck = simple_grdecl([4, 2, 3], 0.12, flat=True)
    >>> deck.cart_dims, deck.zcorn.size
    ((4, 2, 3), 192)
    """
    dims = _dims(dims, "simple_grdecl")
    nx, ny, nz = dims
    phys = np.asarray(phys_dims, dtype=np.float64)
    # MRST's deformations, applied in the units of its default box [0,1] x [0,1] x [0,0.5]
    # and scaled back, so that other physical dimensions give the same shapes.
    scale = phys / np.array([1.0, 1.0, 0.5])
    X, Y, Z = (c / s for c, s in zip(_lattice(dims, phys), scale, strict=True))
    if not undisturbed:
        X = X + 0.2 * (0.5 - np.abs(X - 0.5)) * (Z - 0.5)
    if not flat and not undisturbed:
        Z = Z - 0.05 * np.sin(np.pi * (X - 0.5)) - 0.075 * np.sin(np.pi * (Y + 2 * X))
        Z = np.sort(Z, axis=2)
    X, Y, Z = X * scale[0], Y * scale[1], Z * scale[2]
    coord = _coord(X, Y, Z)
    z = Z[np.ix_(_corner_index(nx), _corner_index(ny), _corner_index(nz))].copy()
    half = nx  # corner columns 2nx/2 .. 2nx - 1 are the downthrown block
    if callable(drop):
        d = np.asarray(drop(np.linspace(0, phys[1], ny + 1)), dtype=np.float64)
        rows = np.r_[np.arange(0, 2 * ny, 2), 2 * ny - 1]  # one corner row per pillar row
        z[half:, rows, :] += d[None, :, None]
        z[half:, 1 : 2 * ny - 1 : 2, :] = z[half:, 2 : 2 * ny : 2, :]
    else:
        z[half:] += float(drop)
    return Deck(dims, coord, z.ravel(order="F"), np.ones(nx * ny * nz, np.int32), source="simple_grdecl")


def make_model3(
    dims: Sequence[int], phys_dims: Sequence[float] = (1000.0, 600.0, 15.0), seed: int = 0
) -> Deck:
    """MRST's ``makeModel3``: part of an anticline cut by two faults (book §3.5).

    Layers are perturbed by a smooth dome plus a random wave per layer (numpy's
    generator with ``seed``, so values differ from MRST's, the structure does
    not), two blocks are displaced by -2 m and +3 m, negative thicknesses are
    pinched to zero, and cells outside two circles are inactive.
    """
    dims = _dims(dims, "make_model3")
    nx, ny, nz = dims
    phys = np.asarray(phys_dims, dtype=np.float64)
    rng = np.random.default_rng(seed)
    a = rng.random(nz + 1)
    s = rng.standard_normal((nz + 1, 2))
    X, Y, Z = _lattice(dims, phys)
    xi, eta = X / phys[0], Y / phys[1]
    wave = a / 2 * np.sin(2 * np.pi * xi + s[:, 0]) * np.sin(4 * np.pi * eta + s[:, 1])
    Z = Z + 5 * np.sin(np.pi * (xi - 0.5)) + 3 * np.sin(np.pi * (eta + 2 * xi)) - wave
    coord = _coord(X, Y, Z)
    z = Z[np.ix_(_corner_index(nx), _corner_index(ny), _corner_index(nz))].copy()

    def mround(v: float) -> int:  # MATLAB's round: halves away from zero
        return int(np.floor(v + 0.5))

    i1, j1 = mround(0.6 * nx), mround(0.5 * ny)
    i2, j2 = mround(0.5 * nx), mround(ny / 3)
    if min(i1, j1, i2, j2) < 1:
        raise InputError(f"make_model3: dims {dims} are too small to place the two faults")
    z[: 2 * i1, : 2 * j1, :] -= 2.0
    z[2 * i2 :, 2 * j2 :, :] += 3.0
    z = np.cumsum(np.concatenate([z[:, :, :1], np.maximum(0.0, np.diff(z, axis=2))], axis=2), axis=2)
    x, y, _ = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, ny), np.linspace(0, 1, nz), indexing="ij")
    actnum = np.ones(dims, dtype=np.int32)
    actnum[(x - 0.4) ** 2 + y**2 > 0.95] = 0
    actnum[(x - 0.6) ** 2 + (y - 1) ** 2 > 0.9] = 0
    return Deck(dims, coord, z.ravel(order="F"), actnum.ravel(order="F"), source="make_model3")


def cut_grdecl(deck: Deck, box: Sequence[Sequence[int]]) -> Deck:
    """The sub-deck of cells ``box = ((i0, i1), (j0, j1), (k0, k1))``, 0-based, end exclusive.

    COORD, ZCORN, ACTNUM, every cell keyword and the FAULTS clipped to the box
    are kept (MRST's ``cutGrdecl``).
    """
    nx, ny, nz = deck.cart_dims
    try:
        (i0, i1), (j0, j1), (k0, k1) = ((int(a), int(b)) for a, b in box)
    except (TypeError, ValueError) as exc:
        raise InputError(f"cut_grdecl: box must be ((i0, i1), (j0, j1), (k0, k1)), got {shown(box)}") from exc
    if not (0 <= i0 < i1 <= nx and 0 <= j0 < j1 <= ny and 0 <= k0 < k1 <= nz):
        raise InputError(f"cut_grdecl: box {shown(box)} is not inside the {nx}x{ny}x{nz} grid")
    pillars = deck.pillars()[j0 : j1 + 1, i0 : i1 + 1]
    zc = deck.zcorn_array()[2 * k0 : 2 * k1, 2 * j0 : 2 * j1, 2 * i0 : 2 * i1]

    def cells(values: np.ndarray) -> np.ndarray:
        return values.reshape(nz, ny, nx)[k0:k1, j0:j1, i0:i1].ravel()

    faults = []
    for f in deck.faults:
        lo = (max(f.i1, i0), max(f.j1, j0), max(f.k1, k0))
        hi = (min(f.i2, i1 - 1), min(f.j2, j1 - 1), min(f.k2, k1 - 1))
        if all(a <= b for a, b in zip(lo, hi, strict=True)):
            faults.append(
                FaultSegment(
                    f.name, lo[0] - i0, hi[0] - i0, lo[1] - j0, hi[1] - j0, lo[2] - k0, hi[2] - k0, f.face
                )
            )
    return Deck(
        (i1 - i0, j1 - j0, k1 - k0),
        pillars.reshape(-1),
        zc.reshape(-1),
        None if deck.actnum is None else cells(deck.actnum),
        {name: cells(v) for name, v in deck.cell_data.items()},
        tuple(faults),
        dict(deck.multflt),
        deck.mapaxes,
        deck.mapunits,
        deck.gridunit,
        deck.units,
        deck.pinch,
        deck.minpv,
        f"{deck.source} cut to {box}",
        deck.notes,
    )
