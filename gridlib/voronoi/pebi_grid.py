"""``pebi_grid``: PEBI (Voronoi) grids whose faces follow faults and whose cells refine around wells.

The generating points ("sites") are, in this order of precedence:

* **fault sites** (:mod:`.fault_sites`): mirrored pairs along every fault trace, so
  that Voronoi edges lie exactly on the trace, plus tip sites beyond free ends;
* **well sites** (:mod:`.wells`): a centre and radial rings for vertical wells,
  a row of sites along well paths and mirrored rows beside them (:mod:`.path_sites`);
* **background sites** (:mod:`.sites`): a hexagonal or Cartesian lattice of
  spacing ``cell_size`` (or graded by a size function), optionally with rows of
  Cartesian cells along the boundary; lattice sites inside the fault circles,
  near fault sites or inside a well's clearance zone are removed.

The grid is the Voronoi diagram of the sites clipped to the domain
(:mod:`.bounded`): cell c is the part of the domain closer to site c than to any
other site, so interior faces are perpendicular bisectors of their two sites.

Near the boundary: lattice sites outside the domain, or closer to its boundary
than ``boundary_clearance`` (0.25) times their spacing, are dropped (no half-width
sliver cells); well sites must lie inside (wells whose rings reach outside are
errors); a fault's sites may not (below). Where a concave
boundary cuts a site's region in two, a site is added for the cut-off piece, the
region's site mirrored across the boundary edge between them (so that the edge's
line is their bisector and the new cell is as wide as the old one), and the diagram
recomputed (a note says how many; where that site would fall into a fault circle, the
fault's steps are refined there first). Ridges shorter than 1e-7 of the smallest spacing
(co-circular sites) are contracted, and the vertices of fault faces are set to the
exact circle centres on the traces.

Awkward layouts build; what could not be honoured exactly is said in ``notes``:

* faults meeting each other or the boundary at small angles, and sharply kinked
  traces, get one row of cells shared by both sides of the wedge; splays of any
  number of faults at any angles get rows of cells along every arm, shared where
  both arms of a gap want the same (:mod:`.wedges`, a note per wedge or fan);
* faults running close to each other or to the boundary get locally smaller steps,
  as small as the gap needs, down to 1/64 of the cell size (a note says how many rounds
  of refinement);
* a fault running closer to the boundary than its sites stand off it gets smaller steps
  there too, down to a quarter of its own step (``conformity.GRAZE_FLOOR``); the sites
  still outside then stay: the face between a site and its mirror image is the step all
  the same, and the boundary closes the site's cell, the strip between the trace and the
  boundary (a note names the fault and counts those cells);
* a well near a fault keeps its rings clear of the fault's circles: they are
  shrunk (or dropped, one cell at the well), with a note; a vertical well on a fault
  trace, at its tip, where faults meet or closer to it than the fault's cells are wide
  gets one of the fault's cells, on its ``fault_side`` or the nearer side, with a note
  (:mod:`.fault_wells`); a well path crossing a
  fault or running along it gets the fault cells it runs through there instead of
  sites of its own; fault steps are refined where a well's site would fall into a circle;
* geometry finer than the cells can follow is resolved: a trace passing a
  re-entrant corner within a tenth of the cell size, or any corner within the
  smallest cell the refinement may make (the cell size times 2^-max_refinements),
  goes through it; crossings and ends that close join; the notes name the faults
  and how far their traces moved. ``fault_traces`` holds the traces honoured;
* cells smaller than 0.1 h^2 and faces shorter than 0.01 h (h = ``site_size``)
  that a constraint forces are counted in a note, with the smallest and its cause
  (:mod:`.size_notes`).

Errors remain for input that is wrong: an invalid domain or trace, a fault or well
outside the domain, rings reaching outside it, wells overlapping each other. They
are :class:`GridError` naming the object.

No tiny faces: nearly co-circular sites (generic along the boundary and where
the lattice meets fault and well sites) would give faces of millimetres. Where a
face is shorter than 5 % of its cells' target size (``site_size``), a background
site is moved, by at most about twice that length, onto the circle that makes
the configuration exactly degenerate: the face vanishes and every face stays an
exact perpendicular bisector (:mod:`.degenerate`). Where no background site can
move (only fault or well sites, or Cartesian lattice sites held by their
co-circular squares), faces shorter than 1 % are contracted instead (never fault
faces; the faces next to them are then orthogonal to their sites within about a
degree). Both are noted. Where two arms of a fault junction nearly share their
first site (two straight faults crossing), they are made to share it exactly.

Fault faces carry ``faces.tag`` = fault id (1-based position in ``faults``),
every other face 0; ``cell_well`` is the 1-based well id of the cells generated
by a well's sites (not by the side rows of its path), of the fault cell of a vertical well on
a fault, and of the other free cells a well path runs through (fault cells where it has no
site), else 0. Coordinates are metres in the
caller's frame (UTM-sized coordinates are fine: everything is computed in a
local frame); the grid follows :mod:`gridlib.grid`'s conventions (0-based,
2-D faces are edges whose normal (dy, -dx) points from ``neighbors[:, 0]`` to
``neighbors[:, 1]``, -1 = outside).

>>> g = pebi_grid(((0, 0), (4, 3)), 1.0, pattern="cartesian")
>>> g.grid.num_cells, g.grid.num_faces
(12, 31)
>>> f = pebi_grid(((0, 0), (10, 10)), 1.0, faults=[Fault([(2, 2), (8, 7)])])
>>> lengths = np.linalg.norm(np.diff(f.grid.nodes.coords[f.grid.faces.nodes.reshape(-1, 2)], axis=1), axis=2)
>>> round(float(lengths[f.grid.faces.tag == 1].sum()), 9), round(float(np.hypot(6, 5)), 9)
(7.810249676, 7.810249676)
"""

