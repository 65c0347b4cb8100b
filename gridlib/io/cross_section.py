"""The cross-section of a case (``{case}_section.png``): its cells cut by a vertical section,
coloured by a property, with the faults and the wells near the section.

Where the section runs (:func:`default_section`), unless the case gives it
(``pictures.section``, a polyline in plan view):

* through the wells: each well's point where it reaches the grid's depth range (a vertical
  well's point; a deviated well's first point in that range, else its head), in order along
  their principal direction (the major axis of their spread), extended at both ends along the
  end segments to the grid's bounding box in plan view;
* through a single well: along the longer side of the grid's bounding box;
* without wells: through the centre of the bounding box along its longer side (the stage
  falls back on this line too where the line through the wells cuts no cell).

The picture (:func:`section_figure`): the cut cells (:mod:`gridlib.io.section_cut`) as
polygons in (distance along the section, depth) coloured by porosity (else zone, else layer,
else depth) with thin dark edges (the layers show), the faults as lines in their colours
(:func:`gridlib.io.picture_style.fault_colour`) with their names, the wells that come within a
cell size of the section projected onto it (black lines, named), depth increasing downwards,
and a vertical exaggeration of 1, 2 or 5 x 10^k, 10 where the section is long enough (at most
half the section's length over its thickness), stated on the picture. The section's ends are
marked A and A' above it, as on the plan view, and its bends by dotted lines.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..grid import Grid
from . import picture_style as style
from .section_cut import SectionCut, clip_parts, cut_grid
from .well_tracks import WellTrack

MAX_EXAGGERATION = 10.0
EXAGGERATION = "vertical exaggeration"
FAULT_NAME = style.FAULT_NAME
WELL_NAME = "well name"
OUTLINED_POLYGONS = 20000  # polygons drawn with their edges up to this many
MARGINS = style.SECTION_MARGINS  # inches of a section's figure beside and above/below its axes
MAX_HEIGHT = 8.0  # inches


def well_heads(wells: Sequence[WellTrack], depths: tuple[float, float]) -> np.ndarray:
    """(n, 2) each well's point where its main path first reaches the ``depths`` range (a
    vertical well's point), else its head; duplicates dropped, in the wells' order."""
    heads = []
    for well in wells:
        xyz = well.paths[0]
        inside = np.flatnonzero((xyz[:, 2] >= depths[0]) & (xyz[:, 2] <= depths[1]))
        heads.append(xyz[inside[0], :2] if inside.size and not well.vertical else well.head)
    if not heads:
        return np.zeros((0, 2))
    points = np.array(heads, dtype=np.float64)
    _, first = np.unique(points, axis=0, return_index=True)
    return points[np.sort(first)]


def default_section(heads: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The default section line (see the module's docstring) through the points ``heads``
    ((n, 2)) in the plan-view box ``lo``..``hi`` ((2,) each).

    >>> default_section(np.zeros((0, 2)), np.array([0.0, 0.0]), np.array([4.0, 2.0])).tolist()
    [[0.0, 1.0], [4.0, 1.0]]
    >>> default_section(np.array([[3.0, 1.0], [1.0, 1.0]]), np.zeros(2), np.array([4.0, 2.0])).tolist()
    [[0.0, 1.0], [1.0, 1.0], [3.0, 1.0], [4.0, 1.0]]
    """
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    if heads.shape[0] < 2:
        through = heads[0] if heads.shape[0] else 0.5 * (lo + hi)
        axis = int(np.argmax(hi - lo))
        a, b = through.copy(), through.copy()
        a[axis], b[axis] = lo[axis], hi[axis]
        return np.array([a, b])
    d = heads - heads.mean(axis=0)
    sxx, syy, sxy = (d[:, 0] * d[:, 0]).sum(), (d[:, 1] * d[:, 1]).sum(), (d[:, 0] * d[:, 1]).sum()
    major = 0.5 * (sxx + syy) + np.sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy)
    axis = (
        np.array([sxy, major - sxx]) if abs(sxy) > 0 else np.array([1.0, 0.0] if sxx >= syy else [0.0, 1.0])
    )
    ordered = heads[np.argsort(d[:, 0] * axis[0] + d[:, 1] * axis[1], kind="stable")]
    start = _to_box(ordered[0], ordered[0] - ordered[1], lo, hi)
    end = _to_box(ordered[-1], ordered[-1] - ordered[-2], lo, hi)
    line = np.vstack([start, ordered, end])
    keep = np.r_[True, (np.diff(line, axis=0) != 0).any(axis=1)]
    return line[keep]


