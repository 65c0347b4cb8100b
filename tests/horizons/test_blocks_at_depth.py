"""Picks go to fault blocks by an inclined fault's surface at their own depth (issue 25, item 5),
the rule stair-stepped cells follow: checked against the analytic plane of a 45-degree fault."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib.horizons import fault_blocks
from gridlib.horizons.build import HorizonSource, horizons_from_sources
from gridlib.pillars.fault_surface import FaultSurface
from gridlib.pillars.fault_traces import FaultTrace

TRACE = [(500.0, -10.0), (500.0, 1010.0)]  # cuts the top horizon (1000 m) at x = 500, walked north
EXTENT = (0.0, 1000.0, 0.0, 1000.0)


def dipping_east(throw: float = 20.0) -> FaultTrace:
    """Dips 45 degrees east (its right, the hanging wall): the plane x = 500 + (z - 1000)."""
    return FaultTrace(TRACE, throw, "F", "right", FaultSurface.from_dip(TRACE, 1000.0, 45.0, "right"))


def test_a_pick_across_the_surface_at_its_depth_goes_to_that_block():
    blocks = fault_blocks([dipping_east()], EXTENT)
    west, east = 0, 1
    x = np.array([495.0, 505.0, 100.0, 900.0, 520.0, 480.0])
    z = np.array([980.0, 1010.0, 1010.0, 980.0, 1010.0, 990.0])
    # In plan: west of the trace, east, west, east, east, west.
    assert blocks.classify(x, 500.0).tolist() == [west, east, west, east, east, west]
    # At depth: the plane is at x = 480, 510, 510, 480, 510, 490: east of it is the hanging wall.
    expected = np.where(x > 500.0 + (z - 1000.0), east, west)
    assert expected.tolist() == [east, west, west, east, east, west]
    assert blocks.classify(x, np.full(6, 500.0), z).tolist() == expected.tolist()


def test_vertical_faults_and_plan_points_are_classified_as_before():
    vertical = FaultTrace(TRACE, 20.0, "F", "right", FaultSurface.from_dip(TRACE, 1000.0, 90.0, "right"))
    x, z = np.array([495.0, 505.0]), np.array([980.0, 1010.0])
    for fault in (FaultTrace(TRACE, 20.0, "F"), vertical):
        assert fault_blocks([fault], EXTENT).classify(x, 500.0, z).tolist() == [0, 1]


def test_per_fault_block_surfaces_take_each_pick_by_its_depth():
    """The hanging-wall (east) block has two picks in plan and a third just east of the surface at
    its depth (x = 490 at 985 m: the plane is at x = 485 there): three picks make its surface."""
    picks = np.array(
        [
            [100.0, 100.0, 1000.0],
            [100.0, 900.0, 1000.0],
            [300.0, 500.0, 1000.0],
            [450.0, 200.0, 1000.0],
            [900.0, 100.0, 1020.0],
            [900.0, 900.0, 1020.0],
            [490.0, 500.0, 985.0],
        ]
    )
    source = HorizonSource("top", "top", "points", picks, {"extrapolation": "nearest"}, "picks")
    xa, ya = np.linspace(0.0, 1000.0, 101), np.linspace(0.0, 1000.0, 11)
    ds = horizons_from_sources([source], xa, ya, faults=[dipping_east()], per_block=True)
    by_block = ds["depth_by_block"].values  # (block, horizon, y, x)
    assert by_block[1, 0, 5, 49] == pytest.approx(985.0, abs=1e-9)  # the east surface through the pick
    assert by_block[0, 0, 5, 49] == pytest.approx(1000.0, abs=1e-9)  # the west one does not see it