from __future__ import annotations

import functools
import itertools
import math
import numbers
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import cKDTree

from ..errors import GridError
from .bounded import ClippedVoronoi, Contraction, clipped_voronoi
from .conformity import (
    GRAZE_FLOOR,
    fault_problems,
    graze_notes,
    outside_sites,
    problem_kinds,
    raise_fault_problem,
    refine_factor,
    snap_to_traces,
    verify,
)
from .degenerate import CONTRACT, SHORT, Collapse, MoveRules, collapse_moves
from .domain import Domain
from .fault_junctions import FITTED
from .fault_layout import FaultLayout, Refinement, layout, ring_room
from .fault_network import Fault
from .fault_sites import FaultSites, build_sites, circle_violations
from .fault_wells import fault_cells
from .lattice import Lattice
from .path_sites import cells_along
from .pebi_result import ADDED, BACKGROUND, FAULT, FAULT_TIP, PADDING_SITE, WELL, WELL_SIDE, PebiGrid
from .ridges import Ridges
from .sites import PADDING, Background, background_sites
from .size_notes import KIND_NAMES, size_notes
from .wells import Well, WellSites, build_wells, check_clearances, removal_mask

MAX_EXTRA_ROUNDS = 6
EXTRA_ROUNDS = 4  # x max_refinements: the most rounds of fault refinement, while each is worth it


def _size_function(cell_size: object, dom: Domain) -> tuple[Callable[[np.ndarray], np.ndarray], float | None]:
    """A vectorised size function of local points (m), validated, and the constant size if any."""
    if callable(cell_size):

        def size(p: np.ndarray) -> np.ndarray:
            p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
            g = p + dom.origin
            try:
                v = np.asarray(cell_size(g[:, 0], g[:, 1]), dtype=np.float64)
                v = np.broadcast_to(v, (p.shape[0],)).copy()
            except (TypeError, ValueError) as exc:
                raise GridError(
                    f"pebi_grid: cell_size(x, y) must return one size (m) per point for arrays x, y ({exc})"
                ) from exc
            bad = ~(np.isfinite(v) & (v > 0))
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                raise GridError(
                    f"pebi_grid: cell_size(x, y) must be a positive length, but it is {float(v[k])!r} at "
                    f"({g[k, 0]:.6g}, {g[k, 1]:.6g})"
                )
            return v

        return size, None
    if (
        isinstance(cell_size, bool)
        or not isinstance(cell_size, numbers.Real)
        or not np.isfinite(float(cell_size))
        or float(cell_size) <= 0
    ):
        raise GridError(
            "pebi_grid: cell_size must be a positive length in metres or a callable h(x, y), "
            f"got {cell_size!r}"
        )
    h = float(cell_size)

    def constant(p: np.ndarray) -> np.ndarray:
        return np.full(np.asarray(p).reshape(-1, 2).shape[0], h)

    return constant, h


