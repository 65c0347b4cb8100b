"""Well sites: radial rings around vertical wells, rows of sites on and beside well paths.

A vertical well (``Well(point, rings=Rings(...))``) gets its centre site plus
rings of ``sectors`` sites at geometrically graded radii (MRST book §3.3.2 and
§3.5.2, Figs. 3.25 and 3.37); background sites closer to the centre than the
outer radius plus half a cell are removed. A well without rings is one site.
A well path (``Well(path=polyline)``, or several branches and points of one well:
``Well(path=[polyline, polyline, point])``) gets sites on the polyline, at all its
vertices and about ``spacing`` apart in between, and mirrored rows of sites beside
it so that the path's cells are symmetric about it where it runs straight: their
centroids lie on the path (:mod:`.path_sites`). Background sites in a band of about
1.5 cells around the path are removed. The cells of a well's sites are that well's
cells (``PebiGrid.cell_well``); the cells of the side rows are not.

Near a fault, a well's rings end a quarter step outside the fault's circles (the
circles that keep the fault's faces on its trace must hold no site): rings reaching
farther are shrunk to that radius, same inner radius and growth, or dropped if not
even the first ring fits (the well is then one cell), and a note says so. A well path
crossing a fault, or running along it, has no sites that close to the trace: the
fault cells it runs through there are the well's (every cell holding a point of the
path is, ``WellSites.along``). The well
and fault sites then coexist; where one still falls into a fault circle (a circle at
a junction is larger), the fault's steps are refined there. Wells must keep clear of
each other.

Units are metres and radians; x, y in plan view.

>>> Rings(inner=0.1, outer=10.0, growth=10 ** 0.5).radii(8).round(3).tolist()
[0.1, 0.316, 1.0, 3.162, 10.0]
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from ..errors import GridError
from ..reproducible import exp, log, power
from .domain import Domain
from .path_sites import EDGE, MERGE, band, clearance, path_graph, path_rows, segment_steps, steps_of


def _positive(value: object, what: str) -> float:
    if not (
        isinstance(value, int | float) and not isinstance(value, bool) and np.isfinite(value) and value > 0
    ):
        raise GridError(f"{what} must be a positive number, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class Rings:
    """Radial rings of sites around a vertical well (lengths in metres).

    ``inner`` is the radius of the first ring. Give two of ``outer`` (radius of
    the last ring), ``growth`` (ratio of consecutive radii, > 1) and ``count``
    (number of rings); with ``outer`` alone the growth is exp(2 pi / sectors),
    which makes the ring cells about as long as they are wide. With ``outer``
    and ``growth`` the number of rings is rounded and the growth adjusted so that
    the last ring lies exactly at ``outer``. ``sectors`` (sites per ring)
    defaults to 2 pi outer / cell size (at least 6); ``angle`` (radians) is the
    direction of every ring's first site.

    >>> r = Rings(inner=np.exp(-3.5), outer=1.0, growth=np.exp(0.25), sectors=16)
    >>> r.radii(16).size, float(r.radii(16)[-1])
    (15, 1.0)
    """

    inner: float
    outer: float | None = None
    growth: float | None = None
    count: int | None = None
    sectors: int | None = None
    angle: float = 0.0

    def radii(self, sectors: int, what: str = "Rings") -> np.ndarray:
        inner = _positive(self.inner, f"{what}: inner")
        outer = None if self.outer is None else _positive(self.outer, f"{what}: outer")
        growth = None if self.growth is None else _positive(self.growth, f"{what}: growth")
        count = self.count
        if count is not None and not (isinstance(count, int | np.integer) and count >= 1):
            raise GridError(f"{what}: count must be a positive integer, got {count!r}")
        if growth is not None and growth <= 1:
            raise GridError(f"{what}: growth must be larger than 1, got {growth!r}")
        if outer is not None and outer < inner:
            raise GridError(f"{what}: outer ({outer}) is smaller than inner ({inner})")
        given = sum(x is not None for x in (outer, growth, count))
        if given == 3:
            raise GridError(f"{what}: give two of outer, growth and count, not all three")
        if outer is not None and growth is not None:
            count = int(np.round(log(outer / inner) / log(growth))) + 1
            return np.geomspace(inner, outer, max(count, 1)) if count > 1 else np.array([inner])
        if outer is not None and count is not None:
            return np.geomspace(inner, outer, count) if count > 1 else np.array([inner])
        if growth is not None and count is not None:
            return inner * power(growth, np.arange(count, dtype=np.float64))
        if outer is not None:
            g = float(exp(2 * np.pi / sectors))
            count = int(np.round(log(outer / inner) / log(g))) + 1
            return np.geomspace(inner, outer, count) if count > 1 else np.array([inner])
        if count is not None and count == 1:
            return np.array([inner])
        raise GridError(f"{what}: give the outer radius, or the growth and the number of rings (count)")


@dataclass(frozen=True, eq=False)
class Well:
    """A vertical well at ``point`` (with optional ``rings``) or a well ``path``.

    ``path``: one polyline (n, 2), or a sequence of pieces of one well, each a polyline
    (k, 2) or a point (1, 2): branches meeting at a point (a multilateral well), or the parts
    of a trajectory inside the reservoir (:func:`~.areal.areal_path`), a vertical part
    being a point. ``name`` defaults to ``W<k>`` (k = 1-based position). ``spacing`` (m) is
    the distance between sites along a path (default: the cell size there).

    >>> Well((100.0, 50.0), name="I1", rings=Rings(inner=1.0, outer=20.0)).name
    'I1'
    """

    point: ArrayLike | None = None
    name: str | None = None
    rings: Rings | None = None
    path: ArrayLike | None = None
    spacing: float | None = None
    fault_side: str | None = None


FAULT_SIDES = {None: 0, "left": 1, "right": -1}  # Well.fault_side: the sign of the side's normal


@dataclass(frozen=True, eq=False)
class PathZone:
    """A path well's zone (local frame, m): its ``geometry`` (segments and points), ``probes``
    on it (every point of the path within ``spread`` of one), the ``band`` where background
    sites are removed and the ``clearance`` other wells keep."""

    well: int
    geometry: shapely.Geometry
    probes: np.ndarray
    spread: float
    band: float
    clearance: float


@dataclass
class WellSites:
    """Sites of all wells and the zones where background sites are removed (local frame)."""

    sites: np.ndarray  # (k, 2)
    site_well: np.ndarray  # (k,) well id 1..m
    site_size: np.ndarray  # (k,) target size (m) of each site's cell: sqrt of the area it is meant to have
    site_side: np.ndarray  # (k,) bool: a site of a path's side rows (its cell is not the well's)
    disc_centre: np.ndarray  # (w, 2) point wells: centre
    disc_radius: np.ndarray  # (w,) outer ring radius (0 without rings)
    disc_margin: np.ndarray  # (w,) background clearance beyond the outer ring
    disc_well: np.ndarray  # (w,)
    paths: list[PathZone]
    labels: list[str]
    along: np.ndarray  # (a, 2, 2) the steps of the well paths
    along_well: np.ndarray  # (a,) their well ids: the free cells they run through become that well's
    on_fault_well: np.ndarray  # (f,) ids of the point wells with no site (on or next to a fault trace)
    on_fault_point: np.ndarray  # (f, 2) their points
    on_fault_side: np.ndarray  # (f,) their fault_side: +1 left, -1 right, 0 the nearer side

    @property
    def count(self) -> int:
        return len(self.labels)

    @property
    def cell_well(self) -> np.ndarray:
        """The well id of every site's cell: 0 for the side rows."""
        return np.where(self.site_side, 0, self.site_well)


