"""The 3-D view of a case (``{case}.png``): an off-screen pyvista scene of the grid's outer faces
coloured by one cell value, the fault faces in one colour per fault with a legend of their
names, the wells (deviated paths and vertical wells) named, axes with their units (x east, y
north, and depth down the vertical axis) and the vertical exaggeration stated on the picture.

:func:`grid_scene` builds the scene and returns the :class:`pyvista.Plotter` (tests read its
actors: the colour bar's title, the axes' titles, the texts, the well labels, the fault actors);
:func:`render_grid` saves its screenshot atomically.

Orientation: gridlib's z is depth (positive down); the scene's z is the elevation ``-depth``
scaled by the vertical exaggeration (the VTK files' convention, :func:`gridlib.io.vtu.vtk_points`),
and the vertical axis is labelled with depths. The exaggeration is a round number (1, 2, 5 x 10^k)
chosen so that the reservoir's mean thickness (its volume over its plan area) is about a quarter
of its lateral extent, but never so large that the depth range (a dipping reservoir's) exceeds
1.2 times that extent: SPE9, 359 ft thick over 7,500 ft and dipping 1,600 ft, gets 5x.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..connectivity import cell_node_cycles_2d, offsets, ragged_arange
from ..grid import Grid
from .atomic import write_keeping_suffix
from .picture_style import fault_colour
from .well_tracks import WellTrack

WINDOW = (1400, 900)  # pixels
_THICKNESS_FRACTION = 0.25  # target: exaggerated thickness / lateral extent
_MAX_DEPTH_RANGE = 1.2  # cap: exaggerated depth range / lateral extent


def grid_polydata(grid: Grid, values: np.ndarray, name: str):
    """What a picture shows, as VTK PolyData with ``values`` as cell data: the outer boundary
    faces of a 3-D grid (coloured by the cell inside; far smaller than the polyhedra), their
    nodes all ordered the same way about the outward normal, so that they close a consistently
    oriented surface whose enclosed volume is the grid's; or the cells of a 2-D grid as
    polygons. Coordinates are gridlib's (z depth)."""
    import pyvista as pv

    if grid.griddim == 3:
        nb = grid.faces.neighbors
        faces = np.flatnonzero((nb < 0).any(axis=1))
        owner = nb[faces].max(axis=1)
        counts = np.diff(grid.faces.node_pos)[faces]
        # a face's nodes turn about its normal from neighbors[0] to neighbors[1]: reversed where
        # the cell is neighbors[1], every polygon turns about the outward normal (a closed surface)
        local = ragged_arange(np.zeros(faces.size, np.int64), counts)
        inward = np.repeat(nb[faces, 0] < 0, counts)
        local = np.where(inward, np.repeat(counts - 1, counts) - local, local)
        nodes = grid.faces.nodes[np.repeat(grid.faces.node_pos[:-1][faces], counts) + local]
    else:
        pos, nodes = cell_node_cycles_2d(grid)
        counts, owner = np.diff(pos), np.arange(grid.num_cells)
    used, local = np.unique(nodes, return_inverse=True)
    coords = grid.nodes.coords[used]
    if coords.shape[1] == 2:
        coords = np.column_stack([coords, np.zeros(coords.shape[0])])
    cells = np.insert(local.reshape(-1), offsets(counts)[:-1], counts).astype(np.int64)
    mesh = pv.PolyData(coords, faces=cells)
    mesh.cell_data[name] = np.asarray(values)[owner]
    return mesh


def nice_floor(value: float) -> float:
    """The largest of 1, 2, 5 x 10^k not above ``value`` (1 for values below 1).

    >>> nice_floor(5.2), nice_floor(19.9), nice_floor(0.3), nice_floor(1000.0)
    (5.0, 10.0, 1.0, 1000.0)
    """
    if not value >= 1.0 or not math.isfinite(value):
        return 1.0
    decade = float(10 ** decimal_exponent(value))
    return next(m * decade for m in (5.0, 2.0, 1.0) if m * decade <= value)


