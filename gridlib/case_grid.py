"""The grid of a case, for every grid type, with what the later stages need.

:func:`build_case_grid` turns a validated :class:`~gridlib.config.Case` (and, for
cornerpoint and pebi grids, its horizons Dataset) into a :class:`CaseGrid`: the
grid, its non-neighbour connections, fault and well names, per-cell data
(bulk volume, well, zone, layer; for pebi grids the generating ``site`` (x, y) of
each cell's column, whose perpendicular bisectors the lateral faces are: the
transmissibility stage uses them as cell centres) and, for corner-point grids,
the deck (written as ``grid.grdecl``). The case's faults and wells become
gridlib objects here:

* a fault's ``trace`` and ``throw`` (a number, or ``{start, end}`` varying
  linearly along the trace) and ``side`` give a
  :class:`~gridlib.stratigraphic.fault_traces.FaultTrace` (both grid builders apply
  it to the restored horizons), and for pebi grids also a
  :class:`~gridlib.voronoi.Fault` the cell faces follow;
* a well's ``point`` + ``rings`` or ``path`` give a :class:`~gridlib.voronoi.Well`.

Paths in the case (deck files) are relative to the case file.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .build import build_grid
from .config import Case
from .cornerpoint.deck import Deck
from .cornerpoint.horizons import horizons_to_grdecl
from .cornerpoint.process import process_grdecl
from .errors import GridError, InputError
from .grid import Grid
from .stratigraphic.extrude import extrude
from .stratigraphic.fault_traces import FaultTrace
from .stratigraphic.nnc import NNC
from .voronoi import Fault, Rings, Well, pebi_grid, rectangle


@dataclass(frozen=True, eq=False)
class CaseGrid:
    """A case's grid and what comes with it (see the module docstring)."""

    grid: Grid
    nnc: NNC | None = None
    fault_names: tuple[str, ...] = ()
    well_names: tuple[str, ...] = ()
    cell_data: dict[str, np.ndarray] = field(default_factory=dict)
    deck: Deck | None = None
    notes: tuple[str, ...] = ()


def fault_traces(case: Case) -> list[FaultTrace]:
    """The case's faults as FaultTraces (throw in m; 0 where none is given)."""
    traces = []
    for spec in case.data.get("faults", []):
        throw = spec.get("throw", 0.0)
        if isinstance(throw, dict):
            start, end = float(throw["start"]), float(throw["end"])
            value: Any = lambda s, a=start, b=end: a + (b - a) * np.asarray(s)  # noqa: E731
        else:
            value = float(throw)
        side = spec.get("side", "right")
        traces.append(FaultTrace(spec["trace"], throw=value, name=spec["name"], side=side))
    return traces


def pebi_wells(case: Case) -> list[Well]:
    wells = []
    for spec in case.data.get("wells", []):
        rings = None
        if "rings" in spec:
            r = spec["rings"]
            rings = Rings(r["inner"], r.get("outer"), r.get("growth"), r.get("count"), r.get("sectors"))
        path, spacing = spec.get("path"), spec.get("spacing")
        wells.append(Well(spec.get("point"), spec["name"], rings=rings, path=path, spacing=spacing))
    return wells


def pebi_domain(spec: dict[str, Any]):
    domain = spec["domain"]
    if isinstance(domain, dict):
        return rectangle(*domain["rectangle"])
    return np.asarray(domain, dtype=np.float64)


def build_case_grid(case: Case, horizons=None) -> CaseGrid:
    """The grid of ``case``; ``horizons`` is the horizons Dataset (cornerpoint and pebi grids).

    Every error is an :class:`~gridlib.errors.InputError` naming the case file.
    """
    spec = case.data["grid"]
    kind = spec["type"]
    try:
        if kind == "cornerpoint":
            return _cornerpoint(case, spec, horizons)
        if kind == "pebi":
            return _pebi(case, spec, horizons)
        if kind == "deck":
            return _deck(case, spec)
    except GridError as exc:
        raise InputError(f"{case.path}: grid: {exc}") from exc
    except InputError as exc:
        if str(case.path) in str(exc):
            raise
        raise InputError(f"{case.path}: grid: {exc}") from exc
    return CaseGrid(build_grid(case))


def _horizon_list(case: Case, horizons):
    from .horizons import to_horizons

    if horizons is None:
        raise InputError(f"{case.path}: grid: a {case.data['grid']['type']} grid needs the case's horizons")
    return to_horizons(horizons)