def well_label(well: Well, i: int) -> str:
    return f"well {well.name or f'W{i + 1}'!r} (wells[{i}])"


def build_wells(
    wells: Sequence[Well],
    domain: Domain,
    size: Callable,
    fault_room: Callable[[np.ndarray], tuple[np.ndarray, list[str], np.ndarray]] | None = None,
    notes: list[str] | None = None,
) -> WellSites:
    """Sites of all wells (local frame).

    ``fault_room(points)`` gives, for every point, how far (m) a well's sites may reach
    from it and stay clear of the fault circles, the limiting fault's label and its
    distance (m). A point well's rings reaching farther are shrunk (same inner radius and
    growth, fewer rings), or dropped if not even the first ring fits; a path's sites with
    no room (on or next to a trace) are dropped: the fault cells there become the well's, as
    does every free cell the path runs through (``along``). ``notes`` says so.
    """
    sites, site_well = [np.zeros((0, 2))], [np.zeros(0, dtype=np.int64)]
    site_size, site_side = [np.zeros(0)], [np.zeros(0, dtype=bool)]
    dc, dr, dm, dw = [], [], [], []
    paths: list[PathZone] = []
    along: list[np.ndarray] = [np.zeros((0, 2, 2))]
    along_well: list[np.ndarray] = [np.zeros(0, dtype=np.int64)]
    labels = []
    on_fault: list[tuple[int, np.ndarray, int]] = []
    for i, well in enumerate(wells):  # loop over wells
        if not isinstance(well, Well):
            raise GridError(f"wells[{i}]: expected a Well, got {type(well).__name__}")
        label = well_label(well, i)
        labels.append(label)
        if (well.point is None) == (well.path is None):
            raise GridError(f"{label}: give either a point or a path")
        if well.fault_side not in FAULT_SIDES:
            raise GridError(f"{label}: fault_side must be 'left', 'right' or None, got {well.fault_side!r}")
        if well.fault_side is not None and well.point is None:
            raise GridError(
                f"{label}: fault_side applies to a vertical well (point) on a fault, not to a path"
            )
        if well.point is not None:
            xy, sizes, c, radius, h = _point_well_sites(well, label, domain, size, fault_room, notes)
            if xy.shape[0] == 0:  # on or next to a fault: one of the fault's cells is the well's
                on_fault.append((i + 1, c, FAULT_SIDES[well.fault_side]))
            sites.append(xy)
            site_well.append(np.full(xy.shape[0], i + 1))
            site_size.append(sizes)
            site_side.append(np.zeros(xy.shape[0], dtype=bool))
            dc.append(c)
            dr.append(radius)
            dm.append(0.5 * h)
            dw.append(i + 1)
        else:
            ps, ps_size, side, side_size, steps, zone = _path_well_sites(
                well, i + 1, label, domain, size, fault_room, notes
            )
            along.append(steps)
            along_well.append(np.full(steps.shape[0], i + 1))
            sites += [ps, side]
            site_well.append(np.full(ps.shape[0] + side.shape[0], i + 1))
            site_size += [ps_size, side_size]
            site_side += [np.zeros(ps.shape[0], dtype=bool), np.ones(side.shape[0], dtype=bool)]
            paths.append(zone)
    empty = np.zeros((0, 2))
    return WellSites(
        sites=np.concatenate(sites),
        site_well=np.concatenate(site_well),
        site_size=np.concatenate(site_size),
        site_side=np.concatenate(site_side),
        disc_centre=np.asarray(dc).reshape(-1, 2) if dc else empty,
        disc_radius=np.asarray(dr, dtype=np.float64),
        disc_margin=np.asarray(dm, dtype=np.float64),
        disc_well=np.asarray(dw, dtype=np.int64),
        paths=paths,
        labels=labels,
        along=np.concatenate(along),
        along_well=np.concatenate(along_well),
        on_fault_well=np.array([w for w, _, _ in on_fault], dtype=np.int64),
        on_fault_point=np.array([c for _, c, _ in on_fault], dtype=np.float64).reshape(-1, 2),
        on_fault_side=np.array([side for _, _, side in on_fault], dtype=np.int64),
    )