def _to_box(point: np.ndarray, direction: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Where the ray from ``point`` along ``direction`` leaves the box lo..hi (``point`` itself
    if it is outside already)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        steps = np.where(
            direction > 0, (hi - point) / direction, np.where(direction < 0, (lo - point) / direction, np.inf)
        )
    step = float(np.min(steps))
    return point if not np.isfinite(step) or step <= 0 else point + step * direction


def exaggeration(length: float, thickness: float) -> float:
    """The vertical exaggeration: 1, 2 or 5 x 10^k, at most :data:`MAX_EXAGGERATION` and at
    most half ``length`` over ``thickness``, at least 1.

    >>> exaggeration(3000.0, 100.0), exaggeration(7000.0, 1400.0), exaggeration(4.0, 4.0)
    (10.0, 2.0, 1.0)
    """
    if thickness <= 0:
        return 1.0
    return max(1.0, min(MAX_EXAGGERATION, style.nice_length(0.5 * length / thickness)))


def section_figure(
    grid: Grid,
    line: np.ndarray,
    *,
    length_unit: str,
    values: np.ndarray,
    quantity: tuple[str, str | None],
    categorical: bool = False,
    fault_names: Sequence[str] = (),
    wells: Sequence[WellTrack] = (),
    cell_size: float = 0.0,
    title: str = "",
    cut: SectionCut | None = None,
):
    """The section of the 3-D ``grid`` along ``line`` ((k, 2) plan view) as a matplotlib
    figure (see the module's docstring): cells coloured by ``values`` (per cell; ``quantity``
    their name and unit; ``categorical``: integers such as zones, one colour each), faults
    named by ``fault_names[id - 1]``, the ``wells`` within ``cell_size`` of the line. ``cut``:
    the section's cut if computed already. Raises ValueError where the line cuts no cell."""
    from matplotlib.collections import LineCollection, PolyCollection

    cut = cut_grid(grid, line) if cut is None else cut
    if cut.cells.size == 0:
        raise ValueError("the section cuts no cell of the grid")
    fig, ax = style.new_figure("section")
    polygons = np.split(cut.points, cut.pos[1:-1])
    shown = np.asarray(values)[cut.cells]
    cmap, norm, ticks = _colours(shown, categorical, "depth" if quantity[0] == "depth" else "property")
    cells = PolyCollection(polygons, array=shown, cmap=cmap, norm=norm)
    cells.set_edgecolor("#333333" if cut.cells.size <= OUTLINED_POLYGONS else "face")
    cells.set_linewidth(0.25)
    ax.add_collection(cells)
    style.colour_bar(fig, ax, cells, *quantity, ticks=ticks, downward=quantity[0] == "depth")
    if cut.fault_ids.size:
        faults = LineCollection(cut.fault_lines, colors=style.fault_colours(cut.fault_ids), linewidths=2.2)
        ax.add_collection(faults)
    s_lo, s_hi = float(cut.points[:, 0].min()), float(cut.points[:, 0].max())
    z_lo, z_hi = float(cut.points[:, 1].min()), float(cut.points[:, 1].max())
    _name_faults(ax, cut, fault_names)
    drawn = _draw_wells(ax, wells, line, cut.vertices, (z_lo, z_hi), cell_size)
    z_lo, z_hi = min(z_lo, drawn[0]), max(z_hi, drawn[1])
    pad = 0.05 * (z_hi - z_lo) or 1.0
    ax.set_xlim(min(s_lo, 0.0), max(s_hi, cut.vertices[-1]))
    ax.set_ylim(z_hi + pad, z_lo - pad)  # depth increases downwards
    ve = exaggeration(cut.vertices[-1], z_hi - z_lo + 2 * pad)
    ax.set_aspect(ve, adjustable="box")
    _fit_height(fig, ax, ve)
    _mark_vertices(ax, cut.vertices)
    text = ax.annotate(  # below the axes' right end, clear of the data and of the axis label
        f"vertical exaggeration {ve:g}x",
        (1.0, 0.0),
        xycoords="axes fraction",
        xytext=(0, -34),  # below the tick labels and the axis label's line
        textcoords="offset points",
        ha="right",
        va="top",
        fontsize=style.FONT_SIZE,
    )
    text.set_gid(EXAGGERATION)
    ax.set_xlabel(f"distance along the section [{length_unit}]")
    ax.set_ylabel(f"depth [{length_unit}]")
    ax.set_title(f"{title}: cross-section" if title else "cross-section")
    return fig


def _fit_height(fig, ax, exaggeration: float) -> None:
    """The figure's height fitted to the exaggerated section (:func:`picture_style.fit_figure`:
    a fixed height would leave a long flat section a strip, and crop a steep one), its axes
    placed by :data:`MARGINS`."""
    x0, x1 = ax.get_xlim()
    bottom, top = ax.get_ylim()
    ratio = exaggeration * abs(bottom - top) / max(abs(x1 - x0), np.finfo(float).tiny)
    style.fit_figure(fig, ratio, MARGINS, MAX_HEIGHT)


def _colours(values: np.ndarray, categorical: bool, kind: style.Kind = "property"):
    """The colour map (of ``kind``), norm and colour-bar ticks of the cells' values (one colour
    per integer where ``categorical``)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    if not categorical:
        lo, hi = float(values.min()), float(values.max())
        if hi <= lo:
            lo, hi = lo - 0.5, hi + 0.5
        from matplotlib.colors import Normalize

        return style.colour_map(kind), Normalize(lo, hi), None
    kinds = np.unique(values.astype(np.int64))
    bounds = np.concatenate([kinds - 0.5, [kinds[-1] + 0.5]])
    palette = style.colour_map("category")
    cmap = ListedColormap([palette(k % palette.N) for k in range(kinds.size)])
    steps = np.diff(bounds)
    norm = BoundaryNorm(bounds, cmap.N) if np.all(steps > 0) else None
    return cmap, norm, kinds if kinds.size <= 20 else None


def _name_faults(ax, cut: SectionCut, names: Sequence[str]) -> None:
    """Each fault's name at the shallowest end of its lines, in its colour."""
    for fault in np.unique(cut.fault_ids):
        ends = cut.fault_lines[cut.fault_ids == fault].reshape(-1, 2)
        at = ends[np.argmin(ends[:, 1])]
        style.label_fault(ax, int(fault), at, names, (3, 6))


def _draw_wells(
    ax,
    wells: Sequence[WellTrack],
    line: np.ndarray,
    vertices: np.ndarray,
    depths: tuple[float, float],
    reach: float,
) -> tuple[float, float]:
    """The wells' parts within ``reach`` of the section (and within its extent and the depth
    range ``depths`` widened by a tenth) projected onto it, as black lines, each named at its
    shallowest drawn point (not the wells known in plan view only); returns the depth range
    drawn (``depths`` if none)."""
    from matplotlib.collections import LineCollection

    margin = 0.1 * (depths[1] - depths[0])
    top, bottom = depths[0] - margin, depths[1] + margin
    drawn = depths
    for well in wells:
        if well.plan_only:
            continue
        parts = []
        for xyz in well.paths:
            for j in range(line.shape[0] - 1):
                parts.append(_near(xyz, line[j], line[j + 1], vertices[j], reach, top, bottom))
        segments = np.concatenate(parts) if parts else np.zeros((0, 2, 2))
        if not segments.size:
            continue
        ax.add_collection(LineCollection(segments, colors=style.WELL_COLOUR, linewidths=2.0, zorder=4))
        ends = segments.reshape(-1, 2)
        at = ends[np.argmin(ends[:, 1])]
        drawn = (min(drawn[0], float(ends[:, 1].min())), max(drawn[1], float(ends[:, 1].max())))
        label = ax.annotate(
            well.name,
            at,
            xytext=(0, 6),
            textcoords="offset points",
            ha="center",
            fontsize=style.LABEL_SIZE + 1,
            fontweight="bold",
            bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.7},
            zorder=6,
            annotation_clip=False,
        )
        label.set_gid(WELL_NAME)
    return drawn


