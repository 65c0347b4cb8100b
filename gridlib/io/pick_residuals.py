"""The horizon-pick residuals picture (``{case}_residuals.png``): per horizon given by picks, a
map of the picks coloured by their residual (pick depth minus the interpolated surface's depth
there, :mod:`gridlib.horizons.residuals`) on a diverging colour map centred on 0 (blue: the
pick is shallower than the surface, red: deeper), with the fault traces, a scale bar and a
north arrow, and beside it the residuals' histogram with their RMS and largest magnitude.

The residuals are stored in ``horizons.nc`` by the horizons stage (variables ``pick_*``);
:func:`~gridlib.io.horizon_files.read_pick_residuals` reads them back. Units are the
horizons' (metres); x is east and y north.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from ..horizons.residuals import PickResiduals, residual_figures

__all__ = ["plot_pick_residuals", "read_pick_residuals", "residuals_figure"]
from .horizon_files import read_pick_residuals
from .picture_style import (
    FIGURE_SIZES,
    MAP_MARGINS,
    colour_bar,
    colour_map,
    fault_colour,
    north_arrow,
    panel_layout,
    picture_style,
    quantity_label,
    scale_bar,
)
from .pictures import save_figure

ROW_HEIGHT = 4.2  # inches per horizon
# Inches: a map's (MAP_MARGINS) at the left and below, its colour bar and the histogram's
# count labels between the two columns; the figure's title and a row's titles above each row.
MARGINS = {**MAP_MARGINS, "right": 0.55, "top": 0.75, "across": MAP_MARGINS["right"] + 0.8, "down": 1.0}


def residuals_figure(
    residuals: PickResiduals,
    names: Sequence[str],
    *,
    title: str = "",
    length_unit: str = "m",
    faults: Sequence[tuple[str, np.ndarray]] = (),
):
    """A matplotlib figure of the residuals: one row per horizon with picks, the map (picks
    coloured by residual, the colour norm symmetric about 0 and common to every row, the
    ``faults``' traces (name, (n, 2) x, y) in their colours and named, axes in
    ``length_unit``, a scale bar and a north arrow) and the histogram (residual in
    ``length_unit``, count of picks, 0 marked), its title the horizon's number of picks, RMS
    and largest |residual|. Raises ValueError without picks."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    horizons = np.unique(residuals.horizon)
    if horizons.size == 0:
        raise ValueError("no picks: a residuals picture needs horizons given by points")
    res = residuals.residual
    figures = residual_figures(residuals, names)
    finite = np.abs(res[np.isfinite(res)])
    bound = float(finite.max()) if finite.size and finite.max() > 0 else 1.0
    norm = Normalize(-bound, bound)  # symmetric about 0: white is a pick on its surface
    label = quantity_label("residual", length_unit)
    width = FIGURE_SIZES["residuals"][0]
    with picture_style():
        fig, axes = plt.subplots(
            horizons.size,
            2,
            figsize=(width, ROW_HEIGHT * horizons.size),
            squeeze=False,
            gridspec_kw={"width_ratios": (1.3, 1.0)},
        )
        panel_layout(fig, horizons.size, 2, MARGINS)
        for row, k in enumerate(horizons):
            mine = residuals.horizon == k
            name = str(names[k])
            f = figures[name]
            _map(fig, axes[row, 0], residuals, mine, norm, name, label, length_unit, faults)
            _histogram(axes[row, 1], res[mine], label, name, f, length_unit)
        if title:
            fig.suptitle(title)
    return fig


def plot_pick_residuals(
    path: str | os.PathLike, residuals: PickResiduals, names: Sequence[str], **options
) -> None:
    """:func:`residuals_figure` saved as the PNG ``path``, atomically."""
    save_figure(residuals_figure(residuals, names, **options), path)


def _map(fig, ax, residuals: PickResiduals, mine, norm, name: str, label: str, unit: str, faults) -> None:
    """The picks of one horizon coloured by residual, the fault traces, scale bar, north arrow."""
    r = residuals.residual[mine]
    defined = np.isfinite(r)
    x, y = residuals.x[mine], residuals.y[mine]
    points = ax.scatter(
        x[defined],
        y[defined],
        c=r[defined],
        cmap=colour_map("diverging"),
        norm=norm,
        s=16,
        edgecolors="0.55",  # a pick on its surface is white: outlined
        linewidths=0.3,
    )
    points.set_gid("picks")
    if not defined.all():  # where the surface is undefined: grey crosses
        ax.scatter(x[~defined], y[~defined], marker="x", s=14, color="0.5", label="surface undefined")
        ax.legend(loc="lower right", fontsize="small")
    for fid, (fault, trace) in enumerate(faults, start=1):
        xy = np.asarray(trace, dtype=np.float64)
        ax.plot(xy[:, 0], xy[:, 1], color=fault_colour(fid), lw=2, gid=f"fault {fault}")
        ax.annotate(
            fault,
            _halfway(xy),
            color=fault_colour(fid),
            fontweight="bold",
            xytext=(4, 0),
            textcoords="offset points",
        )
    ax.set_xlim(x.min(), x.max())
    ax.set_ylim(y.min(), y.max())
    ax.margins(0.03)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(f"x (east) [{unit}]")
    ax.set_ylabel(f"y (north) [{unit}]")
    ax.set_title(f"{name}: residual at each pick")
    colour_bar(fig, ax, points, "residual", unit)
    scale_bar(ax, unit)
    north_arrow(ax)


def _histogram(ax, r: np.ndarray, label: str, name: str, figures, unit: str) -> None:
    """The residuals' histogram of one horizon, 0 marked, its RMS and max in the title."""
    defined = r[np.isfinite(r)]
    ax.hist(defined, bins=min(50, max(10, defined.size // 10)), color="0.35")
    ax.axvline(0.0, color="black", lw=1)
    ax.set_xlabel(f"{label} (pick depth - surface depth)")
    ax.set_ylabel("picks")
    rms, largest = figures["rms"], figures["max_abs"]
    ax.set_title(f"{name}: {figures['picks']} picks, RMS {rms:.3g} {unit}, max |r| {largest:.3g} {unit}")


def _halfway(xy: np.ndarray) -> np.ndarray:
    """The point halfway along the polyline ``xy`` (n, 2), where a trace is named."""
    along = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
    half = 0.5 * along[-1]
    return np.array([np.interp(half, along, xy[:, 0]), np.interp(half, along, xy[:, 1])])