def _point_well_sites(well: Well, label: str, domain: Domain, size: Callable, fault_room, notes):
    """The sites of a vertical well: its centre and its rings (shrunk to the room the faults
    leave), their target sizes, the centre (local frame), the outer radius (0 without rings)
    and the cell size there. No sites (and no rings) for a well with no room at all from a fault
    (its site would fall into the fault's circles): a fault cell is its cell instead."""
    p = _points(well.point, label, "point").reshape(-1)
    if p.size != 2:
        raise GridError(f"{label}: point must be one (x, y) pair, got {well.point!r}")
    c = domain.to_local(p)
    if not domain.inside(c[None, :])[0]:
        raise GridError(f"{label}: its point ({p[0]:.6g}, {p[1]:.6g}) lies outside the domain")
    if well.spacing is not None:
        raise GridError(f"{label}: spacing applies to well paths; a point well has rings")
    h = float(size(c[None, :])[0])
    pts = [c[None, :]]
    sizes = [np.array([h])]
    radius = 0.0
    limit = None if fault_room is None else fault_room(c)  # room (m), the fault limiting it, its distance
    on_fault = limit is not None and float(limit[0][0]) < 0
    if well.rings is not None:
        if not isinstance(well.rings, Rings):
            raise GridError(f"{label}: rings must be a Rings, got {type(well.rings).__name__}")
        r0 = well.rings
        outer_guess = r0.outer
        if r0.sectors is not None:
            if not (isinstance(r0.sectors, int | np.integer) and r0.sectors >= 3):
                raise GridError(f"{label}: rings.sectors must be an integer >= 3, got {r0.sectors!r}")
            sectors = int(r0.sectors)
        else:
            if outer_guess is None:
                probe = r0.radii(16, f"{label}: rings")
                outer_guess = float(probe[-1])
            sectors = max(6, int(np.round(2 * np.pi * outer_guess / h)))
        radii = r0.radii(sectors, f"{label}: rings")
        if limit is not None and not on_fault:
            room, by, dist = limit
            radii = _fit_rings(radii, float(room[0]), by[0], float(dist[0]), label, notes)
    if on_fault:
        return np.zeros((0, 2)), np.zeros(0), c, radius, h
    if well.rings is not None and radii.size:
        theta = float(r0.angle) + 2 * np.pi * np.arange(sectors) / sectors
        ring = radii[:, None, None] * np.stack([np.cos(theta), np.sin(theta)], axis=-1)[None]
        ring = ring.reshape(-1, 2) + c
        inside = domain.covers(ring)
        if not inside.all():
            raise GridError(
                f"{label}: its rings (outer radius {radii[-1]:.6g} m) reach outside the domain "
                f"near {domain.fmt(ring[np.flatnonzero(~inside)[0]])}; "
                "reduce rings.outer or move the well"
            )
        pts.append(ring)
        sizes = _ring_sizes(radii, sectors, h)
        radius = float(radii[-1])
    return np.concatenate(pts), np.concatenate(sizes), c, radius, h


