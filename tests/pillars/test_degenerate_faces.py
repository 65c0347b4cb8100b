"""No face of zero area (issue 10, part 2): depths equal up to rounding are one point on a pillar.

A fault whose throw varies along the trace meets other layers' depths at pillars, where the two
depths agree in the model but not in floating point (``0.1 + 0.2`` against ``0.3``). As two
points they made the lines cross a hair's breadth from the pillar: faces of ~1e-33 m², even
exactly collinear ones that ``compute_geometry`` refuses, and connections between cells that do
not touch. The pillar engine now takes depths within the pillar's depth resolution rho (64 units
in the last place of its largest depth, ``gridlib.pillars.pillar_points``) as one point, and its
exact rank tests then never make a face whose nodes are collinear up to rounding.

The criterion checked on every grid: every face is wider than rho, i.e. its area exceeds rho
times its diameter (a face within rho of a line segment has area at most about rho times its
length). Checked on every deck in tests/data/decks and on generated corner-point and extruded
grids, and the linear-throw decks are compared with an exact (rational) overlap computation.
"""

from __future__ import annotations

from collections import Counter
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from real_decks import unpack

import gridlib as gl
from gridlib.cornerpoint.between_horizons import FaultTrace, Horizon, horizons_to_grdecl
from gridlib.cornerpoint.generators import cut_grdecl, make_model3, simple_grdecl
from gridlib.cornerpoint.process import FAULT, process_grdecl
from gridlib.grid import E, W
from gridlib.io.grdecl import read_grdecl
from gridlib.pillars.extrude import extrude
from gridlib.pillars.pillar_points import depth_resolution, unique_points, unique_points_rows

DECKS = Path(__file__).parents[1] / "data" / "decks"
# Every vendored deck but SPE10 model 2, whose PORO and PERM includes its own test writes (its grid,
# DX/DY/DZ/TOPS boxes, is the kind SPE1 covers here); compressed includes (.xz) are unpacked first.
DECK_FILES = sorted(
    str(p.relative_to(DECKS))
    for p in DECKS.glob("*/*.DATA")
    if "RUNSPEC" in p.read_text(errors="replace") and p.parent.name != "spe10model2"
) + ["seed/simple_grdecl_4x2x3_flat_drop012.grdecl"]


def assert_no_face_of_zero_area(grid: gl.Grid) -> gl.Geometry:
    """Every face is wider than the depth resolution: area > rho * diameter (bounded here by twice
    the largest distance from its first node); returns the checked geometry."""
    geo = gl.compute_geometry(grid)  # raises on a face of exactly zero area
    gl.check_grid(grid, geo)
    pos, xyz = grid.faces.node_pos, grid.nodes.coords
    counts = np.diff(pos)
    first = np.repeat(grid.faces.nodes[pos[:-1]], counts)
    reach = np.linalg.norm(xyz[grid.faces.nodes] - xyz[first], axis=1)
    diameter_bound = 2.0 * np.maximum.reduceat(reach, pos[:-1])
    rho = float(depth_resolution(np.abs(xyz[:, 2]).max()))
    width = geo.face_areas / diameter_bound
    worst = int(np.argmin(width))
    assert width[worst] > rho, (
        f"face {worst}: area {geo.face_areas[worst]:.3g}, width {width[worst]:.3g} <= {rho:.3g}"
    )
    return geo


# --------------------------------------------------------------------------- the engine's points


def test_depths_equal_up_to_rounding_are_one_point_the_shallowest():
    assert 0.1 + 0.2 != 0.3  # one unit in the last place apart
    z = np.array([0.3, 0.1 + 0.2, 0.3 + 1e-9, 2.0, 2.0 + 1e-13, 0.1 + 0.2])
    pillar = np.array([0, 0, 0, 0, 0, 1])
    pts = unique_points(pillar, z, 2)
    # On pillar 0 (rho = 64 eps * 2.0 = 2.8e-14 m) 0.3 and 0.1 + 0.2 are one point, the shallower;
    # 1e-9 m and 1e-13 m apart are not rounding at these depths.
    assert pts.z.tolist() == [0.3, 0.3 + 1e-9, 2.0, 2.0 + 1e-13, 0.1 + 0.2]
    assert pts.node_of_corner.tolist() == [0, 0, 1, 2, 3, 4]
    assert np.diff(pts.offset).tolist() == [4, 1]
    # The rows variant (corner-point decks) decides the same; NaN is no point.
    rows = np.array([[0.1 + 0.2, np.nan, 0.3, 0.3 + 1e-9, 2.0, 2.0 + 1e-13], [np.nan] * 6])
    ids, count, depths = unique_points_rows(rows)
    assert ids.tolist() == [[0, -1, 0, 1, 2, 3], [-1] * 6]
    assert count.tolist() == [4, 0] and depths.tolist() == [0.3, 0.3 + 1e-9, 2.0, 2.0 + 1e-13]