@dataclass(frozen=True)
class PebiTuning:
    """The expert settings of :func:`pebi_grid`; the defaults (upr's) suit every layout we know.

    ``fault_ratio``: circle radius / step length along faults, in (0.5, 1).
    ``boundary_clearance``: lattice sites closer than this fraction of their spacing to the
    boundary are dropped, in [0, 0.5).
    ``max_refinements``: sets the finest fault step the local refinement makes where the
    empty-circle condition fails, and the smallest feature honoured: the cell size times
    2^-max_refinements. That many rounds are always allowed (each at least halving the steps
    where it refines); more, up to 4 x max_refinements, while they still make a step smaller
    without going below that minimum.
    """

    fault_ratio: float = 0.6
    boundary_clearance: float = 0.25
    max_refinements: int = 6


def pebi_grid(
    domain: object,
    cell_size: float | Callable,
    faults: Sequence[Fault] = (),
    wells: Sequence[Well] = (),
    *,
    pattern: str = "hexagonal",
    padding: int | None = None,
    tuning: PebiTuning = PebiTuning(),
) -> PebiGrid:
    """A PEBI grid of ``domain`` conforming to ``faults`` and refined around ``wells``.

    Parameters
    ----------
    domain
        The polygon: a sequence of (x, y) vertices (m), either orientation, closed
        implicitly; two points ``((xmin, ymin), (xmax, ymax))`` give a rectangle;
        a shapely Polygon without holes works too.
    cell_size
        Background spacing (m): the distance between neighbouring lattice sites,
        or a vectorised callable ``h(x, y) -> sizes`` for a graded lattice (see
        :mod:`gridlib.voronoi.sites`).
    faults
        :class:`Fault` traces; clipped to the domain, split where they cross or touch.
    wells
        :class:`Well` points (with optional :class:`~gridlib.voronoi.wells.Rings`) and paths.
    pattern
        ``"hexagonal"`` or ``"cartesian"`` background lattice.
    padding
        Number of rows of Cartesian cells along the boundary (numeric ``cell_size`` only).
    tuning
        :class:`PebiTuning`: the fault circles' ratio to the steps (0.6 as upr), the boundary
        clearance of lattice sites and how often fault steps may be refined.

    Raises
    ------
    GridError
        On invalid input, naming the object: ``fault 'F2' (faults[1]): ...``.
    """
    if not isinstance(tuning, PebiTuning):
        raise GridError(f"pebi_grid: tuning must be a PebiTuning, got {tuning!r}")
    fault_ratio, boundary_clearance = tuning.fault_ratio, tuning.boundary_clearance
    max_refinements = tuning.max_refinements
    notes: list[str] = []
    dom = Domain(domain)
    size, constant = _size_function(cell_size, dom)
    pattern = _check_options(pattern, padding, constant, fault_ratio, max_refinements, boundary_clearance)
    faults = list(faults)
    wells = list(wells)

    lay = layout(faults, dom, size, float(fault_ratio), notes, math.ldexp(1.0, -int(max_refinements)))
    fault_labels = lay.net.labels if lay is not None else []
    room = None if lay is None else functools.partial(ring_room, lay)
    ws = build_wells(wells, dom, size, room, notes)
    check_clearances(ws)
    bg = _background(dom, size, constant, pattern, padding, boundary_clearance, ws)
    attempt = 0
    for _ in range(max_refinements + 1):  # a site added for a cut-off piece may ask for smaller fault steps
        ss, lay, attempt = _conforming_fault_sites(lay, bg, size, dom, ws, attempt, max_refinements)
        if ss.xy.shape[0] == 0:  # a domain smaller than one cell: one cell
            ss = _one_cell(ss, dom)
            bg = ss.bg
            notes.append("the domain is smaller than one cell: one site at a point inside it")
        clipped = _clip_rounds(ss, dom, size, fault_labels, attempt < max_refinements)
        if not clipped.refine:
            break
        lay = lay.refined(clipped.refine)
        attempt += 1
    notes.extend(_adjustment_notes(ss, clipped, attempt))
    notes.extend(graze_notes(ss.faults, dom, fault_labels))

    fs, keep, n_bg, vor, sites = ss.faults, ss.keep, ss.n_bg, clipped.vor, clipped.sites
    n_f = fs.sites.shape[0]
    n_sites = sites.shape[0]
    tags = _fault_tags(vor, fs, n_bg, n_sites)
    grid = vor.to_grid(dom.origin, tags, ("pebi_grid",))
    cell_well = np.zeros(n_sites, dtype=np.int64)
    cell_well[n_bg + n_f : n_bg + n_f + ws.sites.shape[0]] = ws.cell_well
    if ws.on_fault_well.size:  # wells on a fault: one of its cells each
        traces = [dom.to_local(np.asarray(f.points, dtype=np.float64)) for f in faults]
        had_rings = np.array([wells[w - 1].rings is not None for w in ws.on_fault_well.tolist()], dtype=bool)
        mine, on_notes = fault_cells(
            ws.on_fault_well,
            ws.on_fault_point,
            ws.on_fault_side,
            fs.sites,
            fs.site_step,
            traces,
            fault_labels,
            ws.labels,
            had_rings,
            dom.fmt,
        )
        cell_well[n_bg + mine] = ws.on_fault_well
        notes.extend(on_notes)
    if ws.along.shape[0]:  # the free cells a well path runs through (fault cells where it has no site)
        tree = cKDTree(sites)
        cells, owner = cells_along(lambda p: tree.query(p)[1], ws.along, ws.along_well, dom.tol)
        free = cell_well[cells] == 0
        cell_well[cells[free]] = owner[free]
    site_kind = np.full(n_sites, ADDED, dtype=np.int8)
    site_kind[:n_bg] = np.where(bg.padding[keep], PADDING_SITE, BACKGROUND)
    site_kind[n_bg : n_bg + n_f] = np.where(fs.is_tip, FAULT_TIP, FAULT)
    site_kind[n_bg + n_f : n_bg + n_f + ws.sites.shape[0]] = np.where(ws.site_side, WELL_SIDE, WELL)
    n_given = clipped.site_size.size  # the sites before those added for cut-off pieces
    site_size = np.concatenate([clipped.site_size, size(sites[n_given:])])
    verify(vor, dom, tags, fs, fault_labels, ws, cell_well)
    notes.extend(_size_notes(vor, site_size, site_kind, fs, n_bg, dom))
    names_f = tuple((f.name or f"F{i + 1}") for i, f in enumerate(faults))
    names_w = tuple((w.name or f"W{i + 1}") for i, w in enumerate(wells))
    site_xy = sites + dom.origin
    traces = _honoured_traces(lay, len(faults), dom)
    for a in (cell_well, site_xy, site_kind, site_size, *traces):
        a.flags.writeable = False
    return PebiGrid(grid, cell_well, names_f, names_w, site_xy, tuple(notes), site_kind, site_size, traces)


