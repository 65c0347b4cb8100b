"""``{case}_quality.png``: histograms of a grid's cell-quality measures with the case's qc limits.

One panel per measure of :data:`gridlib.quality.MEASURES` that varies over the cells where it
is defined (a measure that is NaN everywhere, or one value everywhere, says nothing as a
histogram and is left out (:func:`varies`), unless a qc rule names it and it is defined somewhere), in the
order of ``MEASURES``. Each x axis names the measure and its unit (``maxangle_sides [degree]``,
``aspect_ratio [1]``; a flag has none); the count axis is logarithmic where the tallest bar is more than 100
times the lowest non-empty one (a few bad cells beside thousands of good ones stay visible).
A flag (collapsed, faulted, negative_thickness, concave_proj) is a bar per value. Each qc
rule on a measure is a vertical dashed line at its limit, labelled with the rule and the
number of cells past the limit in the legend (``warn max 60: 12 cells past it``; orange warn,
red fail). Sizes and fonts are gridlib's one picture style (:mod:`gridlib.io.picture_style`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..quality import MEASURES
from .picture_style import (
    DPI,
    FIGURE_SIZES,
    few_ticks,
    logarithmic,
    panel_layout,
    picture_style,
    quantity_label,
)
from .pictures import save_figure
from .quality_file import FLAGS, measure_units

ACTION_COLOURS = {"warn": "tab:orange", "fail": "tab:red"}
COLUMNS = 4


def plot_quality(
    path: str | os.PathLike,
    values: Mapping[str, np.ndarray],
    rules: Sequence[Mapping[str, Any]],
    title: str,
) -> None:
    """:func:`quality_figure` saved as ``path`` (atomically)."""
    save_figure(quality_figure(values, rules, title), path, dpi=DPI)


def shown_measures(values: Mapping[str, np.ndarray], rules: Sequence[Mapping[str, Any]] = ()) -> list[str]:
    """The measures a panel shows: those of ``values`` that vary over their defined cells, and
    those a rule names that are defined somewhere; in the order of ``MEASURES``."""
    ruled = {r["quantity"] for r in rules}
    out = []
    for m in MEASURES:
        v = values.get(m.name)
        if v is None:
            continue
        finite = v[np.isfinite(v)]
        if finite.size and (varies(finite) or m.name in ruled):
            out.append(m.name)
    return out


def varies(v: np.ndarray) -> bool:
    """The finite values ``v`` span more than round-off: 1e-9 of their magnitude, at least 1e-9
    (a PEBI grid's orientation errors of 1e-10 degree are one value, 0)."""
    return bool(np.ptp(v) > 1e-9 * max(1.0, float(np.abs(v).max())))


def quality_figure(values: Mapping[str, np.ndarray], rules: Sequence[Mapping[str, Any]], title: str):
    """A matplotlib figure in gridlib's picture style (:mod:`gridlib.io.picture_style`): a
    histogram per shown measure (:func:`shown_measures`) with the qc limits of ``rules`` drawn
    on it; a figure with one line of text where no measure varies."""
    with picture_style():
        return _figure(values, rules, title)


def _figure(values: Mapping[str, np.ndarray], rules: Sequence[Mapping[str, Any]], title: str):
    import matplotlib.pyplot as plt

    names = shown_measures(values, rules)
    units = {m.name: measure_units(m) for m in MEASURES}
    width, height = FIGURE_SIZES["histograms"]
    if not names:
        fig, ax = plt.subplots(figsize=(width, 0.5 * height))
        ax.axis("off")
        ax.text(0.5, 0.5, "no quality measure varies over this grid", ha="center", va="center")
        fig.suptitle(title)
        return fig
    rows = -(-len(names) // COLUMNS)
    cols = min(COLUMNS, len(names))
    fig = plt.figure(figsize=(width * cols, height * rows))
    axes = [fig.add_subplot(rows, cols, k + 1) for k in range(len(names))]  # not the empty cells'
    panel_layout(fig, rows, cols)
    for ax, name in zip(axes, names, strict=True):
        v = values[name]
        v = v[np.isfinite(v)]
        label = quantity_label(name, units[name])
        (_flag_panel if name in FLAGS else _panel)(ax, v, label)
        few_ticks(ax)
        for rule in rules:
            if rule["quantity"] != name:
                continue
            bound = "max" if "max" in rule else "min"
            limit, action = float(rule[bound]), str(rule["action"])
            past = int(np.count_nonzero(v > limit if bound == "max" else v < limit))
            ax.axvline(
                limit,
                color=ACTION_COLOURS[action],
                linestyle="--",
                linewidth=1.5,
                label=f"{action} {bound} {limit:g}: {past:,d} cells past it",
            )
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize="small", loc="best")
    fig.suptitle(f"{title}: cell quality")
    return fig


def _flag_panel(ax, v: np.ndarray, label: str) -> None:
    """A flag's cells per value (0, 1, ...; a bar each, also for a value no cell has), x
    labelled ``label``, the count axis logarithmic where it spans more than two decades."""
    top = max(1, int(v.max()))
    counts = np.bincount(v.astype(np.int64), minlength=top + 1)
    ax.bar(np.arange(top + 1), counts, width=0.6, color="tab:blue")
    ax.set_xticks(np.arange(top + 1))
    ax.set_xlim(-0.5, top + 0.5)
    nonzero = counts[counts > 0]
    if nonzero.size and nonzero.max() > 100 * nonzero.min():
        logarithmic(ax, "y")
    ax.set_xlabel(label)
    ax.set_ylabel("cells")


def _panel(ax, v: np.ndarray, label: str) -> None:
    """One histogram of the values ``v`` (finite), x labelled ``label``, the count axis
    logarithmic where the bars span more than two decades."""
    if varies(v):
        counts, edges = np.histogram(v, bins=50)
        ax.stairs(counts, edges, fill=True, color="tab:blue")  # one artist, not 50 bars
    else:  # one value (a rule names the measure): one bar
        width = 0.1 * abs(float(v[0])) or 1.0
        counts = np.array([v.size])
        ax.bar([float(v[0])], [v.size], width=width, color="tab:blue")
    nonzero = counts[counts > 0]
    if nonzero.size and nonzero.max() > 100 * nonzero.min():
        logarithmic(ax, "y")
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 4), useOffset=False)  # 1e-3 as x 1e-3
    ax.set_xlabel(label)
    ax.set_ylabel("cells")