def vertical_exaggeration(lateral: float, thickness: float, depth_range: float) -> float:
    """The view's vertical exaggeration (a round number, >= 1): the mean ``thickness`` about a
    quarter of the ``lateral`` extent, the ``depth_range`` at most 1.2 times it (module docstring).

    >>> vertical_exaggeration(7500.0, 359.0, 1609.0)  # SPE9, ft
    5.0
    >>> vertical_exaggeration(1000.0, 500.0, 500.0)
    1.0
    """
    if thickness <= 0 or depth_range <= 0:
        return 1.0
    return nice_floor(
        min(_THICKNESS_FRACTION * lateral / thickness, _MAX_DEPTH_RANGE * lateral / depth_range)
    )


def label_format(spans: Sequence[float]) -> str:
    """The axes' label format (VTK's, Python-like): as many decimals as a fifth of the
    smallest positive span needs.

    >>> label_format([7200.0, 7500.0, 1609.0]), label_format([1.0, 2.0])
    ('{0:.0f}', '{0:.1f}')
    """
    positive = [s for s in spans if s > 0]
    step = min(positive) / 5 if positive else 1.0
    return f"{{0:.{max(0, -decimal_exponent(step))}f}}"


def decimal_exponent(value: float) -> int:
    """The exponent k of a positive ``value`` = m x 10^k with 1 <= m < 10 (from its decimal
    representation: exact, no logarithm).

    >>> decimal_exponent(1000.0), decimal_exponent(999.9), decimal_exponent(0.05)
    (3, 2, -2)
    """
    return int(f"{value:.15e}".split("e")[1])


def grid_scene(
    grid: Grid,
    values: np.ndarray,
    faults,
    *,
    scalar: str,
    title: str,
    bar_title: str | None = None,
    length_unit: str = "m",
    wells: Sequence[WellTrack] = (),
    fault_colours: Sequence | None = None,
    window_size: tuple[int, int] = WINDOW,
):
    """The 3-D scene of ``grid`` coloured by ``values`` (per cell, named ``scalar``), as an
    off-screen :class:`pyvista.Plotter` ready for a screenshot.

    ``faults``: the fault faces (``{case}_faults.vtp`` or its PolyData: z elevation, cell data
    ``fault`` the 1-based fault id, field data ``fault_names``), each fault in its colour
    (``fault_colours[id - 1]``, any matplotlib colour; default
    :func:`~gridlib.io.picture_style.fault_colour`, as in every picture of the case) with a
    legend of names. ``bar_title``: the colour bar's title, the quantity and its unit (default
    ``scalar``). ``length_unit``: the case's length unit, on the axes. ``wells``: drawn as black
    lines where they are within half the grid's depth range of it, named at the top of their
    main path there; the grid is then half transparent so that the paths show.

    Actors are named for tests: ``grid``, ``fault <name>``, ``well <name>``, ``well labels``,
    ``title``, ``exaggeration``; the colour bar is ``plotter.scalar_bars[bar_title]``, the axes
    ``plotter.renderer.cube_axes_actor`` and the legend ``plotter.legend``."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkLogger

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)  # no X server here: VTK falls back, noisily
    pv.OFF_SCREEN = True
    mesh = grid_polydata(grid, values, scalar)
    faults = pv.read(faults) if isinstance(faults, str | Path) else faults
    flat = grid.griddim == 2 or float(np.ptp(mesh.points[:, 2])) == 0.0
    exaggeration = 1.0 if flat else _exaggeration(mesh)
    scale = np.array([1.0, 1.0, -exaggeration])  # depth to exaggerated elevation
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    # No multisample anti-aliasing: VTK renders off screen in software (Mesa's llvmpipe), where
    # pyvista's default of 8 samples took a third of the picture's CPU (0.12 of 0.37 s for 1,300
    # cells) for edges a pixel smoother at 1400 x 900; the lines drawn are 3 to 4 pixels wide.
    plotter.disable_anti_aliasing()
    plotter.set_background("white")
    bar_title = bar_title or scalar
    plotter.add_mesh(
        mesh.scale(scale, inplace=False),
        scalars=scalar,
        show_edges=grid.num_cells < 60_000,
        edge_color="#404040",
        cmap="viridis",
        scalar_bar_args=_bar_args(bar_title),
        opacity=0.45 if wells else 1.0,
        name="grid",
    )
    bar = plotter.scalar_bars[bar_title]
    bar.SetVerticalTitleSeparation(14)  # pixels between the title and the top label
    bar.UnconstrainedFontSizeOn()  # the fonts' sizes as given, not shrunk to the bar's width
    _add_faults(plotter, faults, exaggeration, fault_colours)
    bounds = mesh.bounds
    _add_wells(plotter, wells, scale, (float(bounds[4]), float(bounds[5])))
    plotter.add_text(title, position=(12, window_size[1] - 40), font_size=14, color="black", name="title")
    if not flat:
        plotter.add_text(
            f"vertical exaggeration {exaggeration:g}x",
            position=(12, 12),
            font_size=11,
            color="black",
            name="exaggeration",
        )
    _add_axes(plotter, bounds, scale, length_unit, flat)
    if flat:
        plotter.view_xy()
    else:  # from the south-east, 25 degrees above the horizon: sides and layers show
        plotter.view_vector((0.55, -0.85, 0.47), viewup=(0.0, 0.0, 1.0))
        plotter.reset_camera()
        plotter.camera.zoom(0.95)
    return plotter


def _exaggeration(mesh) -> float:
    """:func:`vertical_exaggeration` of the boundary ``mesh`` (gridlib coordinates): its
    thickness the enclosed volume over the area of its plan's bounding box."""
    span = np.ptp(mesh.points, axis=0)
    lateral = float(max(span[0], span[1], 1e-12))
    area = float(max(span[0] * span[1], 1e-24))
    volume = abs(float(mesh.triangulate().volume))
    return vertical_exaggeration(lateral, volume / area, float(span[2]))


