"""Synthetic corner-point decks with what geomodelling exports hold and OPM Flow runs: thin wedges
beside a fault (a layer pinching out, three of four corners of each cell collapsed), and the
full DATA deck around such a grid for Flow."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from flow_tools import rest_of_deck

from gridlib.cornerpoint.deck import Deck
from gridlib.io.grdecl import write_grdecl


def wedge_deck(
    seed: int = 7,
    dims: tuple[int, int, int] = (4, 10, 3),
    fault: int = 2,
    throw: float = 0.5,
    wedge: float = 5e-4,
) -> Deck:
    """Three layers of 10 m over an irregular plan grid (pillars up to 25 m off a 100 m lattice,
    vertical) and a warped top surface, with a fault between i = ``fault`` and ``fault`` + 1
    (``throw`` m down on its +i side). The middle layer pinches out everywhere but at every
    other pillar on the fault, where it is ``wedge`` m thick: each cell of it beside the fault
    has three of its four corners collapsed. The layers above and below leave gaps of up to 1 m
    over and under it (surfaces exported with their own interpolation), as exports have."""
    rng = np.random.default_rng(seed)
    nx, ny, nz = dims
    x, y = np.meshgrid(np.arange(nx + 1) * 100.0, np.arange(ny + 1) * 100.0)
    x += rng.uniform(-25.0, 25.0, x.shape)
    y += rng.uniform(-25.0, 25.0, y.shape)
    top = 1000.0 + 0.02 * x + 0.01 * y + 3.0 * np.sin(x / 70.0) * np.cos(y / 90.0)
    coord = np.stack([x, y, np.full_like(x, 900.0), x, y, np.full_like(x, 1200.0)], axis=-1)
    thickness = np.full((nz, ny + 1, nx + 1), 10.0)
    thickness[1] = 0.0
    thickness[1][1::2, fault] = wedge
    surfaces = np.concatenate([top[None], top[None] + np.cumsum(thickness, axis=0)])
    zcorn = np.empty((2 * nz, 2 * ny, 2 * nx))
    for k in range(nz):
        for c in (0, 1):
            for b in (0, 1):
                for a in (0, 1):
                    zcorn[2 * k + c, b::2, a::2] = surfaces[k + c][b : b + ny, a : a + nx]
    zcorn[:, :, 2 * fault :] += throw
    zcorn[1] -= rng.uniform(0.0, 1.0, zcorn[1].shape)
    zcorn[4] += rng.uniform(0.0, 1.0, zcorn[4].shape)
    return Deck(dims, coord.reshape(-1), zcorn.reshape(-1), source="wedges")


def write_data_deck(folder: Path, name: str, deck: Deck, rock: dict[str, np.ndarray]) -> Path:
    """``folder/NAME.DATA``: an oil-water METRIC deck around ``deck`` (``NAME.grdecl``, with the
    cell keywords ``rock``) that Flow runs, with INIT (Flow then writes PORV and T)."""
    folder.mkdir(parents=True, exist_ok=True)
    write_grdecl(folder / f"{name}.grdecl", deck, rock)
    nx, ny, nz = deck.cart_dims
    text = f"RUNSPEC\nDIMENS\n {nx} {ny} {nz} /\nOIL\nWATER\nMETRIC\n"
    text += "TABDIMS\n 1 1 20 20 /\nEQLDIMS\n 1 /\nSTART\n 1 'JAN' 2020 /\nUNIFOUT\n"
    text += f"GRID\nINIT\nINCLUDE\n '{name}.grdecl' /\n"
    text += rest_of_deck(float(deck.zcorn.min()), float(deck.zcorn.max()) + 1.0)
    path = folder / f"{name}.DATA"
    path.write_text(text)
    return path
