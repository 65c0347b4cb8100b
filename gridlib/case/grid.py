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
  :class:`~gridlib.pillars.fault_traces.FaultTrace` (both grid builders apply
  it to the restored horizons), and for pebi grids also a
  :class:`~gridlib.voronoi.Fault` the cell faces follow;
* a well's ``point`` + ``rings`` or ``path`` give a :class:`~gridlib.voronoi.Well`, and
  so does a trajectory or survey well in a pebi grid: its plan view where it is in the
  reservoir (:func:`~gridlib.case.wells.pebi_wells`).

Paths in the case (deck files) are relative to the case file.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..config import Case
from ..cornerpoint.between_horizons import horizons_to_grdecl
from ..cornerpoint.deck import Deck
from ..cornerpoint.pillar_grdecl import horizons_to_pillar_grdecl
from ..cornerpoint.process import process_grdecl
from ..errors import GridError, InputError
from ..geometry import compute_geometry
from ..grid import Grid
from ..horizons import to_horizons
from ..horizons.by_block import block_horizons, horizons_to_grdecl_by_block
from ..pillars.extrude import extrude
from ..pillars.fault_pillars import FaultPillars, depth_range, fault_pillars, inclined, largest_throw
from ..pillars.horizon_maps import DepthFunction, depth_function
from ..pillars.nnc import NNC
from ..voronoi import Fault, pebi_grid, rectangle
from .deck import read_case_deck
from .faults import fault_traces
from .horizons import block_fault_traces
from .simple_grids import build_grid
from .wells import pebi_wells


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


def pebi_domain(spec: dict[str, Any]):
    """The areal domain of a pebi grid: ``{rectangle: [...]}`` or a polygon's vertices."""
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
    if horizons is None:
        raise InputError(f"{case.path}: grid: a {case.data['grid']['type']} grid needs the case's horizons")
    return to_horizons(horizons)


def _cornerpoint(case: Case, spec: dict[str, Any], horizons) -> CaseGrid:
    if spec.get("fault_geometry") == "pillars":
        return _pillar_cornerpoint(case, spec, horizons)
    by_block = block_horizons(horizons) if horizons is not None else None
    ordering = case.data["horizons"]["ordering"]
    if by_block is not None:  # picks of faulted surfaces: every cell from its own block's surfaces
        stacks, blocks = by_block
        tops = np.stack([s[0].z for s in stacks])  # inclined faults meet the footwall tops at their traces
        faults = block_fault_traces(case, blocks, tops, stacks[0][0].x, stacks[0][0].y)
        deck = horizons_to_grdecl_by_block(
            stacks, blocks, spec["dims"], spec["layers"], faults, ordering=ordering
        )
    else:  # fault_geometry stair_steps: vertical pillars, inclined faults stepped cell by cell
        hz = _horizon_list(case, horizons)
        deck = horizons_to_grdecl(hz, spec["dims"], spec["layers"], _case_faults(case, hz[0]))
    deck = replace(deck, source=f"{case.path} (horizons_to_grdecl)")
    return _processed(deck, spec["tolerance"])


def _case_faults(case: Case, top) -> list:
    """The case's faults; inclined ones (a dip or sticks) are placed against the top horizon."""
    return fault_traces(case, top=depth_function(top))


def _pillar_cornerpoint(case: Case, spec: dict[str, Any], horizons) -> CaseGrid:
    """fault_geometry pillars: pillars that follow the faults' surfaces (horizons_to_pillar_grdecl)."""
    if horizons is not None and block_horizons(horizons) is not None:
        raise InputError(
            f"{case.path}: grid: fault_geometry pillars does not take horizons picked per fault block "
            "yet; use fault_geometry: stair_steps"
        )
    hz = _horizon_list(case, horizons)
    deck = horizons_to_pillar_grdecl(
        hz,
        spec["dims"],
        spec["layers"],
        _case_faults(case, hz[0]),
        ordering=case.data["horizons"]["ordering"],
        relax_distance=spec.get("relax_distance"),
    )
    deck = replace(deck, source=f"{case.path} (horizons_to_pillar_grdecl)")
    return _processed(deck, spec["tolerance"])


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
    top = depth_function(hz[0])
    traces = fault_traces(case, top=top)
    faults = [Fault(t.points, t.name) for t in traces]
    specs = case.data.get("faults", [])
    moving = [t for t, f in zip(traces, specs, strict=True) if f["throw"] != 0.0]
    areal = pebi_grid(
        pebi_domain(spec),
        spec["cell_size"],
        faults,
        pebi_wells(case, *_reservoir(hz, largest_throw(moving))),
        pattern=spec["pattern"],
        padding=spec.get("padding"),
    )
    lines = _inclined_pillars(spec, areal, traces, top, depth_function(hz[-1], len(hz) - 1), moving)
    pillars = None if lines is None else lines.pillars()
    r = extrude(areal.grid, hz, spec["layers"], moving, pillars=pillars, centres=areal.sites)
    grid, names = _one_tag_per_fault(r.grid, r.fault_names, areal.fault_names)
    column = grid.layering.column
    if lines is None:
        site = areal.sites[column]  # the generating site (x, y) of each cell's column
    else:  # the site followed down its inclined column to the cell's centroid depth
        site = lines.sites_at(column, compute_geometry(grid).cell_centroids[:, 2])
    return CaseGrid(
        grid,
        r.nnc,
        names,
        areal.well_names,
        cell_data={
            "well": areal.cell_well[column],
            "zone": r.zone,
            "layer": grid.layering.layer,
            "site": site,
        },
        notes=areal.notes + (() if lines is None else lines.notes) + r.notes,
    )


def _reservoir(hz, throw: float) -> tuple[DepthFunction, DepthFunction]:
    """The depths (m, f(x, y)) between which a pebi grid's deviated wells are refined: the top
    horizon less and the base horizon plus the largest throw (a hanging wall lies deeper by up
    to it; the wells' sites then reach a little beyond the reservoir near faults, never fall
    short), each carried on beyond its lattice from its edge."""
    top = depth_function(hz[0], clamped=True)
    base = depth_function(hz[-1], len(hz) - 1, clamped=True)
    return (lambda x, y: top(x, y) - throw), (lambda x, y: base(x, y) + throw)


def _inclined_pillars(spec, areal, traces, top, base, moving) -> FaultPillars | None:
    """The pillars of a pebi grid with inclined faults (in the fault surfaces, relaxing back to
    vertical; wells' cells vertical), or None when every fault is vertical."""
    if not inclined(traces):
        return None
    xy = areal.grid.nodes.coords[:, :2]
    depths = depth_range(top, base, xy, moving)
    return fault_pillars(
        areal.grid,
        traces,
        top,
        depths.z_lo,
        depths.z_hi,
        vertical_cells=areal.cell_well > 0,
        relax_distance=spec.get("relax_distance"),
        thickness=depths.thickness,
        base=base,
        throw=depths.throw,
        sites=areal.sites,
        who="pebi grid",
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


def _deck(case: Case, spec: dict[str, Any]) -> CaseGrid:
    return _processed(read_case_deck(case), spec["tolerance"], spec["pinch"])
