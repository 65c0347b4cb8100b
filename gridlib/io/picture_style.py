"""The one style of gridlib's pictures: figure sizes and resolution, fonts, a colour map per
kind of quantity, one colour per fault, colour bars titled with their unit, a scale bar and a
north arrow for matplotlib map axes.

Conventions: x is east, y north (a map's up), z depth (positive down); lengths are in the
case's length unit (m, or a FIELD deck's ft). Every picture of a case colours fault ``k`` (the
``faults.tag`` of its faces, 1-based; names ``fault_names[k - 1]``) with :func:`fault_colour`
``(k)``: the 3-D view, the plan view and the section agree, and two faults of a case differ.
Artists that tests and readers look for carry a ``gid``: :data:`SCALE_BAR`, :data:`NORTH_ARROW`.

Use::

    with picture_style():
        fig, ax = new_figure("plan")
        ...
        colour_bar(fig, ax, mappable, "depth", "m")
        scale_bar(ax, "m")
        north_arrow(ax)
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from typing import Any, Literal

import numpy as np

Kind = Literal["depth", "property", "diverging", "category"]

DPI = 120
FIGURE_SIZES: dict[str, tuple[float, float]] = {  # inches
    "plan": (8.5, 7.5),
    "section": (12.0, 5.5),
    "histograms": (5.0, 3.6),  # per panel
    "residuals": (12.0, 5.0),
}
FONT_SIZE = 10
TITLE_SIZE = 12
LABEL_SIZE = 8  # names of faults and wells, contour labels
RC: dict[str, Any] = {
    "font.family": "DejaVu Sans",
    "font.size": FONT_SIZE,
    "axes.titlesize": TITLE_SIZE,
    "axes.labelsize": FONT_SIZE,
    "xtick.labelsize": FONT_SIZE - 1,
    "ytick.labelsize": FONT_SIZE - 1,
    "figure.titlesize": TITLE_SIZE,
    "savefig.dpi": DPI,
    "image.cmap": "viridis",
}
# Perceptually uniform maps. Depth: shallow is bright (crests stand out), deep is dark.
COLOUR_MAPS: dict[str, str] = {
    "depth": "viridis_r",
    "property": "viridis",
    "diverging": "RdBu_r",  # residuals: blue negative, red positive, white 0 (centre the norm)
    "category": "tab20",
}
# Faults: a categorical palette (Okabe-Ito's colour-blind safe set, then Tableau's 10) of
# colours distinct from each other and from the maps above's ends; fault k gets colour k - 1
# (cycling beyond 17 faults).
FAULT_PALETTE: tuple[str, ...] = (
    "#D55E00",  # vermillion
    "#0072B2",  # blue
    "#CC79A7",  # reddish purple
    "#E69F00",  # orange
    "#009E73",  # bluish green
    "#56B4E9",  # sky blue
    "#000000",  # black
    "#F0E442",  # yellow
    "#d62728",  # red
    "#9467bd",  # purple
    "#8c564b",  # brown
    "#e377c2",  # pink
    "#7f7f7f",  # grey
    "#bcbd22",  # olive
    "#17becf",  # cyan
    "#1f77b4",  # tab blue
    "#2ca02c",  # tab green
)
NO_FAULT = "#999999"
WELL_COLOUR = "black"
SCALE_BAR = "scale bar"
NORTH_ARROW = "north arrow"


@contextlib.contextmanager
def picture_style() -> Iterator[None]:
    """matplotlib's Agg backend and gridlib's fonts and defaults (:data:`RC`) inside the block."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with plt.rc_context(RC):
        yield


def new_figure(kind: str, ncols: int = 1):
    """A figure of the size of ``kind`` (a key of :data:`FIGURE_SIZES`; its width per panel
    times ``ncols``) and its axes, placed by the kind's fixed margins (:data:`MARGINS`,
    :func:`panel_layout`)."""
    import matplotlib.pyplot as plt

    width, height = FIGURE_SIZES[kind]
    if kind == "histograms":
        width *= ncols
    fig, axes = plt.subplots(1, ncols, figsize=(width, height))
    panel_layout(fig, 1, ncols, MARGINS[kind])
    return fig, axes


