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
