"""The plan view of a case (``{case}_plan.png``): the map a geomodeller checks first.

A 3-D grid's top (:mod:`gridlib.io.top_surface`) is drawn as filled depth contours with
labelled contour lines (levels at round depths inside the top's depth range; a flat top is
one colour), the top faces' outlines where they are few enough to read (under 4000), the
fault traces along the top in each fault's colour with its name, and the wells: a vertical
well as a symbol at its point, a deviated well's path as a line (solid where it is within the
grid's depth range, dashed above or below it) with a symbol where it enters that range, each
named. A 2-D grid's cells are drawn coloured by a property (porosity, else cell area) and its
fault edges as lines. Axes x (east) and y (north) in the case's length unit, equal aspect, a
scale bar, a north arrow and a colour bar titled with the quantity and its unit; the style is
:mod:`gridlib.io.picture_style`'s.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..connectivity import cell_node_cycles_2d
from ..geometry import Geometry
from ..grid import Grid
from . import picture_style as style
from .pictures import depth_window
from .top_surface import TopSurface, face_edges, fault_traces, top_surface
from .well_tracks import WellTrack

OUTLINED_FACES = 4000  # top faces drawn with their outlines up to this many
FAULTS = "faults"
FAULT_NAME = style.FAULT_NAME
WELL_NAME = "well name"
WELL = "well"
SECTION = "section line"


def plan_figure(
    grid: Grid,
    geo: Geometry,
    *,
    length_unit: str,
    fault_names: Sequence[str] = (),
    wells: Sequence[WellTrack] = (),
    values: np.ndarray | None = None,
    quantity: tuple[str, str | None] = ("depth", None),
    title: str = "",
    section: np.ndarray | None = None,
):
    """The plan view of ``grid`` as a matplotlib figure (see the module's docstring).

    ``length_unit``: the label of the grid's length unit (m, ft); ``fault_names[k - 1]`` names
    fault k; ``values`` (per cell) and ``quantity`` (name, unit) colour a 2-D grid's cells (a
    3-D grid's map is its top's depth, in ``length_unit``); ``section``: the cross-section's
    line (k, 2), drawn dashed from A to A'."""
    fig, ax = style.new_figure("plan")
    if grid.griddim == 3:
        top = top_surface(grid, geo)
        mappable, ticks = _depth_map(ax, top)
        style.colour_bar(fig, ax, mappable, "top depth", length_unit, ticks=ticks, downward=True)
        segments, ids = fault_traces(grid, top)
        window = (float(grid.nodes.coords[:, 2].min()), float(grid.nodes.coords[:, 2].max()))
    else:
        mappable = _cell_map(ax, grid, geo.cell_volumes if values is None else values)
        style.colour_bar(fig, ax, mappable, *quantity)
        faults = np.flatnonzero(grid.faces.tag > 0)
        edges, owner = face_edges(grid, faults)
        segments, ids = grid.nodes.coords[edges][:, :, :2], grid.faces.tag[faults[owner]]
        window = None
    xy = grid.nodes.coords[:, :2]
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    margin = 0.04 * float(max(hi - lo))
    ax.set_xlim(lo[0] - margin, hi[0] + margin)
    ax.set_ylim(lo[1] - margin, hi[1] + margin)
    ax.set_aspect("equal")
    # the figure as tall as the map needs (up to its kind's height): no bands of white above
    # and below a wide map
    ratio = (hi[1] - lo[1] + 2 * margin) / (hi[0] - lo[0] + 2 * margin)
    style.fit_figure(fig, float(ratio), style.MAP_MARGINS, style.FIGURE_SIZES["plan"][1])
    draw_faults(ax, segments, ids, fault_names)
    draw_wells(ax, wells, window)
    if section is not None:
        draw_section_line(ax, section)
    ax.set_xlabel(f"x [{length_unit}]")
    ax.set_ylabel(f"y [{length_unit}]")
    ax.set_title(f"{title}: plan view" if title else "plan view")
    lower, upper = free_corners(ax, () if section is None else (section[0], section[-1]))
    style.scale_bar(ax, length_unit, corner=lower)
    style.north_arrow(ax, corner=upper)
    return fig


