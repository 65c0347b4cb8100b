"""Pictures of a grid, written atomically as PNG: the 3-D view (:func:`render_grid`, pyvista,
:mod:`gridlib.io.grid_view`), histograms of its geometry, porosity and transmissibilities
(matplotlib), and :func:`save_figure` for any matplotlib figure."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..geometry import Geometry
from ..reproducible import log10
from ..units import UnitSystem
from .atomic import write_keeping_suffix
from .grid_view import depth_window, grid_polydata, grid_scene, render_grid
from .picture_style import few_ticks, logarithmic, panel_layout
from .quantities import picture_label

__all__ = [
    "depth_window",
    "grid_polydata",
    "grid_scene",
    "histogram_figure",
    "plot_histograms",
    "render_grid",
    "save_figure",
]


def save_figure(fig, path: str | os.PathLike, dpi: int = 100) -> None:
    """Save a matplotlib figure atomically (PNG by the suffix of ``path``) and close it."""
    import matplotlib.pyplot as plt

    try:
        write_keeping_suffix(path, lambda tmp: fig.savefig(tmp, dpi=dpi))
    finally:
        plt.close(fig)


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
        panels.append((picture_label("poro", units), poro))
    if trans is not None:
        panels.append((f"log10 T, T in {units.unit('transmissibility')}", log10(trans[trans > 0])))
    linear = ("poro", "log10")
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 3.6))
    for ax, (label, values) in zip(np.atleast_1d(axes), panels, strict=True):
        plain = label.startswith(linear)
        v = values if plain else values[np.isfinite(values) & (values > 0)]
        # the bars as one filled outline (ax.stairs), not a rectangle per bin (ax.hist)
        if v.size and not plain and v.max() > 100 * v.min():
            ax.stairs(*np.histogram(v, bins=np.geomspace(v.min(), v.max(), 50)), fill=True)
            logarithmic(ax, "x")
        elif v.size and np.ptp(v) > 1e-9 * np.abs(v).max():
            ax.stairs(*np.histogram(v, bins=50), fill=True)
        else:  # one value (a regular grid): one bar
            ax.bar(
                [float(v[0]) if v.size else 0.0],
                [v.size],
                width=1.0 if not v.size else 0.1 * abs(float(v[0])) or 1.0,
            )
        few_ticks(ax)
        ax.set_xlabel(label)
        ax.set_ylabel("count")
    fig.suptitle(title)
    panel_layout(fig, 1, len(panels))
    return fig