def _path_well_sites(well: Well, wid: int, label: str, domain: Domain, size: Callable, fault_room, notes):
    """The sites of a well path (:mod:`.path_sites`): the sites on it (those with no room next to
    a fault dropped) and their target sizes, its side rows (those outside the domain, next to its
    boundary or to a fault dropped) and theirs, the path's steps (the free cells they run through
    become the well's: the fault cells where its sites were dropped) and the zone where
    background sites are removed."""
    if well.rings is not None:
        raise GridError(f"{label}: rings apply to a vertical well (point), not to a path")
    graph = path_graph(_path_pieces(well.path, label, domain), domain.tol, label)
    spacing = None if well.spacing is None else _positive(well.spacing, f"{label}: spacing")
    n, node_step = segment_steps(graph, spacing, size)
    rows = path_rows(graph, n, node_step)
    ps, ps_size, side, side_size = rows.on_path, rows.on_size, rows.side, rows.side_size
    ok = domain.inside(side)
    ok[ok] = domain.boundary_distance(side[ok]) >= EDGE * side_size[ok]
    side, side_size = side[ok], side_size[ok]
    probes = ps
    if fault_room is not None:  # sites on or next to a fault trace: the fault's cells serve
        clear = fault_room(side)[0] >= 0
        side, side_size = side[clear], side_size[clear]
        room, by, _ = fault_room(ps)
        gone = room < 0
        if gone.any():
            names = ", ".join(dict.fromkeys(b for b, g in zip(by, gone.tolist(), strict=True) if g))
            (notes if notes is not None else []).append(
                f"{label}: {int(gone.sum())} of its {ps.shape[0]} sites would lie in the circles of "
                f"{names}; the fault cells it runs through there are the well's"
            )
            ps, ps_size = ps[~gone], ps_size[~gone]
    along = steps_of(graph, n)
    s_max = float(np.max(rows.on_size))
    h = float(np.max(size(probes)))
    zone = PathZone(wid, graph.geometry, probes, 0.5 * s_max, band(s_max, h), clearance(s_max, h))
    return ps, ps_size, side, side_size, along, zone