def contour_levels(zmin: float, zmax: float, bins: int = 12) -> np.ndarray:
    """Round contour levels (1, 2, 2.5 or 5 x 10^k apart, at most ``bins`` + 1) strictly inside
    (``zmin``, ``zmax``).

    >>> contour_levels(1012.0, 1093.0).tolist()
    [1020.0, 1030.0, 1040.0, 1050.0, 1060.0, 1070.0, 1080.0, 1090.0]
    """
    from matplotlib.ticker import MaxNLocator

    ticks = MaxNLocator(nbins=bins, steps=[1, 2, 2.5, 5, 10]).tick_values(zmin, zmax)
    return ticks[(ticks > zmin) & (ticks < zmax)]


def _depth_map(ax, top: TopSurface):
    """Filled contours of the top's depth with labelled lines (one colour where flat), and the
    top faces' outlines where few; returns the mappable of the colour bar and its ticks (the
    one depth of a flat top, else None)."""
    from matplotlib.tri import Triangulation

    x, y, z = top.points.T
    tri = Triangulation(x, y, top.triangles)
    p = top.points[top.triangles]
    twice_area = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (
        p[:, 2, 0] - p[:, 0, 0]
    )
    tri.set_mask(np.abs(twice_area) <= 1e-12 * max(float(np.ptp(x) * np.ptp(y)), 1e-300))
    zmin, zmax = top.depth_range
    levels = contour_levels(zmin, zmax)
    ticks = None
    if zmax - zmin <= 1e-9 * max(abs(zmax), 1.0):
        mappable = ax.tripcolor(tri, z, cmap=style.colour_map("depth"), vmin=zmin - 0.5, vmax=zmax + 0.5)
        ticks = [zmin]
    else:
        fill = np.unique(np.concatenate([[zmin], levels, [zmax]]))
        mappable = ax.tricontourf(tri, z, levels=fill, cmap=style.colour_map("depth"))
        if levels.size:
            lines = ax.tricontour(tri, z, levels=levels, colors="black", linewidths=0.6)
            ax.clabel(lines, fmt="%g", fontsize=style.LABEL_SIZE)
    if top.faces.size <= OUTLINED_FACES:
        edges = top.triangles[:, 1:]  # each fan triangle's outer edge: the face's edge
        style.segment_lines(ax, top.points[edges][:, :, :2], color="white", linewidth=0.3, alpha=0.5)
    return mappable, ticks


def _cell_map(ax, grid: Grid, values: np.ndarray):
    """A 2-D grid's cells coloured by ``values``; returns the collection."""
    from matplotlib.collections import PolyCollection

    pos, nodes = cell_node_cycles_2d(grid)
    xy = grid.nodes.coords[nodes, :2]
    polygons = np.split(xy, pos[1:-1])
    cells = PolyCollection(polygons, array=np.asarray(values), cmap=style.colour_map("property"))
    cells.set_edgecolor("white" if grid.num_cells <= OUTLINED_FACES else "face")
    cells.set_linewidth(0.3)
    ax.add_collection(cells)
    return cells


def draw_faults(ax, segments: np.ndarray, ids: np.ndarray, names: Sequence[str]) -> None:
    """The fault ``segments`` ((n, 2, 2) in the axes' coordinates) in their fault's colour
    (``ids``, 1-based), each fault named (``names[id - 1]``, else "fault <id>") beside its
    segment a third of the way along its trace (not the middle: faults that cross each other
    there keep their names apart)."""
    from matplotlib.collections import LineCollection

    if not ids.size:
        return
    lines = LineCollection(segments, colors=style.fault_colours(ids), linewidths=2.2, zorder=3)
    lines.set_gid(FAULTS)
    ax.add_collection(lines)
    middle = segments.mean(axis=1)
    for fault in np.unique(ids):
        at = along_trace(middle[ids == fault], 1.0 / 3.0)
        style.label_fault(ax, int(fault), at, names, (4, 4), zorder=5)


