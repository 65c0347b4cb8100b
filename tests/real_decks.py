"""Real decks against OPM Flow's dry run: what each computes, and the four comparisons.

``compare(name, deck, out)`` runs Flow's dry run on ``deck`` and gridlib's
``read_grdecl`` -> ``process_grdecl`` -> ``deck_transmissibility`` with the pore volumes
the transmissibility stage makes for a deck case (the deck's PORV where given, else bulk
volume x PORO x NTG x MULTPV in the deck's reservoir volume unit). The ``check_*``
functions then demand Flow's active cells, its connection set, every T within 1e-6
relative (INIT stores float32: 6e-8) and every pore volume within 1e-6 relative; T and
pore volumes on the pairs and cells both have, so that each says what it can.
"""

from __future__ import annotations

import lzma
import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr
from flow_tools import flow_connection_arrays, read_keywords, run_flow_dry

from gridlib.config import load_case
from gridlib.cornerpoint.pore_volume import pore_volumes
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl
from gridlib.stages import case_outputs, run_stage
from gridlib.transmissibility import deck_transmissibility

DECKS = Path(__file__).parent / "data" / "decks"
REL = 1e-6


@dataclass(frozen=True)
class Computed:
    """Active cells (0-based linear, ascending), connections ((n, 2) linear pairs, first <
    second, sorted; T in deck units) and pore volumes per active cell (deck units)."""

    active: np.ndarray
    pairs: np.ndarray
    trans: np.ndarray
    porv: np.ndarray


@dataclass(frozen=True)
class Comparison:
    """Flow's and gridlib's results for one deck; gridlib's exception where it failed."""

    name: str
    deck: Path
    dims: tuple[int, int, int]
    flow: Computed
    gridlib_result: Computed | Exception

    def gridlib(self) -> Computed:
        """gridlib's result, or its exception raised again (the test fails with it)."""
        if isinstance(self.gridlib_result, Exception):
            raise self.gridlib_result
        return self.gridlib_result

    def ijk(self, cells) -> list[tuple[int, int, int]]:
        """1-based (i, j, k) of linear cell indices."""
        nx, ny, _ = self.dims
        g = np.atleast_1d(cells)
        i, j, k = g % nx + 1, g // nx % ny + 1, g // (nx * ny) + 1
        return list(zip(i.tolist(), j.tolist(), k.tolist(), strict=True))

    def keys(self, pairs: np.ndarray) -> np.ndarray:
        """One int64 per pair, ascending as the pairs are sorted."""
        return pairs[:, 0] * int(np.prod(self.dims)) + pairs[:, 1]


def unpack(folder: str, dest: Path) -> Path:
    """Copy tests/data/decks/``folder`` to ``dest``, decompressing its .xz files."""
    src = DECKS / folder
    for path in sorted(src.rglob("*")):
        if path.is_dir():
            continue
        target = dest / path.relative_to(src)
        target.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".xz":
            target.with_suffix("").write_bytes(lzma.decompress(path.read_bytes()))
        else:
            shutil.copyfile(path, target)
    return dest


def flow_result(deck: Path, out: Path) -> tuple[Computed, tuple[int, int, int]]:
    case = run_flow_dry(deck, out)
    egrid = read_keywords(Path(f"{case}.EGRID"))
    init = read_keywords(Path(f"{case}.INIT"))
    dims = tuple(int(v) for v in egrid["GRIDHEAD"][1:4])
    active = np.flatnonzero(egrid["ACTNUM"] > 0)
    porv = init["PORV"].astype(np.float64)
    porv = porv[active] if porv.size == np.prod(dims) else porv
    pairs, trans = flow_connection_arrays(case)
    return Computed(active, pairs, trans, porv), dims


def gridlib_result(deck_path: Path, unknown_keywords: str = "error") -> Computed:
    deck = read_grdecl(deck_path, unknown_keywords=unknown_keywords)
    cp = process_grdecl(deck)
    conn = deck_transmissibility(deck, cp)
    cells = cp.grid.cells.index_map
    porv = pore_volumes(deck, cells, cp.bulk_volumes)
    order = np.lexsort((conn.global_cells[:, 1], conn.global_cells[:, 0]))
    return Computed(np.asarray(cells), conn.global_cells[order], conn.trans[order], np.asarray(porv))