def _cornerpoint(case: Case, spec: dict[str, Any], horizons) -> CaseGrid:
    from .horizons.by_block import block_horizons, horizons_to_grdecl_by_block

    by_block = block_horizons(horizons) if horizons is not None else None
    ordering = case.data["horizons"].get("ordering", "error")
    if by_block is not None:  # picks of faulted surfaces: every cell from its own block's surfaces
        stacks, blocks = by_block
        deck = horizons_to_grdecl_by_block(
            stacks, blocks, spec["dims"], spec["layers"], fault_traces(case), ordering=ordering
        )
    else:
        deck = horizons_to_grdecl(
            _horizon_list(case, horizons), spec["dims"], spec["layers"], fault_traces(case)
        )
    deck = replace(deck, source=f"{case.path} (horizons_to_grdecl)")
    return _processed(deck, spec.get("tolerance", 0.0))


def _processed(deck: Deck, tolerance: float, pinch: bool = False) -> CaseGrid:
    """A deck through process_grdecl, with its bulk volumes and layer index as cell data."""
    r = process_grdecl(deck, tolerance=tolerance, pinch=pinch)
    layer = r.grid.cells.index_map // (deck.cart_dims[0] * deck.cart_dims[1])
    return CaseGrid(
        r.grid,
        r.nnc,
        r.fault_names,
        cell_data={"bulk_volume": r.bulk_volumes, "layer": layer},
        deck=deck,
        notes=deck.notes + r.notes,
    )


def _pebi(case: Case, spec: dict[str, Any], horizons) -> CaseGrid:
    hz = _horizon_list(case, horizons)
    traces = fault_traces(case)
    faults = [Fault(t.points, t.name) for t in traces]
    areal = pebi_grid(
        pebi_domain(spec),
        spec["cell_size"],
        faults,
        pebi_wells(case),
        pattern=spec.get("pattern", "hexagonal"),
        padding=spec.get("padding"),
    )
    specs = case.data.get("faults", [])
    moving = [t for t, f in zip(traces, specs, strict=True) if f.get("throw", 0.0) != 0.0]
    r = extrude(areal.grid, hz, spec["layers"], moving, centres=areal.sites)
    grid, names = _one_tag_per_fault(r.grid, r.fault_names, areal.fault_names)
    column = grid.layering.column
    return CaseGrid(
        grid,
        r.nnc,
        names,
        areal.well_names,
        cell_data={
            "well": areal.cell_well[column],
            "zone": r.zone,
            "layer": grid.layering.layer,
            "site": areal.sites[column],  # the generating site (x, y) of each cell's column
        },
        notes=areal.notes + r.notes,
    )


def _one_tag_per_fault(grid: Grid, names: tuple[str, ...], areal_names: tuple[str, ...]):
    """Faces tagged by the areal (conforming) grid and by a fault trace of the same name get one tag:
    the areal grid's, named after the fault."""
    n_areal = len(areal_names)
    new = np.arange(len(names) + 1, dtype=np.int32)
    for t, name in enumerate(names[n_areal:], start=n_areal + 1):
        if name in areal_names:
            new[t] = areal_names.index(name) + 1
    kept = sorted(set(range(1, n_areal + 1)) | {int(v) for v in new[n_areal + 1 :] if v > n_areal})
    compact = np.zeros(len(names) + 1, dtype=np.int32)
    compact[kept] = np.arange(1, len(kept) + 1)
    tags = compact[new[grid.faces.tag]]
    final_names = tuple(areal_names[k - 1] if k <= n_areal else names[k - 1] for k in kept)
    faces = replace(grid.faces, tag=tags)
    return replace(grid, faces=faces), final_names


def deck_path(case: Case):
    name = case.data["grid"]["file"]
    path = case.path.parent / name
    if not path.is_file():
        raise InputError(f"{case.path}: grid.file: '{name}' not found (looked for {path})")
    return path


def read_case_deck(case: Case) -> Deck:
    from .io.egrid import read_egrid
    from .io.grdecl import read_grdecl

    path = deck_path(case)
    return read_egrid(path) if path.suffix.lower() in (".egrid", ".fegrid") else read_grdecl(path)


def _deck(case: Case, spec: dict[str, Any]) -> CaseGrid:
    return _processed(read_case_deck(case), spec.get("tolerance", 0.0), spec.get("pinch", False))