def draw_wells(ax, wells: Sequence[WellTrack], window: tuple[float, float] | None) -> None:
    """The wells in plan view: a vertical well as a symbol at its point; a deviated well's paths
    as lines, solid within the depth ``window`` (the grid's depth range; None: all solid) and
    dashed outside it, with a symbol where the main path enters the window; each named."""
    from matplotlib.collections import LineCollection

    for well in wells:
        if well.vertical:
            at = well.head
        else:
            at = None
            for k, xyz in enumerate(well.paths):
                ax.plot(xyz[:, 0], xyz[:, 1], color=style.WELL_COLOUR, lw=0.8, ls="--", alpha=0.6, zorder=4)
                inside = (xyz[:, :2], xyz[:, :2]) if window is None else depth_window(xyz, *window)
                a, b = inside[0][:, :2], inside[1][:, :2]
                if a.size:
                    solid = LineCollection(np.stack([a, b], axis=1), colors=style.WELL_COLOUR, linewidths=2.0)
                    ax.add_collection(solid).set_zorder(4)
                    if k == 0:
                        at = a[0]
            at = well.head if at is None else at
        marker = ax.plot(
            *at, marker="o", ms=7, mfc="white", mec=style.WELL_COLOUR, mew=1.8, ls="none", zorder=6
        )[0]
        marker.set_gid(WELL)
        label = ax.annotate(
            well.name,
            at,
            xytext=(6, -10),
            textcoords="offset points",
            fontsize=style.LABEL_SIZE + 1,
            fontweight="bold",
            bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.7},
            zorder=6,
        )
        label.set_gid(WELL_NAME)


def along_trace(points: np.ndarray, fraction: float) -> np.ndarray:
    """The point of ``points`` (n, 2) at ``fraction`` of their extent along their longer axis
    of spread (x or y) (a trace's segment midpoints in no particular order).

    >>> along_trace(np.array([[0.0, 5.0], [3.0, 5.0], [1.0, 5.0], [2.0, 5.0]]), 1 / 3).tolist()
    [1.0, 5.0]
    """
    axis = int(np.argmax(np.ptp(points, axis=0)))
    order = np.argsort(points[:, axis], kind="stable")
    return points[order[round(fraction * (order.size - 1))]]


def draw_section_line(ax, line: np.ndarray) -> None:
    """The cross-section's line dashed, its start marked A and its end A'."""
    (drawn,) = ax.plot(line[:, 0], line[:, 1], color="white", lw=1.4, ls=(0, (6, 3)), zorder=3)
    drawn.set_gid(SECTION)
    for at, letter in ((line[0], "A"), (line[-1], "A'")):
        ax.annotate(
            letter,
            at,
            xytext=(0, 0),
            textcoords="offset points",
            ha="center",
            va="center",
            fontsize=style.LABEL_SIZE + 1,
            fontweight="bold",
            bbox={"boxstyle": "circle,pad=0.15", "facecolor": "white", "edgecolor": "black", "lw": 0.6},
            zorder=6,
        ).set_gid(SECTION)


def free_corners(ax, marks: Sequence[np.ndarray]) -> tuple[str, str]:
    """The lower and the upper corner of the map ``ax`` farthest from the points ``marks``
    (the section's ends, which often lie in corners): where the scale bar and the north arrow
    go (lower left and upper right without marks)."""
    if not len(marks):
        return "lower left", "upper right"
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    at = np.array([[(x - x0) / (x1 - x0), (y - y0) / (y1 - y0)] for x, y in marks])

    def clearance(cx: float, cy: float) -> float:
        return float(np.min(np.hypot(at[:, 0] - cx, at[:, 1] - cy)))

    lower = "lower left" if clearance(0.0, 0.0) >= clearance(1.0, 0.0) else "lower right"
    upper = "upper right" if clearance(1.0, 1.0) >= clearance(0.0, 1.0) else "upper left"
    return lower, upper