def _bar_args(bar_title: str) -> dict:
    """A vertical colour bar at the right with its title above it (never over its labels), five
    labels of three significant digits."""
    return {
        "title": bar_title,
        "vertical": True,
        "position_x": 0.86,
        "position_y": 0.2,
        "width": 0.05,
        "height": 0.6,
        "n_labels": 5,
        "fmt": "%.3g",
        "title_font_size": 16,
        "label_font_size": 14,
        "color": "black",
    }


def _add_faults(plotter, faults, exaggeration: float, colours: Sequence | None) -> None:
    """Each fault's faces (cell data ``fault``, 1-based ids) in its own colour, with a legend
    of the fault names (field data ``fault_names``)."""
    if not faults.n_cells:
        return
    from matplotlib.colors import to_hex

    names = [str(n) for n in np.asarray(faults.field_data.get("fault_names", []))]
    ids = (
        np.asarray(faults.cell_data["fault"]) if "fault" in faults.cell_data else np.ones(faults.n_cells, int)
    )
    present = np.unique(ids[ids > 0])
    scaled = faults.scale((1.0, 1.0, exaggeration), inplace=False)  # the file stores elevation
    entries = []
    for fid in present:
        name = names[fid - 1] if 0 < fid <= len(names) and names[fid - 1] else f"fault {fid}"
        colour = to_hex(colours[(fid - 1) % len(colours)]) if colours else fault_colour(int(fid))
        part = scaled.extract_cells(np.flatnonzero(ids == fid))
        plotter.add_mesh(part, color=colour, line_width=3, opacity=0.85, name=f"fault {name}")
        entries.append([name, colour])
    plotter.add_legend(
        entries, bcolor="white", border=True, loc="upper left", size=(0.16, 0.05 * len(entries))
    )