# The margins of a picture's axes (inches): fixed, where tight or constrained layout measure
# every text of the figure (0.2 to 0.35 s of CPU for a histogram picture that draws in 0.2 s,
# and a second draw of the whole figure when it is saved).
# Histograms: room for tick labels of up to 6 characters and one line of axis label at
# FONT_SIZE beside and below each panel, and the title above all.
PANEL_MARGINS = {"left": 0.8, "right": 0.3, "bottom": 0.65, "top": 0.55, "across": 0.85, "down": 0.8}
# A map (plan view, residuals): y tick labels of up to 7 characters and the axis label at the
# left; the colour bar (:func:`colour_bar`), its tick labels of up to 6 characters and its
# title at the right; a line of tick labels and the axis label below, the title above.
MAP_MARGINS = {"left": 1.0, "right": 1.45, "bottom": 0.7, "top": 0.5, "across": 0.0, "down": 0.0}
# A section: as a map, and below the axes label the vertical exaggeration's line; above, the
# ends' letters (A, A') beside the title.
SECTION_MARGINS = {**MAP_MARGINS, "left": 0.95, "bottom": 1.0, "top": 0.6}
MARGINS = {"histograms": PANEL_MARGINS, "plan": MAP_MARGINS, "section": SECTION_MARGINS}
# A colour bar beside its axes (inches; its length a fraction of the axes' height).
COLOUR_BAR = {"pad": 0.15, "width": 0.22, "length": 0.85}


def panel_layout(fig, rows: int, cols: int, margins: dict[str, float] = PANEL_MARGINS) -> None:
    """Place the ``rows`` x ``cols`` axes of ``fig`` (made by ``plt.subplots`` without a layout
    engine) by ``margins`` (inches: ``left``, ``right``, ``bottom``, ``top`` of the figure,
    ``across`` and ``down`` between panels; :data:`MARGINS`): the same place whatever the
    panels' texts, none of which overlap for labels within the margins. Call it again after
    the figure is resized (the margins are kept in inches)."""
    width, height = fig.get_size_inches()
    m = margins
    panel_width = (width - m["left"] - m["right"] - (cols - 1) * m["across"]) / cols
    panel_height = (height - m["bottom"] - m["top"] - (rows - 1) * m["down"]) / rows
    fig.subplots_adjust(
        left=m["left"] / width,
        right=1.0 - m["right"] / width,
        bottom=m["bottom"] / height,
        top=1.0 - m["top"] / height,
        wspace=m["across"] / panel_width,
        hspace=m["down"] / panel_height,
    )


def fit_figure(
    fig, ratio: float, margins: dict[str, float], max_height: float, min_height: float = 3.0
) -> None:
    """Fit the height of ``fig`` (one axes) to an axes box of height over width ``ratio`` (its
    data's aspect) within ``margins`` (inches, :data:`MARGINS`), its width kept; where that is
    taller than ``max_height``, narrower instead (not cropped); at least ``min_height``. Then
    place its axes by the margins (:func:`panel_layout`)."""
    width = fig.get_size_inches()[0]
    side, room = margins["left"] + margins["right"], margins["bottom"] + margins["top"]
    height = ratio * (width - side) + room
    if height > max_height:
        width, height = (max_height - room) / ratio + side, max_height
    fig.set_size_inches(width, max(height, min_height))
    panel_layout(fig, 1, 1, margins)


_SUPERSCRIPTS = str.maketrans(
    "-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
)


def power_of_ten_label(x: float) -> str:
    """``x`` (> 0) as a power of ten in plain text with Unicode superscripts, as matplotlib's
    logarithmic tick labels read (``10^-3``, ``2 x 10^1``) without its TeX-like mathtext.

    >>> power_of_ten_label(1e-3), power_of_ten_label(20.0), power_of_ten_label(1.0)
    ('10⁻³', '2×10¹', '10⁰')
    """
    mantissa, power = f"{x:.0e}".split("e")  # a tick is c x 10^p: '2e+01'
    coefficient = "" if mantissa == "1" else f"{mantissa}\u00d7"
    return f"{coefficient}10{str(int(power)).translate(_SUPERSCRIPTS)}"


def _power_of_ten_formatter(minor: bool):
    """matplotlib's choice of which logarithmic ticks get a label (every power of ten; the
    minor ticks too where the axis spans few decades), labelled by :func:`power_of_ten_label`."""
    from matplotlib.ticker import LogFormatter

    class PowerOfTenFormatter(LogFormatter):
        def _num_to_string(self, x, vmin, vmax):
            return power_of_ten_label(x)

    return PowerOfTenFormatter(10.0, labelOnlyBase=not minor)


# A logarithmic axis spanning more than this ratio gets no minor ticks: its powers of ten are
# close enough to read between, and each tick is a dozen artists (a panel's drawing is nearly
# all ticks).
MINOR_TICKS_SPAN = 1e4
# At most this many intervals between the labelled ticks of a histogram's linear axes (matplotlib
# puts up to 10 on a panel 4 inches wide).
HISTOGRAM_TICKS = 5