def test_depth_resolution_is_64_units_in_the_last_place_of_the_largest_depth():
    assert depth_resolution(np.array([3000.0, -1.0, 0.0])).tolist() == [2.0**-46 * 3000.0, 2.0**-46, 0.0]


# --------------------------------------------------------------------------- every deck


def _linear(a: float, b: float):
    return lambda y: a + b * y


def _flat(depth: float) -> Horizon:
    axis = np.linspace(0.0, 100.0, 11)
    return Horizon(axis, axis, np.full((11, 11), depth))


def _horizon_deck(top: float, thickness: float, layers: int, throw, trace=((50.0, -10.0), (50.0, 110.0))):
    faults = [FaultTrace(list(trace), throw, "F")]
    return horizons_to_grdecl([_flat(top), _flat(top + thickness)], layers=layers, faults=faults)


SINE = lambda y: 0.05 * (np.sin(2 * np.pi * y) - 0.5)  # noqa: E731
GENERATED = {
    **{
        f"simple_{drop}_{'flat' if flat else 'wavy'}": (
            lambda d=drop, f=flat: simple_grdecl([10, 8, 5], d, flat=f)
        )
        for drop in (0.0, 0.05, 0.12, 0.25, 0.5)
        for flat in (True, False)
    },
    "simple_sine": lambda: simple_grdecl([10, 8, 5], SINE),
    # Linear throws that meet other layers' depths at pillars (each left faces of ~1e-33 m²).
    "linear_2x2x5": lambda: simple_grdecl([2, 2, 5], _linear(0.0, 0.6), flat=True),
    "linear_4x3x5": lambda: simple_grdecl([4, 3, 5], _linear(1 / 6, 0.1), flat=True),
    "linear_2x3x3": lambda: simple_grdecl([2, 3, 3], _linear(0.1, 0.1), flat=True),
    "linear_2x5x10_collinear": lambda: simple_grdecl(
        [2, 5, 10], _linear(0.0, 0.75), flat=True, undisturbed=True
    ),
    "linear_10x8x5_wavy": lambda: simple_grdecl([10, 8, 5], _linear(0.0, 0.3)),
    "make_model3": lambda: make_model3([30, 20, 6]),
    "cut_make_model3": lambda: cut_grdecl(make_model3([30, 20, 6]), ((5, 20), (3, 15), (1, 5))),
    "horizons_constant_throw": lambda: _horizon_deck(1000.0, 20.0, 4, 2.0),
    "horizons_tip": lambda: _horizon_deck(
        1000.0, 20.0, 4, lambda s: 4.0 * (1.0 - s), ((50.0, -10.0), (50.0, 52.0))
    ),
    "horizons_linear_2_layers": lambda: _horizon_deck(1000.0, 20.0, 3, lambda s: 40.0 / 3.0 * s),
    "horizons_taper_deep": lambda: _horizon_deck(2000.1, 13.3, 7, lambda s: 5.7 * (1.0 - s)),
    "horizons_taper_shallow": lambda: _horizon_deck(0.0, 1.0, 6, lambda s: 0.5 * (1.0 - s)),
    "horizons_oblique": lambda: _horizon_deck(
        0.3, 0.7, 5, lambda s: 0.42 * s, ((-10.0, -5.0), (110.0, 115.0))
    ),
}


@pytest.mark.parametrize("relpath", DECK_FILES)
def test_no_face_of_zero_area_in_any_test_deck(relpath, tmp_path):
    folder = unpack(str(Path(relpath).parent), tmp_path)
    # geometry only: keywords no simulator knows (an export's FACIES) do not matter here
    deck = read_grdecl(folder / Path(relpath).name, unknown_keywords="skip")
    assert_no_face_of_zero_area(process_grdecl(deck).grid)


@pytest.mark.parametrize("name", list(GENERATED))
def test_no_face_of_zero_area_in_generated_decks(name):
    r = process_grdecl(GENERATED[name]())
    assert_no_face_of_zero_area(r.grid)
    assert not [n for n in r.notes if "zero area" in n]  # none was made, so none was removed