def _check_options(pattern, padding, constant, fault_ratio, max_refinements, boundary_clearance) -> str:
    """Raise on an invalid option of :func:`pebi_grid`; the lattice pattern by its canonical name."""
    if pattern == "square":
        pattern = "cartesian"
    if pattern not in ("hexagonal", "cartesian"):
        raise GridError(f"pebi_grid: pattern must be 'hexagonal' or 'cartesian', got {pattern!r}")
    if padding is not None:
        if isinstance(padding, bool) or not isinstance(padding, numbers.Integral) or padding < 0:
            raise GridError(f"pebi_grid: padding must be a number of rows (an integer >= 0), got {padding!r}")
        if padding and constant is None:
            raise GridError("pebi_grid: padding needs a numeric cell_size (the rows have one width)")
    if not (isinstance(fault_ratio, numbers.Real) and 0.5 < fault_ratio < 1):
        raise GridError(f"pebi_grid: fault_ratio must lie in (0.5, 1), got {fault_ratio!r}")
    if isinstance(max_refinements, bool) or not (
        isinstance(max_refinements, numbers.Integral) and max_refinements >= 0
    ):
        raise GridError(f"pebi_grid: max_refinements must be an integer >= 0, got {max_refinements!r}")
    if not (isinstance(boundary_clearance, numbers.Real) and 0 <= boundary_clearance < 0.5):
        raise GridError(f"pebi_grid: boundary_clearance must lie in [0, 0.5), got {boundary_clearance!r}")
    return pattern