def logarithmic(ax, which: Literal["x", "y"]) -> None:
    """Make the axis ``which`` of ``ax`` logarithmic with minor ticks at 2 and 5 times each
    power of ten (matplotlib's default of 2 to 9 makes four times the tick objects of a
    histogram panel, a third of its drawing time), none where it spans more than
    :data:`MINOR_TICKS_SPAN`, labelled in plain text (:func:`power_of_ten_label`: matplotlib's
    own labels are mathtext, whose parser took about 0.2 s of a small case's pictures)."""
    from matplotlib.ticker import LogLocator

    class FewMinorTicks(LogLocator):
        def tick_values(self, vmin, vmax):
            lo, hi = sorted((vmin, vmax))
            if lo > 0 and hi > MINOR_TICKS_SPAN * lo:
                return np.array([])
            return super().tick_values(vmin, vmax)

    (ax.set_xscale if which == "x" else ax.set_yscale)("log")
    axis = ax.xaxis if which == "x" else ax.yaxis
    axis.set_minor_locator(FewMinorTicks(subs=(2.0, 5.0)))
    axis.set_major_formatter(_power_of_ten_formatter(minor=False))
    axis.set_minor_formatter(_power_of_ten_formatter(minor=True))


def few_ticks(ax) -> None:
    """At most :data:`HISTOGRAM_TICKS` intervals of 1, 2 or 5 x 10^k between the labelled ticks
    of the axes of ``ax`` that matplotlib's default locator places (not logarithmic axes, nor
    ticks set by hand): a histogram panel's drawing is nearly all its ticks' artists."""
    from matplotlib.ticker import AutoLocator, MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        if type(axis.get_major_locator()) is AutoLocator:
            axis.set_major_locator(MaxNLocator(nbins=HISTOGRAM_TICKS, steps=[1, 2, 5, 10]))


def colour_map(kind: Kind):
    """The matplotlib colour map of a kind of quantity (:data:`COLOUR_MAPS`)."""
    import matplotlib

    return matplotlib.colormaps[COLOUR_MAPS[kind]]


def fault_colour(fault: int) -> str:
    """The colour (hex) of fault ``fault`` (its 1-based id, ``faults.tag``); :data:`NO_FAULT`
    for 0 (no fault).

    >>> fault_colour(1), fault_colour(2), fault_colour(18) == fault_colour(1), fault_colour(0)
    ('#D55E00', '#0072B2', True, '#999999')
    """
    if fault <= 0:
        return NO_FAULT
    return FAULT_PALETTE[(int(fault) - 1) % len(FAULT_PALETTE)]


def fault_colours(faults: np.ndarray) -> np.ndarray:
    """RGBA (n, 4) of the 1-based fault ids ``faults`` (vectorised :func:`fault_colour`)."""
    from matplotlib.colors import to_rgba_array

    palette = to_rgba_array((NO_FAULT, *FAULT_PALETTE))
    ids = np.asarray(faults, dtype=np.int64)
    return palette[np.where(ids > 0, (ids - 1) % len(FAULT_PALETTE) + 1, 0)]


FAULT_NAME = "fault name"  # the gid of a fault's name on a picture


def label_fault(ax, fault: int, at: Any, names: Sequence[str], offset: tuple[float, float], **kwargs: Any):
    """Write fault ``fault``'s name (1-based id into ``names``; ``fault <id>`` where it has
    none) at ``at`` (data coordinates), ``offset`` points away, bold in the fault's colour on a
    white box, with the gid :data:`FAULT_NAME`; ``kwargs`` go to ``ax.annotate``. Returns the
    annotation."""
    name = names[fault - 1] if 0 < fault <= len(names) and names[fault - 1] else f"fault {fault}"
    label = ax.annotate(
        name,
        at,
        xytext=offset,
        textcoords="offset points",
        color=fault_colour(int(fault)),
        fontsize=LABEL_SIZE,
        fontweight="bold",
        bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.7},
        **kwargs,
    )
    label.set_gid(FAULT_NAME)
    return label


def quantity_label(quantity: str, unit: str | None) -> str:
    """``quantity [unit]`` (``quantity`` alone without a unit).

    >>> quantity_label("depth", "ft"), quantity_label("zone", None)
    ('depth [ft]', 'zone')
    """
    return quantity if not unit else f"{quantity} [{unit}]"


def colour_bar(
    fig, ax, mappable, quantity: str, unit: str | None, *, ticks: Any = None, downward: bool = False
):
    """A vertical colour bar beside ``ax`` (:data:`COLOUR_BAR`: a fixed gap and width in inches,
    centred on the axes' box as drawn, after its aspect; in the axes' right margin, which
    :data:`MARGINS` leave for it) titled ``quantity [unit]`` along its long side, beyond its
    tick labels (matplotlib places the label outside them: they never overlap); at most 8
    ticks (or ``ticks``), none crowded, written in full (no offset); ``downward`` (depths): its
    values increase downwards, shallow at the top as on a section. Returns the colour bar."""
    from matplotlib.ticker import MaxNLocator, ScalarFormatter

    cax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    cax.set_axes_locator(_beside(ax))
    bar = fig.colorbar(mappable, cax=cax, ticks=ticks)
    if ticks is None:
        bar.locator = MaxNLocator(nbins=8)
    bar.formatter = ScalarFormatter(useOffset=False)  # whole depths, not "+1.5e3" above the bar
    bar.update_ticks()
    bar.set_label(quantity_label(quantity, unit), labelpad=8)
    if downward:
        bar.ax.invert_yaxis()
    return bar