def _path_pieces(value: object, label: str, domain: Domain) -> list[np.ndarray]:
    """The pieces of a well's ``path`` in the local frame: one polyline (n, 2), or a sequence of
    polylines and points ((k, 2) each, k >= 1), each inside the domain."""
    try:
        arr = np.asarray(value, dtype=np.float64)
        raw = [arr] if arr.ndim == 2 else list(arr) if arr.ndim == 3 else [arr]
    except (TypeError, ValueError):  # pieces of different lengths
        raw = list(value) if isinstance(value, Sequence) and not isinstance(value, str) else [value]
    pieces = []
    for j, piece in enumerate(raw):  # loop over the pieces of one well
        what = f"path[{j}]" if len(raw) > 1 else "path"
        xy = _points(piece, label, what)
        if xy.ndim != 2 or xy.shape[0] == 0:
            raise GridError(f"{label}: {what} must be (x, y) points, shape (n, 2), got {np.shape(piece)}")
        xy = domain.to_local(xy)
        out = ~domain.covers(xy)
        line = shapely.LineString(xy) if xy.shape[0] > 1 else shapely.Point(xy[0])
        if out.any() or not line.within(domain.polygon.buffer(domain.tol)):
            k = int(np.flatnonzero(out)[0]) if out.any() else 0
            raise GridError(f"{label}: the {what} leaves the domain (near {domain.fmt(xy[k])})")
        pieces.append(xy)
    return pieces


def _fit_rings(
    radii: np.ndarray, max_outer: float, fault: str, distance: float, label: str, notes: list[str] | None
) -> np.ndarray:
    """Ring radii (m) no larger than ``max_outer``: the same inner radius and growth, fewer rings,
    the last exactly at ``max_outer``; none if not even the first ring fits. Noted."""
    if radii[-1] <= max_outer:
        return radii
    if notes is None:
        notes = []
    if radii[0] > max_outer:
        notes.append(
            f"{label}: rings dropped (one cell at the well): {fault} runs {distance:.3g} m away, so "
            f"even the first ring (radius {radii[0]:.3g} m) would reach into its circles"
        )
        return np.zeros(0)
    growth = float(radii[1] / radii[0]) if radii.size > 1 else max_outer / float(radii[0])
    count = int(np.round(log(max_outer / radii[0]) / log(growth))) + 1 if growth > 1 else 1
    fitted = np.geomspace(radii[0], max_outer, count) if count > 1 else radii[:1].copy()
    notes.append(
        f"{label}: rings shrunk to outer radius {fitted[-1]:.3g} m (from {radii[-1]:.3g} m; {fitted.size} "
        f"of {radii.size} rings) to keep clear of {fault}, {distance:.3g} m away"
    )
    return fitted


def _ring_sizes(radii: np.ndarray, sectors: int, h: float) -> list[np.ndarray]:
    """Target sizes of the centre and of the ring sites: sqrt(arc spacing x radial width).

    A ring cell spans the arc 2 pi r / sectors and, radially, from half way to the
    ring inside to half way to the ring outside (the last ring: as far out as in,
    at most the cell size ``h``); the centre cell is the polygon of inradius r_1 / 2.
    """
    inner = np.concatenate([[0.0], radii[:-1]])
    last = radii[-1] + min(h, radii[-1] - inner[-1])
    outer = np.concatenate([radii[1:], [last]])
    width = 0.5 * (outer - inner)
    arc = 2 * np.pi * radii / sectors
    centre = 0.5 * radii[0] * np.sqrt(sectors * np.sin(np.pi / sectors) / np.cos(np.pi / sectors))
    return [np.array([centre]), np.repeat(np.sqrt(arc * width), sectors)]


