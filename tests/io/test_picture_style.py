"""Logarithmic axes of gridlib's pictures: labelled as matplotlib labels them (which ticks), in
plain text with Unicode superscripts instead of mathtext (gridlib.io.picture_style.logarithmic)."""

from __future__ import annotations

import pytest

from gridlib.io.picture_style import logarithmic, power_of_ten_label


@pytest.mark.parametrize(
    ("value", "label"),
    [
        (1e-3, "10⁻³"),
        (1.0, "10⁰"),
        (10.0, "10¹"),
        (1e12, "10¹²"),
        (2e-5, "2×10⁻⁵"),
        (50.0, "5×10¹"),
        (3e4, "3×10⁴"),
    ],
)
def test_power_of_ten_labels(value, label):
    assert power_of_ten_label(value) == label


def _labelled_ticks(limits, ours: bool):
    """(position, label) of the labelled ticks within ``limits`` of a logarithmic x axis: ours
    (:func:`logarithmic`), or matplotlib's own labels on the same ticks."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import LogLocator

    fig, ax = plt.subplots()
    ax.plot(limits, [0.0, 1.0])
    if ours:
        logarithmic(ax, "x")
    else:
        ax.set_xscale("log")
        ax.xaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
    ax.set_xlim(*limits)
    fig.canvas.draw()
    lo, hi = limits
    labelled = [
        [
            (float(t.get_position()[0]), t.get_text())
            for t in ticks
            if t.get_text() and lo <= t.get_position()[0] <= hi
        ]
        for ticks in (ax.xaxis.get_ticklabels(), ax.xaxis.get_ticklabels(minor=True))
    ]
    plt.close(fig)
    return labelled


@pytest.mark.parametrize(
    ("limits", "major", "minor"),
    [
        ((1e-3, 1e3), ["10⁻³", "10⁻²", "10⁻¹", "10⁰", "10¹", "10²", "10³"], []),
        ((15.0, 300.0), ["10²"], ["2×10¹", "2×10²"]),
        ((2.0, 8.0), [], ["2×10⁰"]),
    ],
)
def test_the_ticks_matplotlib_labels_in_plain_text(limits, major, minor):
    ours = _labelled_ticks(limits, ours=True)
    theirs = _labelled_ticks(limits, ours=False)
    assert [[label for _, label in ticks] for ticks in ours] == [major, minor]
    assert [[x for x, _ in ticks] for ticks in ours] == [[x for x, _ in ticks] for ticks in theirs]
    assert all(label.startswith("$") for ticks in theirs for _, label in ticks)  # mathtext, which ours avoid


def test_few_ticks_on_histogram_axes():
    """A log axis over more than MINOR_TICKS_SPAN has no minor ticks (its powers of ten are
    close enough), a narrower one keeps them; few_ticks leaves at most HISTOGRAM_TICKS round
    intervals on a default linear axis and keeps ticks set by hand."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gridlib.io.picture_style import HISTOGRAM_TICKS, few_ticks

    fig, (wide, narrow, linear) = plt.subplots(1, 3, figsize=(15.0, 3.6))
    for ax, limits in ((wide, (1e-3, 1e3)), (narrow, (15.0, 300.0))):
        ax.plot(limits, [0.0, 1.0])
        logarithmic(ax, "x")
        ax.set_xlim(*limits)
    linear.plot([0.12, 0.28], [0.0, 535.0])
    linear.set_xticks([0.12, 0.2, 0.28])
    for ax in (wide, narrow, linear):
        few_ticks(ax)
    fig.canvas.draw()
    assert wide.xaxis.get_minorticklocs().size == 0
    minor = narrow.xaxis.get_minorticklocs()
    assert minor[(minor >= 15.0) & (minor <= 300.0)].tolist() == pytest.approx([20.0, 50.0, 200.0])
    assert linear.get_xticks().tolist() == [0.12, 0.2, 0.28]  # set by hand: kept
    counts = linear.get_yticks()
    shown = counts[(counts >= 0.0) & (counts <= linear.get_ylim()[1])]
    assert shown.size - 1 <= HISTOGRAM_TICKS and shown.tolist() == [0.0, 200.0, 400.0]
    plt.close(fig)