def _beside(ax):
    """An axes locator: the box of a colour bar right of ``ax``'s box as drawn (its aspect
    applied), :data:`COLOUR_BAR`'s gap and width, centred on it vertically."""
    from matplotlib.transforms import Bbox

    def locate(cax, renderer):
        box = ax.get_position()  # the active box: the axes' aspect applied
        width = ax.figure.get_size_inches()[0]
        length = COLOUR_BAR["length"] * box.height
        return Bbox.from_bounds(
            box.x1 + COLOUR_BAR["pad"] / width,
            box.y0 + 0.5 * (box.height - length),
            COLOUR_BAR["width"] / width,
            length,
        )

    return locate


def segment_lines(ax, segments: np.ndarray, **kwargs: Any):
    """The line segments ``segments`` ((n, 2, 2) data coordinates) drawn on ``ax`` in one
    style (``kwargs`` of ``Line2D``) as one line broken by NaNs: one path, where a
    ``LineCollection`` builds a path per segment (0.06 s of CPU for 14,000 outlines). Returns
    the line."""
    gaps = np.full((segments.shape[0], 1, 2), np.nan)
    xy = np.concatenate([segments, gaps], axis=1).reshape(-1, 2)
    (line,) = ax.plot(xy[:, 0], xy[:, 1], **kwargs)
    return line


def nice_length(length: float) -> float:
    """The largest 1, 2 or 5 x 10^k not above ``length`` (> 0), exact in decimal.

    >>> nice_length(730.0), nice_length(0.031), nice_length(2000.0), nice_length(199.0)
    (500.0, 0.02, 2000.0, 100.0)
    """
    if not length > 0:
        raise ValueError(f"a scale bar needs a positive length, not {length}")
    mantissa, exponent = f"{length:.6e}".split("e")
    lead = float(mantissa)
    digit = 5 if lead >= 5 else 2 if lead >= 2 else 1
    return float(f"{digit}e{int(exponent)}")


def scale_bar(ax, unit: str, fraction: float = 0.25, corner: str = "lower left"):
    """A scale bar in a lower ``corner`` of the map ``ax`` (data units: the case's length
    unit ``unit``; equal aspect): a length of 1, 2 or 5 x 10^k up to ``fraction`` of the axes'
    width, labelled e.g. "500 m". Draw it after the data (it reads the axes' limits). Its
    artist has the gid :data:`SCALE_BAR`; returns it."""
    from matplotlib.font_manager import FontProperties
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    x0, x1 = ax.get_xlim()
    length = nice_length(fraction * abs(x1 - x0))
    bar = AnchoredSizeBar(
        ax.transData,
        length,
        f"{length:g} {unit}",
        corner,
        pad=0.4,
        borderpad=0.6,
        sep=4,
        frameon=True,
        size_vertical=0.012 * abs(ax.get_ylim()[1] - ax.get_ylim()[0]),
        fontproperties=FontProperties(size=FONT_SIZE - 1),
    )
    bar.patch.set_facecolor("white")
    bar.patch.set_alpha(0.75)
    bar.set_gid(SCALE_BAR)
    ax.add_artist(bar)
    return bar


def north_arrow(ax, corner: str = "upper right"):
    """A north arrow (y is north) with an "N" in an upper ``corner`` of the map ``ax``; its
    annotation has the gid :data:`NORTH_ARROW`; returns it."""
    arrow = ax.annotate(
        "N",
        xy=(0.95 if corner.endswith("right") else 0.05, 0.95),
        xytext=(0.95 if corner.endswith("right") else 0.05, 0.82),
        xycoords="axes fraction",
        ha="center",
        va="center",
        fontsize=FONT_SIZE + 2,
        fontweight="bold",
        arrowprops={"facecolor": "black", "edgecolor": "black", "width": 3, "headwidth": 10},
        bbox={"boxstyle": "circle,pad=0.2", "facecolor": "white", "edgecolor": "none", "alpha": 0.75},
    )
    arrow.set_gid(NORTH_ARROW)
    return arrow


def named(ax, gid: str) -> list[Any]:
    """The artists of ``ax`` with the gid ``gid`` (its texts, artists, lines, collections)."""
    every = [*ax.texts, *ax.artists, *ax.lines, *ax.collections, *ax.patches]
    return [a for a in every if a.get_gid() == gid]
