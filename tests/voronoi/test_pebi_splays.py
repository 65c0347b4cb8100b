"""Seeded property test: splays of 3 to 6 faults meeting at one point all build (issue 29).

Every layout is a fan or a full star of fault arms leaving one point: every gap between
consecutive arms between 3 and 60 degrees (the gap outside a fan is whatever is left; a full
star closes around the point with every gap in that range), arms 2 to 15 cells long, some
faults crossing the point (a trace through it, two arms, bent there) and the others ending
there; random rotation, a rectangle or an irregular polygon around it, a third at UTM
coordinates. Each grid is checked by ``pebi_invariants.check_pebi``: a valid grid, areas
adding up (1e-10), fault faces exactly on the traces (1e-9 h), faces perpendicular bisectors
of their sites, and cells of at least 0.1 h^2 and faces of at least 0.01 h except those a
note counts.
"""

from __future__ import annotations

import numpy as np
import shapely
from pebi_invariants import build_layout, check_pebi

from gridlib.voronoi import Fault, pebi_grid

H = 10.0  # m: the cell size of every layout
UTM = np.array([5.3e5, 6.7e6])
N_SPLAYS = 500
MIN_GAP, MAX_GAP = 3.0, 60.0  # degrees between consecutive arms


def _gaps(rng, arms: int, star: bool) -> np.ndarray:
    """Gaps (degrees) between consecutive arms: ``arms`` of them closing around the point (a star),
    or ``arms - 1`` (a fan) leaving at least MIN_GAP outside."""
    if star:  # arms gaps in [MIN_GAP, MAX_GAP] summing to 360
        while True:
            g = MIN_GAP + rng.dirichlet(np.full(arms, 2.0)) * (360.0 - arms * MIN_GAP)
            if g.max() <= MAX_GAP:
                return g
    while True:
        g = rng.uniform(MIN_GAP, MAX_GAP, arms - 1)
        if rng.random() < 0.5:  # often all narrow, the hard case
            g = rng.uniform(MIN_GAP, rng.uniform(8.0, 40.0), arms - 1)
        if g.sum() <= 360.0 - MIN_GAP:
            return g


def splay(seed: int) -> dict:
    """Splay ``seed``: domain and faults in metres (caller's frame), and what it is made of."""
    rng = np.random.default_rng([29, seed])
    n_faults = int(rng.integers(3, 7))
    crossing = int(rng.integers(0, n_faults + 1)) if rng.random() < 0.5 else 0
    arms = n_faults + crossing
    # a full star needs at least 6 arms (gaps of at most 60 degrees)
    star = arms >= 7 or (arms == 6 and rng.random() < 0.2)
    if arms == 6 and star:
        gaps = np.full(6, 60.0)
    else:
        gaps = _gaps(rng, arms, star)
    angles = np.radians(np.concatenate([[0.0], np.cumsum(gaps)])[:arms] + rng.uniform(0, 360))
    lengths = rng.uniform(2.0, 15.0, arms)
    tips = np.column_stack([np.cos(angles), np.sin(angles)]) * lengths[:, None]
    order = rng.permutation(arms)  # which arms pair into faults through the point
    faults = [np.array([tips[order[2 * k]], (0.0, 0.0), tips[order[2 * k + 1]]]) for k in range(crossing)]
    faults += [np.array([(0.0, 0.0), tips[a]]) for a in order[2 * crossing :]]
    faults = [faults[k] for k in rng.permutation(len(faults))]
    faults = [f[::-1] if rng.random() < 0.5 else f for f in faults]
    reach = float(lengths.max())
    if rng.random() < 0.5:  # a rectangle around the splay, 1.5 to 4 cells beyond its arms
        lo = np.minimum(tips.min(axis=0), 0.0) - rng.uniform(1.5, 4.0, 2)
        hi = np.maximum(tips.max(axis=0), 0.0) + rng.uniform(1.5, 4.0, 2)
        poly = np.array([lo, (hi[0], lo[1]), hi, (lo[0], hi[1])])
        shape = "rect"
    else:  # an irregular polygon holding the arms with 1.5 cells to spare
        m = int(rng.integers(5, 11))
        th = np.sort(rng.uniform(0, 2 * np.pi, m))
        r = (reach + rng.uniform(1.5, 5.0, m)) * np.where(rng.random(m) < 0.3, 1.4, 1.0)
        poly = np.column_stack([r * np.cos(th), r * np.sin(th)]) + rng.uniform(-1, 1, 2)
        arms = shapely.MultiLineString([[(0.0, 0.0), tuple(p)] for p in tips])
        if not shapely.Polygon(poly).buffer(-1.5).contains(arms):  # a regular polygon instead
            th = 2 * np.pi * np.arange(m) / m + rng.uniform(0, 2 * np.pi)
            poly = (reach + 2.0) / np.cos(np.pi / m) * np.column_stack([np.cos(th), np.sin(th)])
        shape = "polygon"
    rot_angle = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(rot_angle), -np.sin(rot_angle)], [np.sin(rot_angle), np.cos(rot_angle)]])
    offset = UTM + rng.uniform(-1e3, 1e3, 2) if seed % 3 == 0 else rng.uniform(-50, 50, 2)

    def place(xy: np.ndarray) -> np.ndarray:
        return (np.asarray(xy) @ rot.T) * H + offset

    return {
        "domain": place(poly),
        "faults": [Fault(place(f)) for f in faults],
        "wells": [],
        "offset": offset,
        "gaps": gaps,
        "star": star,
        "crossing": crossing,
        "shape": shape,
    }


