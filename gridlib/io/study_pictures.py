"""Pictures of a study, drawn from its Dataset (``study.nc``: one dimension per varied key plus
``realisation``, and ``time`` in days for the simulated series; every variable's ``units``
attribute): pure functions returning matplotlib figures in gridlib's style
(:mod:`gridlib.io.picture_style`).

* :func:`study_figure` (``study.png``): each chosen figure (rows) against each varied key
  (columns). One line per combination of the OTHER varied keys' values (its legend names them
  with their units): every realisation a point, their mean a line through the key's values,
  their spread (min to max) a vertical segment at each value. A segment joins realisations of
  one combination only: it never spans values of another key. In a zipped study
  (``combine: zip``) the other keys move with the key: one line.
* :func:`profiles_figure` (``study_profiles.png``): field oil rate, water cut and pressure over
  time, one line per variant, coloured by its value of the varied key (one row of panels per
  key).
* :func:`tornado_figure` (``study_tornado.png``): each key's swing of oil recovery
  (:func:`tornado_swings` states the definition).

Failed simulations (``simulation == "failed"``) are left out of every line and mean, never
drawn as zero: a red cross at the bottom of a panel marks the key value of each failed variant
(:data:`FAILED`), and the profiles' panels say how many were left out. Grid figures of a failed
variant are drawn (its grid was built).

Axes: a key's label is ``key [unit]`` as study.csv's header, a figure's its name and unit
(``fraction`` for a unit of 1, as :func:`gridlib.io.quantities.picture_quantity`). Values are
written in full, never with a floating offset ("1e7" above a panel): where they are large or
small, the power of ten is in the axis label in plain text (``pore volume [10⁶ m3]``) and the
ticks are scaled, the plotted data stay the table's values. Artists carry a ``gid``
(:data:`MEAN`, :data:`REALISATIONS`, :data:`SPREAD`, :data:`FAILED`, :data:`TORNADO_LOW`,
:data:`TORNADO_HIGH`, :data:`BASE`) for tests and readers.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .picture_style import LABEL_SIZE, colour_map, picture_style, power_of_ten_label

# The figures study.png draws against every varied key, those the study has: its simulated
# responses (and each well's water breakthrough day WBT:<well>) when it simulates, else the grid's.
GRID_FIGURES = ("cells", "fault_connections", "pore_volume", "mean_porosity", "median_trans")
RESPONSES = ("oil_recovery", "FOPT", "FWPT", "FPR")
BREAKTHROUGH = "WBT:"
PROFILES = ("FOPR", "FWCT", "FPR")
TORNADO_RESPONSE = "oil_recovery"

MEAN = "mean"
REALISATIONS = "realisations"
SPREAD = "spread"
FAILED = "failed"
TORNADO_LOW = "tornado lowest value"
TORNADO_HIGH = "tornado highest value"
BASE = "base"
FAILED_COLOUR = "#d62728"
LOW_COLOUR = "#0072B2"
HIGH_COLOUR = "#D55E00"
PANEL = (4.2, 2.9)  # inches per panel
DODGE = 4.0  # points between the lines of one panel (drawn offset, data unchanged)


def varied_keys(ds) -> list[str]:
    """The study's varied keys, in the study's order (the Dataset's ``varied_keys``)."""
    return list(json.loads(ds.attrs["varied_keys"]))


def simulates(ds) -> bool:
    """Whether the study's variants were simulated (study.nc has ``simulation``)."""
    return "simulation" in ds.data_vars


def unit_of(ds, name: str) -> str | None:
    """The unit of variable or coordinate ``name`` (``units``, else ``units_by_unit_system``)."""
    attrs = ds[name].attrs
    return attrs.get("units") or attrs.get("units_by_unit_system") or None


def key_label(ds, key: str) -> str:
    """A varied key's axis label as study.csv's header: ``faults.0.throw [m]``."""
    unit = unit_of(ds, key)
    return f"{key} [{unit}]" if unit else key


def figure_title(ds, name: str) -> tuple[str, str | None]:
    """What a picture calls variable ``name`` (underscores as spaces; summary keys as they are)
    and its unit (``fraction`` for 1)."""
    unit = unit_of(ds, name)
    return name.replace("_", " "), ("fraction" if unit == "1" else unit)


def chosen_figures(ds) -> list[str]:
    """The figures study.png draws: :data:`RESPONSES` and each well's WBT when the study
    simulates, else :data:`GRID_FIGURES`; those with a number for some variant."""
    if simulates(ds):
        names = [*RESPONSES, *sorted(str(n) for n in ds.data_vars if str(n).startswith(BREAKTHROUGH))]
    else:
        names = list(GRID_FIGURES)
    return [
        n
        for n in names
        if n in ds.data_vars
        and "time" not in ds[n].dims
        and _numeric(ds[n])
        and np.isfinite(ds[n].values).any()
    ]


def series_name(ds, name: str) -> str | None:
    """The study.nc variable of response ``name`` over ``time`` (``name`` itself, or
    ``<name>_series`` where a scalar of the same name holds its value at the end), or None."""
    for candidate in (name, f"{name}_series"):
        if candidate in ds.data_vars and "time" in ds[candidate].dims:
            return candidate
    return None


def _numeric(da) -> bool:
    return np.issubdtype(da.dtype, np.number)


def variants_frame(ds, names: Sequence[str]):
    """One row per variant of the study (a zipped study's missing combinations left out): the
    varied keys, ``realisation``, ``variant``, ``simulation`` ("" without) and ``names``."""
    keys = varied_keys(ds)
    wanted = ["variant", *(["simulation"] if simulates(ds) else []), *names]
    frame = ds[list(dict.fromkeys(wanted))].to_dataframe().reset_index()
    frame = frame[frame["variant"].astype(str) != ""].reset_index(drop=True)
    if "simulation" not in frame:
        frame["simulation"] = ""
    return frame[[*keys, "realisation", *dict.fromkeys(["variant", "simulation", *names])]]


def key_values(frame, key: str) -> list[Any]:
    """The key's distinct values among the variants, sorted."""
    return sorted(frame[key].unique().tolist())


def numeric(values: Sequence[Any]) -> bool:
    """Whether a key's values are numbers (else labels: whole sections, names)."""
    return all(isinstance(v, int | float | np.number) and not isinstance(v, bool) for v in values)


def positions(values: Sequence[Any]) -> np.ndarray:
    """x positions of a key's values: the numbers themselves, else their order."""
    if numeric(values):
        return np.asarray(values, dtype=float)
    return np.arange(len(values), dtype=float)


def value_text(value: Any, unit: str | None) -> str:
    """``30 m``, ``0.5`` (no unit), ``pebi``: a key's value as a legend writes it."""
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    return f"{value} {unit}" if unit and unit != "1" else str(value)


def power_of_ten(values: np.ndarray) -> int:
    """The power of ten (a multiple of 3) an axis of ``values`` writes in its label: 0 for
    magnitudes from 1e-3 to under 1e5 (written in full), else the largest magnitude's exponent
    rounded down to a multiple of 3.

    >>> [power_of_ten(np.array(v)) for v in ([1.5e7, 2e6], [4668.0, 11706.0], [2e-5])]
    [6, 0, -6]
    """
    finite = np.abs(values[np.isfinite(values)])
    if finite.size == 0 or finite.max() == 0:
        return 0
    exponent = int(f"{finite.max():e}".split("e")[1])  # exact, no log10
    return 0 if -3 <= exponent < 5 else 3 * (exponent // 3)


def label_axis(axis, title: str, unit: str | None, values: np.ndarray) -> None:
    """Label ``axis`` (an Axis) ``title [unit]`` and write its ticks in full: no offset; where
    :func:`power_of_ten` is k != 0, the ticks divided by 10^k and ``10^k`` in the label."""
    from matplotlib.ticker import FuncFormatter

    k = power_of_ten(np.asarray(values, dtype=float))
    scale = float(f"1e{k}")
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v / scale:g}"))
    power = power_of_ten_label(scale) if k else ""  # plain text: no mathtext parsed per figure
    unit_part = " ".join(p for p in (power, unit) if p)
    axis.set_label_text(f"{title} [{unit_part}]" if unit_part else title)


@dataclass(frozen=True)
class Line:
    """The variants of one line of a study.png panel: the other keys' values (``fixed``; empty
    for a one-key or zipped study) and the rows of the variants (a DataFrame)."""

    fixed: tuple[tuple[str, Any], ...]
    rows: Any


def lines_of(frame, keys: Sequence[str], key: str, combine: str) -> list[Line]:
    """The lines of ``key``'s panels: one per combination of the other keys' values (sorted);
    one line of every variant when the study zips its keys or varies one."""
    others = [k for k in keys if k != key]
    if combine == "zip" or not others:
        return [Line((), frame)]
    return [
        Line(tuple(zip(others, (group if isinstance(group, tuple) else (group,)), strict=True)), rows)
        for group, rows in frame.groupby(others, sort=True)
    ]


def line_statistics(rows, key: str, figure: str, values: Sequence[Any]) -> tuple[np.ndarray, ...]:
    """Mean, min and max of ``figure`` over the realisations of ``rows`` (one line) at each of
    ``values`` of ``key``; failed simulations and missing values left out (NaN where none)."""
    mean, low, high = (np.full(len(values), np.nan) for _ in range(3))
    for i, value in enumerate(values):
        y = _good(rows[rows[key] == value], figure)
        if y.size:
            mean[i], low[i], high[i] = y.mean(), y.min(), y.max()
    return mean, low, high


def _good(rows, figure: str) -> np.ndarray:
    """``figure``'s finite values over ``rows``, failed simulations left out for a response."""
    if figure not in GRID_FIGURES:
        rows = rows[rows["simulation"] != "failed"]
    y = rows[figure].to_numpy(dtype=float)
    return y[np.isfinite(y)]


def _legend_text(ds, line: Line, realisations: int) -> str:
    if not line.fixed:
        return f"mean of {realisations} realisations" if realisations > 1 else "variants"
    return ", ".join(f"{k} = {value_text(v, unit_of(ds, k))}" for k, v in line.fixed)


def _draw_line(ax, line: Line, key: str, figure: str, values, xs, where, style: dict) -> None:
    """One line of a study.png panel: its realisations as points, their mean through the key's
    values, their spread (min to max) as a segment at each value; drawn ``style["dodge"]``
    points sideways (the data stay the table's values)."""
    from matplotlib.transforms import ScaledTranslation

    mean, low, high = line_statistics(line.rows, key, figure, values)
    good = line.rows if figure in GRID_FIGURES else line.rows[line.rows["simulation"] != "failed"]
    colour = style["colour"]
    artists = [
        *ax.plot(
            [where[v] for v in good[key]],
            good[figure].to_numpy(dtype=float),
            "o",
            ms=3.5,
            alpha=0.7,
            color=colour,
            gid=REALISATIONS,
        ),
        *ax.plot(xs, mean, "-", lw=1.4, color=colour, gid=MEAN, label=style["label"]),
    ]
    if style["spread"]:
        has = np.isfinite(low)
        artists.append(ax.vlines(xs[has], low[has], high[has], color=colour, lw=1.0, gid=SPREAD))
    # shifted after the axes took the data's limits (a shifted transform at creation would
    # leave the data out of them)
    shift = ScaledTranslation(style["dodge"] / 72, 0, ax.figure.dpi_scale_trans)
    for artist in artists:
        artist.set_transform(ax.transData + shift)


def _mark_failed(ax, failed, key: str, where) -> None:
    """A red cross at the bottom of ``ax`` at the key's value of each failed variant."""
    from matplotlib.transforms import blended_transform_factory

    if len(failed):
        ax.plot(
            [where[v] for v in failed[key]],
            np.full(len(failed), 0.03),
            "x",
            ms=7,
            mew=1.8,
            color=FAILED_COLOUR,
            transform=blended_transform_factory(ax.transData, ax.transAxes),
            clip_on=False,
            gid=FAILED,
            label="failed simulation (left out)",
        )


def _legend_columns(texts: Sequence[str]) -> int:
    """As many legend columns as entries of ``texts`` fit across a panel (about 60 characters
    of the legend's font), at least one."""
    widest = max((len(t) for t in texts), default=1) + 6  # the handle and the gap
    return max(1, min(len(texts), 60 // widest))


def study_figure(ds):
    """study.png: :func:`chosen_figures` (rows) against each varied key (columns), one line per
    combination of the other keys (see the module's docstring); returns the figure."""
    import matplotlib.pyplot as plt

    keys = varied_keys(ds)
    figures = chosen_figures(ds)
    frame = variants_frame(ds, figures)
    realisations = int(frame["realisation"].nunique())
    combine = str(ds.attrs.get("combine", "product"))
    failed = frame[frame["simulation"] == "failed"]
    with picture_style():
        fig, axes = plt.subplots(
            max(len(figures), 1),
            len(keys),
            figsize=(max(PANEL[0] * len(keys), 6.0), PANEL[1] * max(len(figures), 1) + 0.8),
            squeeze=False,
            layout="constrained",
        )
        for j, key in enumerate(keys):
            values = key_values(frame, key)
            xs = positions(values)
            where = dict(zip(values, xs, strict=True))
            lines = lines_of(frame, keys, key, combine)
            colours = colour_map("property")(np.linspace(0.0, 0.85, len(lines)))
            for i, figure in enumerate(figures):
                ax = axes[i][j]
                for n, line in enumerate(lines):
                    style = {
                        "colour": colours[n],
                        "label": _legend_text(ds, line, realisations),
                        "dodge": (n - (len(lines) - 1) / 2) * DODGE,
                        "spread": realisations > 1,
                    }
                    _draw_line(ax, line, key, figure, values, xs, where, style)
                if figure not in GRID_FIGURES:
                    _mark_failed(ax, failed, key, where)
                slanted = {} if numeric(values) else {"rotation": 30, "ha": "right"}  # labels
                ax.set_xticks(xs, [value_text(v, None) for v in values], **slanted)
                ax.margins(x=0.08)
                ax.set_xlabel(key_label(ds, key))  # ticks: the values as text, no offset
                title, unit = figure_title(ds, figure)
                label_axis(ax.yaxis, title, unit, frame[figure].to_numpy(dtype=float))
                ax.grid(True, lw=0.4, alpha=0.5)
            if not figures:  # every simulation failed: nothing to draw, and a panel says so
                axes[0][j].set_xlabel(key_label(ds, key))
                axes[0][j].text(
                    0.5, 0.5, f"no responses: {len(failed)} failed simulations", ha="center",
                    transform=axes[0][j].transAxes, color=FAILED_COLOUR, gid=FAILED,
                )  # fmt: skip
            handles, texts = axes[0][j].get_legend_handles_labels()
            unique = dict(zip(texts, handles, strict=True))
            axes[0][j].legend(
                unique.values(),
                unique.keys(),
                loc="lower center",
                bbox_to_anchor=(0.5, 1.02),
                fontsize=LABEL_SIZE,
                frameon=False,
                ncols=_legend_columns(list(unique)),
            )
        spread = "\npoints: realisations, bars: their min to max" if realisations > 1 else ""
        fig.suptitle(f"study {ds.attrs.get('study', '')}: {len(frame)} variants{spread}")
    return fig


def _days(time) -> np.ndarray:
    """A time coordinate in days (decoded timedeltas or numbers of days)."""
    values = np.asarray(time)
    if np.issubdtype(values.dtype, np.timedelta64):
        return values / np.timedelta64(1, "D")
    return values.astype(float)


def profiles_figure(ds):
    """study_profiles.png: :data:`PROFILES` (columns) over time, every simulated variant a line
    coloured by its value of the varied key of the row (a legend per row names the values);
    failed variants left out (each panel says how many). Returns the figure."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    keys = varied_keys(ds)
    names = [n for n in (series_name(ds, p) for p in PROFILES) if n is not None]
    frame = variants_frame(ds, [])
    days = _days(ds["time"])
    failed = int((frame["simulation"] == "failed").sum())
    with picture_style():
        fig, axes = plt.subplots(
            len(keys),
            max(len(names), 1),
            figsize=(PANEL[0] * max(len(names), 1) + 1.6, PANEL[1] * len(keys)),
            squeeze=False,
            layout="constrained",
        )
        for i, key in enumerate(keys):
            values = key_values(frame, key)
            colours = dict(
                zip(values, colour_map("property")(np.linspace(0.0, 0.9, len(values))), strict=True)
            )
            for j, name in enumerate(names):
                ax = axes[i][j]
                for _, row in frame[frame["simulation"] != "failed"].iterrows():
                    at = {k: row[k] for k in keys} | {"realisation": row["realisation"]}
                    series = ds[name].sel(at).to_numpy().astype(float)
                    ax.plot(days, series, lw=1.0, color=colours[row[key]], gid=str(row["variant"]))
                if failed:
                    ax.text(
                        0.98,
                        0.97,
                        f"{failed} failed variant{'s' if failed > 1 else ''} left out",
                        transform=ax.transAxes,
                        ha="right",
                        va="top",
                        fontsize=LABEL_SIZE,
                        color=FAILED_COLOUR,
                        gid=FAILED,
                    )
                label_axis(ax.xaxis, "time", "day", days)
                title, unit = figure_title(ds, name)
                title = title.removesuffix(" series")
                label_axis(ax.yaxis, title, unit, ds[name].to_numpy().astype(float))
                ax.grid(True, lw=0.4, alpha=0.5)
            handles = [Line2D([], [], color=colours[v], lw=1.5) for v in values]
            axes[i][-1].legend(
                handles,
                [value_text(v, unit_of(ds, key)) for v in values],
                title=key,
                loc="upper left",
                bbox_to_anchor=(1.02, 1.0),
                fontsize=LABEL_SIZE,
                title_fontsize=LABEL_SIZE,
            )
        fig.suptitle(f"study {ds.attrs.get('study', '')}: field profiles of {len(frame) - failed} variants")
    return fig


@dataclass(frozen=True)
class Swing:
    """One bar of the tornado: ``key``'s lowest and highest values, the response's mean over
    the realisations there (``low_mean``, ``high_mean``) and at the base (``base``)."""

    key: str
    low: Any
    high: Any
    low_mean: float
    high_mean: float
    base: float

    @property
    def size(self) -> float:
        """|high_mean - low_mean| (NaN where either is missing)."""
        return abs(self.high_mean - self.low_mean)


def middle_value(values: Sequence[Any]) -> Any:
    """A key's base value for the tornado: the middle of its sorted values (the lower middle for
    an even count: of 2 values the lowest)."""
    return sorted(values)[(len(values) - 1) // 2]


def _mean(frame, response: str, where: dict[str, Any]) -> float:
    rows = frame
    for k, v in where.items():
        rows = rows[rows[k] == v]
    y = _good(rows, response)
    return float(y.mean()) if y.size else float("nan")


def tornado_swings(ds, response: str = TORNADO_RESPONSE) -> list[Swing]:
    """Each varied key's effect on ``response``, largest first. Definition: the base is every
    key at its :func:`middle_value`; a key's bar goes from the mean of ``response`` over the
    realisations at its lowest value to that at its highest value, the other keys at their
    middle values; ``base`` is the mean at the base. A key whose values are labels (whole
    sections: ``grid: [{label: pebi-40m, ...}, ...]``) has no lowest or highest value: its bar
    goes from the label of the least mean to that of the greatest (its middle value is that of
    its labels in sorted order). Means leave failed simulations out (NaN
    where all failed). In a zipped study the other keys move with the key (the variants at its
    lowest and highest values), the base is the variants at the first key's middle value."""
    keys = varied_keys(ds)
    frame = variants_frame(ds, [response])
    middle = {k: middle_value(key_values(frame, k)) for k in keys}
    zipped = str(ds.attrs.get("combine", "product")) == "zip"
    base = _mean(frame, response, {keys[0]: middle[keys[0]]} if zipped else middle)
    swings = []
    for key in keys:
        values = key_values(frame, key)
        fixed = {} if zipped else {k: v for k, v in middle.items() if k != key}
        if numeric(values):
            ends = [values[0], values[-1]]
        else:  # labels have no order: the labels of the least and the greatest mean
            means = np.array([_mean(frame, response, fixed | {key: v}) for v in values])
            has = np.flatnonzero(np.isfinite(means))
            ends = (
                [values[has[np.argmin(means[has])]], values[has[np.argmax(means[has])]]]
                if has.size
                else values[:1] * 2
            )
        low, high = (_mean(frame, response, fixed | {key: v}) for v in ends)
        swings.append(Swing(key, ends[0], ends[1], low, high, base))
    return sorted(swings, key=lambda s: -s.size if np.isfinite(s.size) else np.inf)


def _bar_label(ds, s: Swing) -> str:
    unit = unit_of(ds, s.key)
    return f"{s.key}\n{value_text(s.low, unit)} to {value_text(s.high, unit)}"


def tornado_figure(ds, response: str = TORNADO_RESPONSE):
    """study_tornado.png: :func:`tornado_swings` of ``response`` as horizontal bars from the
    base to the mean at each key's lowest (blue) and highest (orange) value, largest on top.
    Returns the figure."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    swings = tornado_swings(ds, response)
    title, unit = figure_title(ds, response)
    with picture_style():
        fig, ax = plt.subplots(figsize=(7.5, 1.2 + 0.7 * len(swings)), layout="constrained")
        n = len(swings)
        for i, s in enumerate(swings):
            y = n - 1 - i
            for mean, colour, gid in (
                (s.low_mean, LOW_COLOUR, TORNADO_LOW),
                (s.high_mean, HIGH_COLOUR, TORNADO_HIGH),
            ):
                if np.isfinite(mean) and np.isfinite(s.base):
                    ax.barh(y, mean - s.base, left=s.base, height=0.6, color=colour, alpha=0.85, gid=gid)
            if not (np.isfinite(s.low_mean) and np.isfinite(s.high_mean)):
                ax.text(
                    s.base,
                    y,
                    "no value (failed)",
                    ha="center",
                    va="center",
                    fontsize=LABEL_SIZE,
                    color=FAILED_COLOUR,
                    gid=FAILED,
                )
        if swings and np.isfinite(swings[0].base):
            ax.axvline(swings[0].base, color="black", lw=1.0, gid=BASE)
        ax.set_yticks(range(n), [_bar_label(ds, s) for s in reversed(swings)])
        every = np.array([v for s in swings for v in (s.low_mean, s.high_mean, s.base)], dtype=float)
        label_axis(ax.xaxis, title, unit, every)
        base = swings[0].base if swings else float("nan")
        ax.legend(
            [Patch(color=LOW_COLOUR), Patch(color=HIGH_COLOUR), Line2D([], [], color="black", lw=1.0)],
            [
                "key at its lowest value (labels: least mean)",
                "at its highest (labels: greatest mean)",
                f"base (middle values): {base:.4g}",
            ],
            loc="lower center",
            bbox_to_anchor=(0.5, 1.0),
            ncols=2,  # three do not fit the figure's width
            fontsize=LABEL_SIZE,
            frameon=False,
        )
        ax.grid(True, axis="x", lw=0.4, alpha=0.5)
        finite = every[np.isfinite(every)]
        if finite.size:  # the base line and the bars' ends clear of the frame (bars stick to it)
            pad = 0.12 * (finite.max() - finite.min()) or 0.05 * max(abs(finite.max()), 1e-12)
            ax.set_xlim(finite.min() - pad, finite.max() + pad)
        fig.suptitle(
            f"study {ds.attrs.get('study', '')}: effect of each key on {title} (others at middle values)"
        )
    return fig