def _points(value: object, label: str, what: str) -> np.ndarray:
    try:
        xy = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise GridError(f"{label}: {what} must be (x, y) coordinates, got {value!r:.60}") from exc
    if not np.isfinite(xy).all():
        raise GridError(f"{label}: {what} is not finite")
    if xy.ndim == 2 and xy.shape[1] != 2:
        raise GridError(f"{label}: {what} must have shape (n, 2), got {xy.shape}")
    return xy


def removal_mask(ws: WellSites, pts: np.ndarray, tree: cKDTree) -> np.ndarray:
    """Background points inside a well's clearance zone: a point well's disc, a path's band, the
    surroundings of a side site (``MERGE`` x its step)."""
    gone = np.zeros(pts.shape[0], dtype=bool)
    if ws.disc_centre.shape[0]:
        hits = tree.query_ball_point(ws.disc_centre, ws.disc_radius + ws.disc_margin)
        gone[np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64)] = True
    for z in ws.paths:  # loop over wells
        hits = tree.query_ball_point(z.probes, z.spread + z.band)
        cand = np.unique(np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64))
        if cand.size:
            near = shapely.distance(shapely.points(pts[cand]), z.geometry) < z.band
            gone[cand[near]] = True
    if ws.site_side.any():
        hits = tree.query_ball_point(ws.sites[ws.site_side], MERGE * ws.site_size[ws.site_side])
        gone[np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64)] = True
    return gone


def check_clearances(ws: WellSites) -> None:
    """Wells must keep clear of each other: a point well's rings and clearance from another's,
    a path's clearance (its side rows and a little more, :func:`~.path_sites.clearance`) from
    the others'.

    Wells near or across faults are fine: rings are fitted and paths give the fault cells
    they run through to the well (:func:`build_wells`), and the fault's steps are refined
    where a well's site falls into a fault circle.
    """
    nw = ws.disc_centre.shape[0]
    # point wells vs point wells
    if nw > 1:
        c = ws.disc_centre
        reach = ws.disc_radius + ws.disc_margin
        d = np.linalg.norm(c[:, None, :] - c[None, :, :], axis=2)
        need = np.maximum(ws.disc_radius[:, None] + reach[None, :], reach[:, None] + ws.disc_radius[None, :])
        i, j = np.nonzero(np.triu(d < need, 1))
        if i.size:
            a, b = int(i[0]), int(j[0])
            raise GridError(
                f"{ws.labels[ws.disc_well[a] - 1]} and {ws.labels[ws.disc_well[b] - 1]} are too close: "
                f"{d[a, b]:.4g} m apart, their rings and clearances need {need[a, b]:.4g} m"
            )
    # paths vs point wells and paths vs paths
    for k, z in enumerate(ws.paths):  # loop over wells
        if nw:
            dist = shapely.distance(shapely.points(ws.disc_centre), z.geometry)
            bad = dist < ws.disc_radius + np.maximum(ws.disc_margin, z.clearance)
            if bad.any():
                a = int(np.flatnonzero(bad)[0])
                raise GridError(
                    f"{ws.labels[z.well - 1]} and {ws.labels[ws.disc_well[a] - 1]} are too close: "
                    f"{dist[a]:.4g} m apart"
                )
        for z2 in ws.paths[k + 1 :]:
            dd = float(shapely.distance(z.geometry, z2.geometry))
            if dd < z.clearance + z2.clearance:
                raise GridError(
                    f"{ws.labels[z.well - 1]} and {ws.labels[z2.well - 1]} are too close: {dd:.4g} m apart, "
                    f"they need {z.clearance + z2.clearance:.4g} m"
                )
