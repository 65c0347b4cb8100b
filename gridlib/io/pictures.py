"""Pictures of a grid, written atomically as PNG: an off-screen rendering coloured by one cell
value with the fault faces in red and the deviated wells' paths in black (pyvista), histograms
of its geometry, porosity and transmissibilities (matplotlib), and :func:`save_figure` for any
matplotlib figure."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..connectivity import cell_node_cycles_2d, offsets, ragged_arange
from ..geometry import Geometry
from ..grid import Grid
from ..reproducible import log10
from ..units import UnitSystem
from .atomic import write_keeping_suffix


def save_figure(fig, path: str | os.PathLike, dpi: int = 100) -> None:
    """Save a matplotlib figure atomically (PNG by the suffix of ``path``) and close it."""
    import matplotlib.pyplot as plt

    try:
        write_keeping_suffix(path, lambda tmp: fig.savefig(tmp, dpi=dpi))
    finally:
        plt.close(fig)


def grid_polydata(grid: Grid, values: np.ndarray, name: str):
    """What a picture shows, as VTK PolyData with ``values`` as cell data: the outer boundary
    faces of a 3-D grid (coloured by the cell inside; far smaller than the polyhedra), or the
    cells of a 2-D grid as polygons."""
    import pyvista as pv

    if grid.griddim == 3:
        nb = grid.faces.neighbors
        faces = np.flatnonzero((nb < 0).any(axis=1))
        owner = nb[faces].max(axis=1)
        counts = np.diff(grid.faces.node_pos)[faces]
        nodes = grid.faces.nodes[ragged_arange(grid.faces.node_pos[:-1][faces], counts)]
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


def render_grid(
    path: Path,
    grid: Grid,
    values: np.ndarray,
    faults_vtp: Path,
    scalar: str,
    title: str,
    bar_title: str | None = None,
    wells: Sequence[tuple[str, Sequence[np.ndarray]]] = (),
) -> None:
    """An off-screen picture of the grid coloured by ``scalar``, fault faces in red; the colour
    bar titled ``bar_title`` (the quantity and its unit; default ``scalar``). ``wells``: (name,
    paths) of deviated wells, each path an (n, 3) polyline (x, y, z depth), drawn as black lines
    near the grid, named where their main path comes into the picture; the grid is then drawn
    half transparent, so that the paths inside it show."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkLogger

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)  # no X server here: VTK falls back, noisily
    pv.OFF_SCREEN = True
    griddim = grid.griddim
    mesh = grid_polydata(grid, values, scalar)
    faults = pv.read(faults_vtp)
    span = np.ptp(mesh.points, axis=0)
    lateral = max(span[0], span[1], 1e-12)
    # z is depth: flip it for the picture, and exaggerate thin reservoirs to a third of their width.
    exaggeration = 1.0 if griddim == 2 or span[2] == 0 else max(1.0, 0.3 * lateral / span[2])
    scale = (1.0, 1.0, -exaggeration)
    plotter = pv.Plotter(off_screen=True, window_size=(1200, 800))
    plotter.add_mesh(
        mesh.scale(scale, inplace=False),
        scalars=scalar,
        show_edges=grid.num_cells < 60_000,
        cmap="viridis",
        scalar_bar_args={"title": bar_title or scalar},
        opacity=0.45 if wells else 1.0,
    )
    if faults.n_cells:
        # the faults' file stores elevation (vtk_points): only the exaggeration is left to apply
        plotter.add_mesh(
            faults.scale((1.0, 1.0, exaggeration), inplace=False), color="red", line_width=3, opacity=0.8
        )
    _add_wells(plotter, wells, scale, (float(mesh.bounds[4]), float(mesh.bounds[5])))
    plotter.add_text(title, font_size=12)
    if griddim == 2 or span[2] == 0:
        plotter.view_xy()
    else:
        plotter.view_isometric()
    write_keeping_suffix(path, lambda p: plotter.screenshot(str(p)))
    plotter.close()


def _add_wells(
    plotter,
    wells: Sequence[tuple[str, Sequence[np.ndarray]]],
    scale: tuple[float, ...],
    depths: tuple[float, float],
) -> None:
    """The wells' paths as black lines where they are within half the grid's thickness of its
    depth range ``depths`` (the hole down to the reservoir would dwarf it), each well named at
    the top of the drawn part of its main path."""
    import pyvista as pv

    top, bottom = depths
    margin = 0.5 * (bottom - top)
    heads, names = [], []
    for name, paths in wells:
        for k, xyz in enumerate(paths):
            a, b = depth_window(np.asarray(xyz, dtype=np.float64), top - margin, bottom + margin)
            if not a.size:
                continue
            points = np.empty((2 * a.shape[0], 3))
            points[0::2], points[1::2] = a, b
            cells = np.column_stack(
                [np.full(a.shape[0], 2), np.arange(0, points.shape[0], 2), np.arange(1, points.shape[0], 2)]
            )
            plotter.add_mesh(
                pv.PolyData(points * np.asarray(scale), lines=cells.ravel()), color="black", line_width=4
            )
            if k == 0:
                heads.append(a[0] * np.asarray(scale))
                names.append(name)
    if heads:
        plotter.add_point_labels(
            np.array(heads), names, font_size=14, point_size=8, always_visible=True, shape_opacity=0.6
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


def plot_histograms(
    path: Path,
    geo: Geometry,
    poro: np.ndarray | None,
    griddim: int,
    title: str,
    units: UnitSystem,
    trans: np.ndarray | None = None,
) -> None:
    """:func:`histogram_figure` saved as ``path``."""
    save_figure(histogram_figure(geo, poro, griddim, title, units, trans), path)


def histogram_figure(
    geo: Geometry,
    poro: np.ndarray | None,
    griddim: int,
    title: str,
    units: UnitSystem,
    trans: np.ndarray | None = None,
):
    """A matplotlib figure: histograms of cell volumes, face areas, porosity and, with
    ``trans``, log10 T; every axis labelled with its unit in ``units`` (the case's unit system,
    that of the values); logarithmic axes where values span more than two decades."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cell, face = ("cell volume", "face area") if griddim == 3 else ("cell area", "face length")
    panels = [(f"{cell} [{units.unit('cell_measure', griddim)}]", geo.cell_volumes)]
    panels.append((f"{face} [{units.unit('face_measure', griddim)}]", geo.face_areas))
    if poro is not None:
        panels.append((f"porosity [{units.unit('fraction')}]", poro))
    if trans is not None:
        panels.append((f"log10 T, T in {units.unit('transmissibility')}", log10(trans[trans > 0])))
    linear = ("poro", "log10")
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 3.6))
    for ax, (label, values) in zip(np.atleast_1d(axes), panels, strict=True):
        plain = label.startswith(linear)
        v = values if plain else values[np.isfinite(values) & (values > 0)]
        if v.size and not plain and v.max() > 100 * v.min():
            ax.hist(v, bins=np.geomspace(v.min(), v.max(), 50))
            ax.set_xscale("log")
        elif v.size and np.ptp(v) > 1e-9 * np.abs(v).max():
            ax.hist(v, bins=50)
        else:  # one value (a regular grid): one bar
            ax.bar(
                [float(v[0]) if v.size else 0.0],
                [v.size],
                width=1.0 if not v.size else 0.1 * abs(float(v[0])) or 1.0,
            )
        ax.set_xlabel(label)
        ax.set_ylabel("count")
    fig.suptitle(title)
    fig.tight_layout()
    return fig