@dataclass(frozen=True, eq=False)
class _Background:
    """The background sites, lattice sites first (see lattice.py): positions, spacing, lattice
    index, on the lattice, in the padding rows; their tree and which are clear of the wells."""

    back: Background
    xy: np.ndarray
    spacing: np.ndarray
    ij: np.ndarray
    on_lattice: np.ndarray
    padding: np.ndarray
    tree: cKDTree | None
    keep: np.ndarray


@dataclass(frozen=True, eq=False)
class _SiteSet:
    """The sites of one refinement round: the background sites kept (``keep``, a mask over
    ``bg``), then the fault sites, then the well sites, all in ``xy`` (local frame, m)."""

    bg: _Background
    keep: np.ndarray
    faults: FaultSites
    wells: WellSites
    xy: np.ndarray

    @property
    def n_bg(self) -> int:
        """The number of background sites kept (the first sites of ``xy``)."""
        return int(self.keep.sum())


@dataclass(frozen=True, eq=False)
class _Clipped:
    """What :func:`_clip_rounds` made of a site set: the diagram, the sites (those added for
    cut-off pieces last), the target sizes of the sites before those, the background sites
    moved, the number of sites added; or, in ``refine``, the smaller fault steps wanted
    (x, y, step) where a cut-off piece fell into a fault circle: the sites are then rebuilt."""

    vor: ClippedVoronoi
    sites: np.ndarray
    site_size: np.ndarray
    moved: np.ndarray
    n_extra: int
    refine: tuple[Refinement, ...] = ()


def _background(dom: Domain, size, constant, pattern, padding, boundary_clearance, ws) -> _Background:
    back = background_sites(dom, size, constant, pattern, padding, float(boundary_clearance))
    order = np.argsort(~back.on_lattice, kind="stable")  # lattice sites first (see lattice.py)
    bg, bg_spacing, bg_ij = back.xy[order], back.spacing[order], back.ij[order]
    bg_lattice, bg_padding = back.on_lattice[order], back.kind[order] == PADDING
    bg_tree = cKDTree(bg) if bg.shape[0] else None
    bg_keep = np.ones(bg.shape[0], dtype=bool)
    if bg_tree is not None:
        bg_keep &= ~removal_mask(ws, bg, bg_tree)
    return _Background(back, bg, bg_spacing, bg_ij, bg_lattice, bg_padding, bg_tree, bg_keep)


def _site_set(lay: FaultLayout | None, bg: _Background, size, ws: WellSites) -> _SiteSet:
    """The fault sites of the layout, the background sites clear of their circles and of the
    fault sites, and the well sites."""
    fs = build_sites(lay) if lay is not None else FaultSites.empty()
    keep = bg.keep.copy()
    if bg.tree is not None and fs.centres.shape[0]:
        hits = bg.tree.query_ball_point(fs.centres, fs.radii * (1 + 1e-6), return_sorted=False)
        keep[np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64)] = False
        near = 0.5 * np.maximum(fs.site_step, size(fs.sites))
        hits = bg.tree.query_ball_point(fs.sites, near, return_sorted=False)
        keep[np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64)] = False
    return _SiteSet(bg, keep, fs, ws, np.concatenate([bg.xy[keep], fs.sites, ws.sites]))