def case_result(case_file: Path, folder: Path) -> Computed:
    """What the workflow makes of a deck case: its grid, geometry, petrophysics and
    transmissibility stages, then transmissibility.nc's cells, connections and pore volumes."""
    case = load_case(case_file)
    paths = case_outputs(case.name, folder)
    for stage in ("grid", "geometry", "petrophysics", "transmissibility"):
        run_stage(stage, case, paths)
    with xr.open_dataset(paths["transmissibility"]) as ds:
        index, cells = ds["cell_flow_index"].values, ds["connection_cells"].values
        t, porv = ds["trans"].values, ds["porv"].values
    pairs = np.sort(index[cells], axis=1)
    by_pair, by_cell = np.lexsort((pairs[:, 1], pairs[:, 0])), np.argsort(index)
    return Computed(index[by_cell], pairs[by_pair], t[by_pair], porv[by_cell])


def compare(
    name: str,
    deck: Path,
    out: Path,
    gridlib: Callable[[], Computed] | None = None,
    unknown_keywords: str = "error",
) -> Comparison:
    """Flow's dry run of ``deck`` and gridlib's result: ``gridlib()``, by default
    ``gridlib_result(deck, unknown_keywords)``."""
    flow, dims = flow_result(deck, out)
    try:
        ours: Computed | Exception = gridlib() if gridlib else gridlib_result(deck, unknown_keywords)
    except Exception as exc:  # each check raises it again
        ours = exc
    return Comparison(name, deck, dims, flow, ours)


def _within(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """Which of ``values`` are in the ascending ``sorted_set`` (np.isin without its sort)."""
    if sorted_set.size == 0:
        return np.zeros(values.size, dtype=bool)
    return sorted_set[np.minimum(np.searchsorted(sorted_set, values), sorted_set.size - 1)] == values


def check_active_cells(c: Comparison) -> None:
    ours, flow = c.gridlib(), c.flow
    if not np.array_equal(ours.active, flow.active):
        only_ours = ours.active[~_within(ours.active, flow.active)]
        only_flow = flow.active[~_within(flow.active, ours.active)]
        raise AssertionError(
            f"{c.name}: active cells: gridlib {ours.active.size:,d}, Flow {flow.active.size:,d}; "
            f"{only_ours.size:,d} only in gridlib (first (i, j, k): {c.ijk(only_ours[:3])}); "
            f"{only_flow.size:,d} only in Flow (first: {c.ijk(only_flow[:3])})"
        )


def check_connections(c: Comparison) -> None:
    ours, flow = c.gridlib(), c.flow
    ka, kb = c.keys(ours.pairs), c.keys(flow.pairs)
    if not np.array_equal(ka, kb):
        only_ours, only_flow = ours.pairs[~_within(ka, kb)], flow.pairs[~_within(kb, ka)]
        raise AssertionError(
            f"{c.name}: connections: gridlib {ka.size:,d}, Flow {kb.size:,d}; "
            f"{len(only_ours):,d} only in gridlib (first: {[c.ijk(p) for p in only_ours[:3]]}); "
            f"{len(only_flow):,d} only in Flow (first: {[c.ijk(p) for p in only_flow[:3]]})"
        )


def check_transmissibilities(c: Comparison) -> None:
    ours, flow = c.gridlib(), c.flow
    if ours.trans.size == flow.trans.size == 0:  # no connection at all (a column of one cell)
        return
    common, ia, ib = np.intersect1d(
        c.keys(ours.pairs), c.keys(flow.pairs), assume_unique=True, return_indices=True
    )
    assert common.size > 0.9 * flow.trans.size, f"{c.name}: only {common.size:,d} pairs in common"
    a, b = ours.trans[ia], flow.trans[ib]
    rel = np.abs(a - b) / np.abs(b)
    worst = int(np.argmax(rel))
    assert rel[worst] <= REL, (
        f"{c.name}: {int((rel > REL).sum()):,d} of {common.size:,d} T differ by more than {REL:g}; "
        f"worst {c.ijk(flow.pairs[ib[worst]])}: gridlib {a[worst]!r}, Flow {b[worst]!r}"
    )


def check_pore_volumes(c: Comparison) -> None:
    ours, flow = c.gridlib(), c.flow
    common, ia, ib = np.intersect1d(ours.active, flow.active, assume_unique=True, return_indices=True)
    assert common.size > 0.9 * flow.active.size, f"{c.name}: only {common.size:,d} cells in common"
    a, b = ours.porv[ia], flow.porv[ib]
    rel = np.abs(a - b) / np.abs(b)
    worst = int(np.argmax(rel))
    assert rel[worst] <= REL, (
        f"{c.name}: {int((rel > REL).sum()):,d} of {common.size:,d} pore volumes differ by more "
        f"than {REL:g}; worst {c.ijk(common[worst])}: gridlib {a[worst]!r}, Flow {b[worst]!r}"
    )


# the four comparisons, in the order a failure is easiest to read
CHECKS_ALL = (check_active_cells, check_connections, check_transmissibilities, check_pore_volumes)