# Extruded twins of the horizons decks (same traces and throws) on a Cartesian and a PEBI grid.
EXTRUDED = {
    "linear_2_layers": (1000.0, 20.0, 3, lambda s: 40.0 / 3.0 * s),
    "taper_deep": (2000.1, 13.3, 7, lambda s: 5.7 * (1.0 - s)),
    "taper_shallow": (0.0, 1.0, 6, lambda s: 0.5 * (1.0 - s)),
    "taper_whole_layers": (0.0, 1.0, 3, lambda s: 1.0 - s),  # made an exactly collinear face
    "linear_oblique": (0.3, 0.7, 5, lambda s: 0.42 * s),
}
PEBI = gl.pebi(gl.triangle_grid(np.random.default_rng(7).uniform(0.0, 100.0, (150, 2))))


@pytest.mark.parametrize("areal", ["cart", "pebi"])
@pytest.mark.parametrize("name", list(EXTRUDED))
def test_no_face_of_zero_area_in_extruded_grids(name, areal):
    top, thickness, layers, throw = EXTRUDED[name]
    grid = gl.cart_grid([10, 10], [100.0, 100.0]) if areal == "cart" else PEBI
    fault = FaultTrace([(50.0, -10.0), (50.0, 110.0)], throw, "F")
    r = extrude(grid, [top, top + thickness], layers=layers, faults=[fault])
    assert_no_face_of_zero_area(r.grid)
    assert not [n for n in r.notes if "zero area" in n]
    if areal == "cart":  # the corner-point twin has the same connections (it had extra ones)
        cp = process_grdecl(_horizon_deck(top, thickness, layers, throw))
        assert {tuple(sorted(p)) for p in r.nnc.global_cells.tolist()} == {
            tuple(sorted(p)) for p in cp.nnc.global_cells.tolist()
        }
        assert r.grid.num_faces == cp.grid.num_faces


# --------------------------------------------------------------------------- exact connections


def exact_fault_faces(nx: int, ny: int, nz: int, a: Fraction, b: Fraction) -> Counter:
    """The faces on the fault of ``simple_grdecl([nx, ny, nz], lambda y: a + b * y, flat=True)`` in
    exact rational arithmetic, independently of the engine: (A cell, B cell) global indices, -1 for
    the void above or below a block, counted with multiplicity.

    The fault pillars (x = 0.5) are vertical; on the pair of pillar rows j, j + 1 (s from 0 to 1
    along it) the west cell of layer k lies between the lines z_k and z_(k+1) (z_k = k / (2 nz)), the
    east cell of layer m between z_m + d(s) and z_(m+1) + d(s), d(s) = d_j + s (d_(j+1) - d_j),
    d_j = a + b j / ny. Two of these bands share area iff the thickness of their intersection,
    min(bottoms) - max(tops), a concave piecewise-linear function of s, is positive somewhere:
    at s = 0, s = 1 or where two of the four lines cross.
    """
    far = Fraction(10**6)
    z = [Fraction(k, 2 * nz) for k in range(nz + 1)]
    d = [a + b * Fraction(j, ny) for j in range(ny + 1)]
    west, east = nx // 2 - 1, nx // 2

    def side(i: int, j: int, shift: tuple[Fraction, Fraction]) -> list:
        """Column (i, j) on the pair as (cell, top line, bottom line), the voids above and below
        first and last; a line is (depth at s = 0, depth at s = 1)."""

        def line(depth: Fraction) -> tuple[Fraction, Fraction]:
            return depth + shift[0], depth + shift[1]

        cells = [(i + nx * j + nx * ny * k, line(z[k]), line(z[k + 1])) for k in range(nz)]
        return [(-1, (-far, -far), line(z[0])), *cells, (-1, line(z[nz]), (far, far))]

    def at(line: tuple[Fraction, Fraction], s: Fraction) -> Fraction:
        return line[0] + s * (line[1] - line[0])

    faces: Counter = Counter()
    for j in range(ny):
        for ca, ta, ba in side(west, j, (Fraction(0), Fraction(0))):
            for cb, tb, bb in side(east, j, (d[j], d[j + 1])):
                if ca < 0 and cb < 0:
                    continue
                lines = (ta, tb, ba, bb)
                s_values = {Fraction(0), Fraction(1)}
                for u in range(4):
                    for v in range(u + 1, 4):
                        g0, g1 = lines[u][0] - lines[v][0], lines[u][1] - lines[v][1]
                        if g0 != g1 and 0 < g0 / (g0 - g1) < 1:
                            s_values.add(g0 / (g0 - g1))
                thickness = max(min(at(ba, s), at(bb, s)) - max(at(ta, s), at(tb, s)) for s in s_values)
                if thickness > 0:
                    faces[(ca, cb)] += 1
    return faces