def _conforming_fault_sites(
    lay: FaultLayout | None,
    bg: _Background,
    size,
    dom: Domain,
    ws: WellSites,
    attempt: int,
    max_refinements: int,
) -> tuple[_SiteSet, FaultLayout | None, int]:
    """Fault sites meeting the empty-circle condition with everything else, the fault steps
    refined where they do not (from round ``attempt`` on): the site set, the layout with the
    refinements made and the round reached."""
    while True:  # rebuild the fault sites where they conflict
        ss = _site_set(lay, bg, size, ws)
        fs = ss.faults
        floor = _graze_floor(lay, fs, size, last=attempt >= max_refinements)
        problems = fault_problems(fs, ss.xy, ss.n_bg, dom, bg.tree, ss.keep, floor)
        if not problems:
            return ss, lay, attempt
        if attempt >= max_refinements:
            kinds = problem_kinds(problems, fs)
            hard = [p for p, why in zip(problems, kinds, strict=True) if why != FITTED]
            if not hard:  # only junctions whose arms were fitted to them: the sites conform
                return ss, lay, attempt
            # more rounds while they make fault steps smaller, down to the finest allowed
            floor = math.ldexp(1.0, -max_refinements) * size(np.array([w for w, _ in hard]))
            finer = lay.refined(
                (float(w[0]), float(w[1]), max(step, f))
                for (w, step), f in zip(hard, floor.tolist(), strict=True)
            )
            if finer.refine == lay.refine or attempt >= EXTRA_ROUNDS * max(max_refinements, 1):
                raise_fault_problem(hard, fs, dom, lay, attempt, ws)
            lay, attempt = finer, attempt + 1
            continue
        lay = lay.refined((float(where[0]), float(where[1]), step) for where, step in problems)
        attempt += 1


def _graze_floor(lay: FaultLayout | None, fs: FaultSites, size, last: bool) -> np.ndarray | None:
    """The smallest step (m) a fault site outside the domain may ask for: ``GRAZE_FLOOR`` times its
    fault's unrefined step; in the last round none (every such site's cell is closed by the boundary)."""
    if lay is None or fs.sites.shape[0] == 0:
        return None
    if last:
        return np.full(fs.sites.shape[0], np.inf)
    spacing = lay.net.spacing[fs.site_fault - 1]
    own = np.isfinite(spacing)
    base = spacing.copy()
    if not own.all():
        base[~own] = size(fs.site_foot[~own])
    return GRAZE_FLOOR * base


def _one_cell(ss: _SiteSet, dom: Domain) -> _SiteSet:
    """A domain smaller than one cell: one background site at a point inside it (the background
    replaced by that site; which sites were kept before is kept for the notes)."""
    rp = dom.polygon.point_on_surface()
    xy = np.array([[rp.x, rp.y]])
    bg = replace(
        ss.bg,
        xy=xy,
        spacing=np.array([dom.diameter]),
        ij=np.zeros((1, 2), dtype=np.int64),
        on_lattice=np.zeros(1, bool),
        padding=np.zeros(1, bool),
    )
    return replace(ss, bg=bg, keep=np.ones(1, dtype=bool), xy=xy.copy())


class _ShortFaceRepair:
    """The ``adjust`` step of :func:`~.bounded.clipped_voronoi` for one diagram: background sites
    moved to collapse short faces (:mod:`.degenerate`). ``collapse``, what was done so far,
    is carried from one diagram of the rounds to the next."""

    def __init__(self, rules: MoveRules, collapse: Collapse) -> None:
        self.rules = rules
        self.collapse = collapse

    def __call__(self, sites: np.ndarray, ridges: Ridges, fresh: np.ndarray | None):
        idx, xy, self.collapse = collapse_moves(ridges, sites, self.rules, self.collapse, fresh)
        return idx, xy, self.collapse.involved


def _outside_fault_circles(fs: FaultSites, xy: np.ndarray) -> np.ndarray:
    """Which new positions of background sites are allowed: those outside every fault circle."""
    ok = np.ones(xy.shape[0], dtype=bool)
    if fs.centres.shape[0]:
        ok[circle_violations(fs, xy)[1]] = False
    return ok