def _near(
    xyz: np.ndarray, a: np.ndarray, b: np.ndarray, start: float, reach: float, top: float, bottom: float
) -> np.ndarray:
    """The parts of the polyline ``xyz`` within ``reach`` of the vertical plane a -> b, within
    the segment's extent and between the depths ``top`` and ``bottom``, as (k, 2, 2) segments
    in (distance along the section from ``start``, depth)."""
    length = float(np.hypot(*(b - a)))
    u = (b - a) / length
    rel = xyz[:, :2] - a
    side = rel[:, 0] * -u[1] + rel[:, 1] * u[0]
    along = rel[:, 0] * u[0] + rel[:, 1] * u[1]
    z = xyz[:, 2]
    functions = (reach - side, reach + side, along, length - along, z - top, bottom - z)
    lo, hi = clip_parts([f[:-1] for f in functions], [f[1:] for f in functions])
    keep = lo <= hi
    p = np.column_stack([start + along, z])
    p0, d = p[:-1][keep], np.diff(p, axis=0)[keep]
    return np.stack([p0 + lo[keep, None] * d, p0 + hi[keep, None] * d], axis=1)


def _mark_vertices(ax, vertices: np.ndarray) -> None:
    """The section's start (A) and end (A') above the axes (the plan view marks its line the
    same), its bends as thin dotted lines."""
    from matplotlib.transforms import blended_transform_factory

    at = blended_transform_factory(ax.transData, ax.transAxes)
    for s in vertices[1:-1]:
        ax.axvline(s, color="grey", lw=0.6, ls=":")
    for s, letter in ((vertices[0], "A"), (vertices[-1], "A'")):
        ax.text(
            s,
            1.01,
            letter,
            transform=at,
            ha="center",
            va="bottom",
            fontsize=style.FONT_SIZE,
            fontweight="bold",
        )