def _add_axes(plotter, bounds, scale: np.ndarray, length_unit: str, flat: bool) -> None:
    """Axes around the grid: x and y in ``length_unit``, the vertical axis labelled with depths
    (the scene's z is the exaggerated elevation; VTK labels an increasing range only, so the
    axis gets the elevations' labels negated)."""
    from pyvista.plotting.cube_axes_actor import make_axis_labels

    x0, x1, y0, y1, d0, d1 = (float(b) for b in bounds)
    fmt = label_format([x1 - x0, y1 - y0] + ([] if flat else [d1 - d0]))
    axes = plotter.show_bounds(
        bounds=[x0, x1, y0, y1, d1 * scale[2], d0 * scale[2]],
        axes_ranges=[x0, x1, y0, y1, -d1, -d0],
        xtitle=f"x (east) [{length_unit}]",
        ytitle=f"y (north) [{length_unit}]",
        ztitle=f"depth [{length_unit}]",
        show_zaxis=not flat,
        n_xlabels=4,
        n_ylabels=4,
        n_zlabels=3,
        fmt=fmt,
        location="outer",
        color="black",
        font_size=11,
        use_3d_text=False,
    )
    if not flat:
        elevations = make_axis_labels(vmin=-d1, vmax=-d0, n=3, fmt=fmt)
        depths = type(elevations)()
        for k in range(elevations.GetNumberOfValues()):
            depths.InsertNextValue(fmt.format(-float(elevations.GetValue(k))))
        axes.SetAxisLabels(2, depths)


def render_grid(path: str | Path, grid: Grid, values: np.ndarray, faults, **options) -> None:
    """:func:`grid_scene` saved as the PNG ``path``, atomically."""
    plotter = grid_scene(grid, values, faults, **options)
    try:
        write_keeping_suffix(Path(path), lambda p: plotter.screenshot(str(p)))
    finally:
        plotter.close()


def _add_wells(plotter, wells: Sequence[WellTrack], scale: np.ndarray, depths: tuple[float, float]) -> None:
    """The wells' paths as black lines where they are within half the grid's thickness of its
    depth range ``depths`` (the hole down to the reservoir would dwarf it), each well named at
    the top of the drawn part of its main path."""
    import pyvista as pv

    top, bottom = depths
    margin = 0.5 * (bottom - top)
    heads, names = [], []
    for well in wells:
        for k, xyz in enumerate(well.paths):
            a, b = depth_window(np.asarray(xyz, dtype=np.float64), top - margin, bottom + margin)
            if not a.size:
                continue
            points = np.empty((2 * a.shape[0], 3))
            points[0::2], points[1::2] = a, b
            cells = np.column_stack(
                [np.full(a.shape[0], 2), np.arange(0, points.shape[0], 2), np.arange(1, points.shape[0], 2)]
            )
            plotter.add_mesh(
                pv.PolyData(points * scale, lines=cells.ravel()),
                color="black",
                line_width=4,
                name=f"well {well.name}" + (f" branch {k}" if k else ""),
            )
            if k == 0:
                heads.append(a[0] * scale)
                names.append(well.name)
    if heads:
        plotter.add_point_labels(
            np.array(heads),
            names,
            font_size=14,
            point_size=8,
            always_visible=True,
            shape_opacity=0.6,
            name="well labels",
        )


def depth_window(xyz: np.ndarray, top: float, bottom: float) -> tuple[np.ndarray, np.ndarray]:
    """The parts of the polyline ``xyz`` (n, 3; z depth) between the depths ``top`` and
    ``bottom``, as the start and end points (k, 3) of its segments' parts there, in order.

    >>> a, b = depth_window(np.array([[0.0, 0, 0], [0, 0, 100], [100, 0, 100]]), 50.0, 200.0)
    >>> a.tolist(), b.tolist()
    ([[0.0, 0.0, 50.0], [0.0, 0.0, 100.0]], [[0.0, 0.0, 100.0], [100.0, 0.0, 100.0]])
    """
    from ..voronoi.areal import clip_segments  # shapely only where wells are drawn

    z = xyz[:, 2]
    lo, hi, keep, _ = clip_segments(z - top, bottom - z)
    p, d = xyz[:-1][keep], np.diff(xyz, axis=0)[keep]
    return p + lo[keep, None] * d, p + hi[keep, None] * d