def _clip_rounds(ss: _SiteSet, dom: Domain, size, labels: Sequence[str], can_refine: bool) -> _Clipped:
    """The clipped Voronoi diagram of the sites, short faces repaired (background sites moved,
    :mod:`.degenerate`; faces contracted), a site added for every piece of a cell a concave
    boundary cuts off, until none is; where such a piece falls into a fault circle, the
    smaller fault steps wanted there instead (``can_refine``; else an error)."""
    bg, keep, fs, ws = ss.bg, ss.keep, ss.faults, ss.wells
    sites, n_bg = ss.xy, ss.n_bg
    tol = _merge_tolerance(dom, bg.spacing, fs, ws)
    back = bg.back
    on_lat = keep & bg.on_lattice
    lattice = Lattice(back.pattern, back.lattice_origin, back.lattice_h, bg.ij[on_lat])
    n_lat = int(on_lat.sum())
    kind_extra = n_extra = 0
    moved = np.zeros(0, dtype=np.int64)
    collapse = Collapse()
    site_size = np.concatenate([bg.spacing[keep], fs.site_step, ws.site_size])
    allowed = functools.partial(_outside_fault_circles, fs)

    for _ in range(MAX_EXTRA_ROUNDS + 1):  # a concave boundary may cut a region in two
        movable = np.zeros(sites.shape[0], dtype=bool)
        movable[:n_bg] = True
        size_now = np.concatenate([site_size, size(sites[site_size.size :])])
        repair = _ShortFaceRepair(MoveRules(dom, size_now, movable, tol, allowed), collapse)
        protect = fs.pairs + n_bg
        vor = clipped_voronoi(
            sites, dom, tol, lattice, repair, contract=Contraction(size_now, protect, CONTRACT)
        )
        collapse = repair.collapse
        changed = np.flatnonzero(np.any(vor.sites != sites, axis=1))
        if changed.size:
            moved = np.union1d(moved, changed)
            sites = vor.sites
            if n_lat:
                active = np.ones(n_lat, dtype=bool)
                active[moved[moved < n_lat]] = False
                lattice = Lattice(back.pattern, back.lattice_origin, back.lattice_h, bg.ij[on_lat], active)
        if vor.extra_points.shape[0] == 0:
            break
        if kind_extra == MAX_EXTRA_ROUNDS:
            raise GridError(
                f"pebi_grid: the domain is too narrow for the cell size near "
                f"{dom.fmt(vor.extra_points[0])}: Voronoi regions keep falling apart there; use a "
                "smaller cell_size"
            )
        extra = vor.extra_points
        if fs.centres.shape[0]:
            c, k = circle_violations(fs, extra)
            if c.size and can_refine:  # the piece lies by a fault: smaller steps there
                rel = extra[k] - fs.centres[c]
                scale = refine_factor(0.9 * np.hypot(rel[:, 0], rel[:, 1]) / fs.radii[c])
                refine = tuple(
                    (float(fs.centres[ci][0]), float(fs.centres[ci][1]), f * float(fs.centre_step[ci]))
                    for ci, f in zip(c.tolist(), scale.tolist(), strict=True)
                )
                return _Clipped(vor, sites, site_size, moved, n_extra, refine)
            if c.size:
                raise GridError(
                    f"{labels[fs.centre_fault[c[0]] - 1]} runs through a part of the domain "
                    f"narrower than the cell size near {dom.fmt(fs.centres[c[0]])}; use a smaller "
                    "cell_size"
                )
        sites = np.concatenate([sites, extra])
        kind_extra += 1
        n_extra += extra.shape[0]
    return _Clipped(vor, sites, site_size, moved, n_extra)


def _adjustment_notes(ss: _SiteSet, clipped: _Clipped, attempt: int) -> list[str]:
    """Notes on what was adjusted: acute wedges, refinements, sites removed, added and moved,
    faces contracted."""
    bg, keep, n_extra, moved, vor = ss.bg, ss.keep, clipped.n_extra, clipped.moved, clipped.vor
    notes = list(ss.faults.wedges)
    if attempt:
        notes.append(f"fault spacing refined locally {attempt} time(s) to keep the empty-circle condition")
    dropped = int(bg.keep.sum() - keep.sum())
    if dropped:
        notes.append(f"{dropped} background sites removed inside fault circles or next to fault sites")
    if (~bg.keep).any():
        notes.append(f"{int((~bg.keep).sum())} background sites removed around wells")
    if n_extra:
        notes.append(f"{n_extra} site(s) added where the concave boundary cut a cell in two")
    if moved.size:
        notes.append(
            f"{moved.size} background site(s) moved slightly to collapse faces shorter than "
            f"{SHORT:g} cell sizes (nearly co-circular sites)"
        )
    if vor.contracted:
        notes.append(
            f"{vor.contracted} face(s) shorter than {CONTRACT:g} cell sizes contracted (no background "
            "site to move there; the faces next to them are orthogonal to within a degree or so)"
        )
    return notes