def test_splays_of_faults_all_build():
    """500 seeded splays, each checked by ``check_pebi``; the layouts cover what the issue asks for."""
    cases = [splay(seed) for seed in range(N_SPLAYS)]
    got = [check_pebi(case, build_layout(case, H), seed, H) for seed, case in enumerate(cases)]
    assert {len(c["faults"]) for c in cases} == {3, 4, 5, 6}
    assert sum(c["star"] for c in cases) >= 50 and sum(c["crossing"] > 0 for c in cases) >= 150
    assert {c["shape"] for c in cases} == {"rect", "polygon"}
    gaps = np.concatenate([c["gaps"] for c in cases])
    assert gaps.min() >= MIN_GAP and gaps.max() <= MAX_GAP and (gaps < 5.0).sum() >= 80
    assert sum(g["utm"] for g in got) == -(-N_SPLAYS // 3)
    for case, g in zip(cases, got, strict=True):  # every acute gap gets rows of shared sites, and a note
        around = case["gaps"] if case["star"] else np.append(case["gaps"], 360.0 - case["gaps"].sum())
        if around.min() < 40.0:
            assert any("cells between them" in n for n in g["notes"]), g["notes"]  # meet, meets or bends


def test_every_arm_of_a_fan_has_rows_at_half_its_narrower_gap():
    """Four faults from one point at gaps of 10.5, 17.7 and 13.4 degrees (the kind refused before):
    every arm's rows lie at half its narrower gap either side of it (5.25, 5.25, 6.7 and 6.7 degrees),
    the 10.5 and 13.4 degree gaps hold one shared row on their bisectors and the 17.7 degree gap two
    (one per arm), and all rows place their sites at the same distances from the point."""
    c = np.array([20.0, 20.0])
    arms = np.array([0.0, 10.5, 28.2, 41.6])
    faults = [Fault([c, c + 12.0 * np.array([np.cos(a), np.sin(a)])]) for a in np.radians(arms)]
    pg = pebi_grid(((0, 0), (40, 40)), 2.0, faults=faults)
    note = "meet at 10.5 and 17.7 and 13.4 degrees at (20, 20): 4 rows of"
    assert any(note in n for n in pg.notes), pg.notes
    rel = pg.sites[pg.site_kind == 2] - c
    dist = np.hypot(rel[:, 0], rel[:, 1])
    near = dist < 4.0  # the rows' first sites
    angle = np.degrees(np.arctan2(rel[near, 1], rel[near, 0]))
    # 0 -/+ 5.25, 10.5 + 5.25, 28.2 -/+ 6.7, 41.6 + 6.7
    rows = np.array([-5.25, 5.25, 15.75, 21.5, 34.9, 48.3])
    assert np.abs(angle[:, None] - rows[None, :]).min(axis=1).max() < 1e-9
    assert set(np.abs(angle[:, None] - rows[None, :]).argmin(axis=1).tolist()) == set(range(6))
    radii = np.unique(np.round(dist[near], 9))
    assert np.all(np.isin(np.round(dist[near], 9), radii)) and radii.size <= 3  # common distances