def fault_faces(r, nx: int) -> Counter:
    """The processed grid's faces on the fault pillar pairs: (west cell, east cell), -1 for none."""
    g = r.grid
    im = g.cells.index_map
    owner = np.repeat(np.arange(g.num_cells), np.diff(g.cells.face_pos))
    i = im[owner] % nx
    on = ((i == nx // 2 - 1) & (g.cells.face_tag == E)) | ((i == nx // 2) & (g.cells.face_tag == W))
    faces = np.unique(g.cells.faces[on])
    cells = np.where(g.faces.neighbors[faces] >= 0, im[np.maximum(g.faces.neighbors[faces], 0)], -1)
    east_first = (cells[:, 0] >= 0) & (cells[:, 0] % nx == nx // 2)
    east_first |= (cells[:, 1] >= 0) & (cells[:, 1] % nx == nx // 2 - 1)
    cells[east_first] = cells[east_first][:, ::-1]
    return Counter(map(tuple, cells.tolist()))


def test_linear_throw_gives_exactly_the_connections_of_the_geometry():
    """``simple_grdecl([2, 2, 5], lambda y: 0.6 * y, flat=True)``: layers 0.1 m thick, the east block
    thrown down by 0, 0.3 and 0.6 m at the pillar rows y = 0, 0.5, 1: exactly 3 and 6 layers.

    Pair j = 0 (throw 0 -> 3 layers): west layer k meets east layer m iff 0 <= k - m <= 3: 5 + 4 + 3
    + 2 = 14 faces, 9 of them NNCs (k != m); west layers 0..2 meet the void above the east block
    (3 faces), east layers 2..4 the void below the west block (3): 20 faces.
    Pair j = 1 (throw 3 -> 6 layers): k - m in {3, 4}: (3, 0), (4, 1), (4, 0), 3 faces, all NNCs;
    every west layer meets the void above, every east layer the void below (5 + 5): 13 faces.
    33 faces on the fault, 12 NNCs. West layer 2 and east layer 0 of row 1 only touch at the pillar
    y = 0.5 (0.2 + 0.1 against 0.3 + 0: equal, not in floating point): no face, no NNC (the engine
    made a triangle of 1e-33 m² and an NNC there).
    """
    nx, ny, nz = 2, 2, 5
    r = process_grdecl(simple_grdecl([nx, ny, nz], lambda y: 0.6 * y, flat=True))
    exact = exact_fault_faces(nx, ny, nz, Fraction(0), Fraction(3, 5))
    assert sum(exact.values()) == 33 and fault_faces(r, nx) == exact
    cell_cell = [pair for pair in exact if min(pair) >= 0]
    nnc = {tuple(sorted(p)) for p in cell_cell if p[0] // (nx * ny) != p[1] // (nx * ny)}
    assert len(nnc) == 12 == r.nnc.num and np.all(r.nnc.kind == FAULT)
    assert {tuple(sorted(p)) for p in r.nnc.global_cells.tolist()} == nnc
    assert (3, 10) not in nnc  # east (1, 1, 0) and west (0, 1, 2): they touch at a pillar only
    assert_no_face_of_zero_area(r.grid)


@pytest.mark.parametrize(
    ("dims", "a", "b", "undisturbed"),
    [
        ((4, 3, 5), Fraction(1, 6), Fraction(1, 10), False),
        ((2, 3, 3), Fraction(1, 10), Fraction(1, 10), False),
        ((2, 3, 3), Fraction(1, 12), Fraction(5, 8), True),
        ((2, 5, 10), Fraction(0), Fraction(3, 4), True),  # made an exactly collinear face
        ((2, 1, 6), Fraction(0), Fraction(5, 12), False),
        ((4, 4, 6), Fraction(1, 4), Fraction(1, 3), False),
        ((6, 6, 8), Fraction(1, 16), Fraction(3, 8), False),
    ],
)
def test_linear_throws_give_the_exact_faces_and_nncs(dims, a, b, undisturbed):
    nx, ny, nz = dims
    deck = simple_grdecl(list(dims), lambda y: float(a) + float(b) * y, flat=True, undisturbed=undisturbed)
    r = process_grdecl(deck)
    exact = exact_fault_faces(nx, ny, nz, a, b)
    assert fault_faces(r, nx) == exact
    nnc = {tuple(sorted(p)) for p in exact if min(p) >= 0 and p[0] // (nx * ny) != p[1] // (nx * ny)}
    assert sorted(map(tuple, np.sort(r.nnc.global_cells, axis=1).tolist())) == sorted(nnc)
    assert_no_face_of_zero_area(r.grid)