def _fault_tags(vor, fs, n_bg: int, n_sites: int) -> np.ndarray:
    """Face tags: the fault id on the faces between the two sites of a fault step, 0 elsewhere.
    The vertices of fault faces are snapped to the exact trace points."""
    nb = vor.neighbors
    tags = np.zeros(nb.shape[0], dtype=np.int32)
    if fs.pairs.shape[0]:
        pr = np.sort(fs.pairs + n_bg, axis=1)
        pkey = pr[:, 0] * n_sites + pr[:, 1]
        order = np.argsort(pkey)
        pkey = pkey[order]
        inner = np.flatnonzero((nb >= 0).all(axis=1))
        lo, hi = np.minimum(nb[inner, 0], nb[inner, 1]), np.maximum(nb[inner, 0], nb[inner, 1])
        fkey = lo * n_sites + hi
        loc = np.minimum(np.searchsorted(pkey, fkey), pkey.size - 1)
        hit = pkey[loc] == fkey
        tags[inner[hit]] = fs.pair_fault[order[loc[hit]]]
        snap_to_traces(vor.coords, vor.face_nodes[tags > 0], fs)
    return tags


def _honoured_traces(lay, n_faults: int, dom: Domain) -> tuple[np.ndarray, ...]:
    """Segments (k, 2, 2) of every fault's honoured trace in the caller's frame (m)."""
    if lay is None:
        return tuple(np.zeros((0, 2, 2)) for _ in range(n_faults))
    net = lay.net
    seg = np.stack([net.nodes[net.edge_a], net.nodes[net.edge_b]], axis=1) + dom.origin
    return tuple(np.ascontiguousarray(seg[net.edge_fault == k + 1]) for k in range(n_faults))


def _size_notes(vor, site_size: np.ndarray, site_kind: np.ndarray, fs, n_bg: int, dom: Domain) -> list[str]:
    """Notes on the cells and faces below the size bounds (:mod:`.size_notes`), with their cause."""
    e = vor.face_nodes
    rel = vor.coords[e[:, 1]] - vor.coords[e[:, 0]]
    length = np.hypot(rel[:, 0], rel[:, 1])

    closed = np.zeros(vor.sites.shape[0], dtype=bool)  # fault cells whose sites lie outside the domain
    closed[n_bg + outside_sites(fs, dom)] = True

    def why(c: int) -> str:
        if site_kind[c] == ADDED:
            return "added where the concave boundary cut a cell in two"
        k = c - n_bg
        if fs.site_wedge is not None and 0 <= k < fs.site_wedge.size and fs.site_wedge[k] >= 0:
            return "in the wedge where " + fs.wedges[fs.site_wedge[k]].split(" at ")[0]
        if closed[c]:
            return "a fault cell between the trace and the boundary, closed by the boundary"
        return f"a {KIND_NAMES[site_kind[c]]} cell"

    def mid(f: int) -> np.ndarray:
        return 0.5 * (vor.coords[e[f, 0]] + vor.coords[e[f, 1]])

    where = vor.sites.copy()  # a cell is named by its site, or its site's foot on the trace if outside
    where[closed] = fs.site_foot[np.flatnonzero(closed) - n_bg]
    return size_notes(vor.areas, length, vor.neighbors, mid, where, site_size, why, dom.fmt)


def _merge_tolerance(dom: Domain, bg_spacing, fs, ws) -> float:
    """Ridges shorter than this (m) are contracted: 1e-7 of the smallest spacing."""
    smallest = [float(bg_spacing.min())] if bg_spacing.size else []
    if fs.centres.shape[0]:
        smallest.append(float(fs.centre_step.min()))
    if ws.sites.shape[0] > 1:
        d, _ = cKDTree(ws.sites).query(ws.sites, k=2)
        smallest.append(float(d[:, 1].min()))
    h = min(smallest) if smallest else dom.diameter
    return max(1e-7 * h, 1e-12 * dom.diameter)
