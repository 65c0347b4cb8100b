"""Picks go to fault blocks by an inclined fault's surface at their own depth (issue 25, item 5),
the rule stair-stepped cells follow: checked against the analytic plane of a 45-degree fault."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gridlib.horizons import fault_blocks
from gridlib.horizons.blocks import footwall_top, with_surfaces
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


# Picks of two horizons faulted by a fault dipping 60 degrees east (its right, walked north), whose
# trace x = 200 is its footwall cut-off: where it meets the footwall's top, which tilts (0.02 m/m
# east, 1004 m at the trace), so the surface depends on the footwall top found from the picks.
# Hanging wall 12 m down; each horizon picked only where it exists (no picks in the gaps).
DIP, THROW, GRADIENT = 60.0, 12.0, 0.02
F60 = [(200.0, -10.0), (200.0, 210.0)]


def fault_x(z):
    """The plane's x at depth z: x = 200 + (z - 1004) / tan(60)."""
    return 200.0 + (np.asarray(z) - (1000.0 + GRADIENT * 200.0)) / np.tan(np.radians(DIP))


def faulted_picks() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Top and base picks (n, 3) and each pick's block (0 west = footwall, 1 east = hanging wall)."""
    gx, gy = np.meshgrid(np.arange(5.0, 600.0, 10.0), np.arange(0.0, 201.0, 50.0))
    x, y = gx.ravel(), gy.ravel()
    out, blocks = [], []
    for thickness in (0.0, 60.0):
        rows, owner = [], []
        for block, drop in ((0, 0.0), (1, THROW)):
            z = 1000.0 + GRADIENT * x + thickness + drop
            east = x > fault_x(z)
            keep = east if block == 1 else ~east
            rows.append(np.column_stack([x, y, z])[keep])
            owner.append(np.full(keep.sum(), block))
        out.append(np.concatenate(rows))
        blocks.append(np.concatenate(owner))
    return out[0], out[1], np.concatenate(blocks)


def dip_faults(trace, side):
    def place(top):
        pts = np.asarray(trace)  # ends beyond the lattice: the top there from its edge (as fault_traces)
        surface = FaultSurface.from_dip(pts, top(pts[:, 0], np.clip(pts[:, 1], 0.0, 200.0)), DIP, side, "F")
        return [FaultTrace(trace, 0.0, "F", side, surface)]

    return place


def per_block(top: np.ndarray, base: np.ndarray, trace=F60, side="right"):
    sources = [
        HorizonSource(name, name, "points", pts, {"extrapolation": "trend"}, name)
        for name, pts in (("top", top), ("base", base))
    ]
    xa, ya = np.linspace(0.0, 600.0, 61), np.linspace(0.0, 200.0, 5)
    plain = [FaultTrace(trace, 0.0, "F", side)]
    return horizons_from_sources(
        sources, xa, ya, faults=plain, per_block=True, fault_surfaces=dip_faults(trace, side)
    )


def test_footwall_top_is_the_top_of_the_block_on_the_footwall_side_of_the_trace():
    xa, ya = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 1000.0, 11)
    tops = np.stack([np.full((11, 11), 1000.0), np.full((11, 11), 1030.0)])  # west, east
    blocks = fault_blocks([FaultTrace(TRACE, 0.0, "F", "right")], EXTENT)
    y = np.array([0.0, 333.0, 1000.0])
    for trace, side, expected in (
        (TRACE, "right", 1000.0),
        (TRACE, "left", 1030.0),
        (TRACE[::-1], "left", 1000.0),
    ):
        top = footwall_top(blocks, tops, xa, ya, [FaultTrace(trace, 0.0, "F", side)])
        assert top(np.full(3, 500.0), y) == pytest.approx([expected] * 3, abs=1e-9)


def test_picks_of_faulted_horizons_go_to_their_blocks_by_the_surface_at_the_footwall_top():
    top, base, expected = faulted_picks()
    picks = np.concatenate([top, base])
    # Footwall base picks east of the trace in plan (the plane meets the footwall base at
    # x = 235.0) and no hanging-wall top pick west of x = 207.0 (where the plane meets it): plan
    # view would put four columns of picks in the wrong block.
    plan_east = picks[:, 0] > 200.0
    assert (plan_east & (expected == 0)).sum() == 4 * 5
    assert picks[expected == 1, 0].min() == 215.0
    ds = per_block(top, base)
    by_block = ds["depth_by_block"].values  # (block, horizon, y, x)
    X = np.broadcast_to(ds["x"].values, by_block.shape[2:])
    for b, drop in ((0, 0.0), (1, THROW)):  # every block's surfaces from its own picks only: exact planes
        for k, thickness in ((0, 0.0), (1, 60.0)):
            assert np.allclose(by_block[b, k], 1000.0 + GRADIENT * X + thickness + drop, rtol=0, atol=1e-9)
    assert any("a fixed point after 1 pass(es)" in n for n in json.loads(ds.attrs["notes"]))
    # The surface placed at the result's footwall top puts every pick in its block (a fixed point).
    blocks = fault_blocks([FaultTrace(F60, 0.0, "F", "right")], (0.0, 600.0, 0.0, 200.0))
    fw_top = footwall_top(
        blocks, by_block[:, 0], ds["x"].values, ds["y"].values, [FaultTrace(F60, 0.0, "F", "right")]
    )
    placed = with_surfaces(blocks, dip_faults(F60, "right")(fw_top))
    assert placed.surfaces[0].section(1004.0)[:, 0] == pytest.approx([200.0, 200.0], abs=1e-9)
    assert placed.classify(picks[:, 0], picks[:, 1], picks[:, 2]).tolist() == expected.tolist()


def test_picks_per_block_do_not_depend_on_the_picks_order_or_the_traces_direction():
    top, base, _ = faulted_picks()
    reference = per_block(top, base)["depth_by_block"].values
    order = np.random.default_rng(3).permutation
    shuffled = per_block(top[order(top.shape[0])], base[order(base.shape[0])])["depth_by_block"].values
    reversed_trace = per_block(top, base, F60[::-1], "left")["depth_by_block"].values
    assert np.allclose(shuffled, reference, rtol=0, atol=1e-9)
    assert np.allclose(reversed_trace, reference, rtol=0, atol=1e-9)
