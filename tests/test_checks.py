"""check_grid passes on every builder and names the broken invariant otherwise."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from seed_points import honeycomb_points, seven_points

import gridlib as gl
from gridlib.grid import Cells, Faces, Nodes

BUILDERS = {
    "cart_2d": lambda: gl.cart_grid([3, 2]),
    "cart_3d": lambda: gl.cart_grid([4, 3, 2], [4, 3, 2]),
    "tensor": lambda: gl.tensor_grid([0, 1, 3, 6], [0, 2, 5], [0, 0.5, 1.5, 3]),
    "twister": lambda: gl.twister(gl.cart_grid([5, 4, 3])),
    "remove_cells": lambda: gl.remove_cells(gl.cart_grid([3, 2]), [1]),
    "extract_subgrid": lambda: gl.extract_subgrid(gl.cart_grid([4, 4, 4]), np.arange(0, 64, 3)).grid,
    "translate": lambda: gl.translate_grid(gl.cart_grid([2, 2, 2]), [1e5, 2e6, 3e3]),
    "triangle": lambda: gl.triangle_grid(seven_points()),
    "surface": lambda: gl.triangle_grid(np.column_stack([seven_points(), [1, 2, 3, 1, 2, 3, 1.5]])),
    "tessellation": lambda: gl.tessellation_grid([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]],
                                                 [[0, 1, 4, 3], [1, 2, 5, 4]]),
    "tetrahedral": lambda: gl.tetrahedral_grid(np.random.default_rng(0).uniform(size=(80, 3))),
    "pebi": lambda: gl.pebi(gl.triangle_grid(honeycomb_points())),
    "layered": lambda: gl.make_layered_grid(gl.pebi(gl.triangle_grid(honeycomb_points())), 3),
    "glue": lambda: gl.glue_2d(gl.cart_grid([2, 2]), gl.translate_grid(gl.cart_grid([3, 3], [1, 2]), [2, 0])),
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(BUILDERS))
def test_every_builder_passes_check_grid(name):
    gl.check_grid(BUILDERS[name]())


def _flip_face(g: gl.Grid, f: int) -> gl.Grid:
    nodes = np.array(g.faces.nodes)
    a, b = g.faces.node_pos[f], g.faces.node_pos[f + 1]
    nodes[a:b] = nodes[a:b][::-1]
    return dataclasses.replace(g, faces=dataclasses.replace(g.faces, nodes=nodes))


def test_flipped_face_is_caught_by_closure():
    g = gl.cart_grid([3, 3, 3])
    with pytest.raises(gl.GridError, match=r"cells not closed .* \[0, 1\]"):
        gl.check_grid(_flip_face(g, 1))  # x-face between cells 0 and 1


def test_missing_half_face_is_caught():
    g = gl.cart_grid([3, 3, 3])
    cells = Cells(np.concatenate([[0], g.cells.face_pos[1:] - 1]), g.cells.faces[1:])
    with pytest.raises(
        gl.GridError, match=r"half-faces missing from cells.faces \(face, cell\): \[\(0, 0\)\]"
    ):
        gl.check_grid(dataclasses.replace(g, cells=cells))


def test_duplicated_face_is_caught():
    g = gl.cart_grid([2, 2, 2])
    f = g.faces
    faces = Faces(
        np.concatenate([f.node_pos, [f.node_pos[-1] + 4]]),
        np.concatenate([f.nodes, f.nodes[:4]]),
        np.concatenate([f.neighbors, [[-1, 0]]]),
    )
    cells = Cells(
        np.concatenate([[0], g.cells.face_pos[1:] + 1]),
        np.concatenate([g.cells.faces[:6], [g.num_faces], g.cells.faces[6:]]),
    )
    with pytest.raises(gl.GridError, match=rf"same nodes as another face: \[{g.num_faces}\]"):
        gl.check_grid(dataclasses.replace(g, faces=faces, cells=cells))


def test_half_face_in_the_wrong_cell_is_caught():
    """Cell 1 lists the x-face between cells 0 and 1 twice and cell 0 not at all: counts per face
    stay right, only the cells differ (the O(n) transpose check sums the cells per face)."""
    g = gl.cart_grid([3, 1, 1])
    faces = np.array(g.cells.faces)
    first = g.cells.face_pos[0]
    shared = np.flatnonzero((g.faces.neighbors == [0, 1]).all(axis=1))[0]
    slot = first + int(np.flatnonzero(faces[first : g.cells.face_pos[1]] == shared)[0])
    other = g.cells.face_pos[1] + int(
        np.flatnonzero(faces[g.cells.face_pos[1] : g.cells.face_pos[2]] != shared)[0]
    )
    faces[slot], faces[other] = faces[other], faces[slot]  # cell 0 takes a face of cell 1 and vice versa
    with pytest.raises(gl.GridError, match=r"cells list faces they are not a neighbour of \(face, cell\)"):
        gl.check_grid(dataclasses.replace(g, cells=Cells(g.cells.face_pos, faces)))


def test_face_listed_twice_by_one_neighbour_and_not_by_the_other_is_caught():
    """Faces F (the x-face between cells 0 and 1) and G (cell 0's west face, made to join 0 and 1):
    cell 0 lists F twice and not G, cell 1 lists G twice and not F. Every half-face names a
    neighbour and every face has two half-faces; only the cells per face differ."""
    g = gl.cart_grid([2, 1, 1])
    nb = np.array(g.faces.neighbors)
    west, shared = 0, 1  # MRST numbering: x-faces of row 0 are 0, 1, 2
    assert nb[west].tolist() == [-1, 0] and nb[shared].tolist() == [0, 1]
    nb[west] = [0, 1]
    c0 = [f for f in g.cells.faces[: g.cells.face_pos[1]] if f not in (west, shared)]
    c1 = [f for f in g.cells.faces[g.cells.face_pos[1] :] if f != shared]
    cells = Cells(
        np.array([0, len(c0) + 2, len(c0) + len(c1) + 4]), np.array([shared, shared, *c0, west, west, *c1])
    )
    broken = dataclasses.replace(g, cells=cells, faces=dataclasses.replace(g.faces, neighbors=nb))
    with pytest.raises(gl.GridError) as err:
        gl.check_grid(broken)
    assert "half-faces missing from cells.faces (face, cell): [(0, 0), (1, 1)]" in str(err.value)
    assert "cells list the same face twice (face, cell): [(0, 1), (1, 0)]" in str(err.value)


def test_face_repeating_a_node_and_duplicates_among_mixed_faces_are_caught():
    """A triangle face 0-1-1 and, among faces of 3 and 4 nodes, two faces with one node set in
    other orders: each is named, and only the later copy is a duplicate."""
    g = gl.cart_grid([2, 2, 2])
    f = g.faces
    a = f.nodes[f.node_pos[5] : f.node_pos[6]]
    extra = [a[[2, 3, 0, 1]], a[:3], a[[2, 1, 0]], np.array([a[0], a[1], a[1]])]
    pos = np.concatenate([f.node_pos, f.node_pos[-1] + np.cumsum([e.size for e in extra])])
    faces = Faces(pos, np.concatenate([f.nodes, *extra]), np.concatenate([f.neighbors, [[-1, 0]] * 4]))
    n = g.num_faces
    cells = Cells(
        np.concatenate([[0], g.cells.face_pos[1:] + 4]),
        np.concatenate([g.cells.faces[:6], np.arange(n, n + 4), g.cells.faces[6:]]),
    )
    with pytest.raises(gl.GridError) as err:
        gl.check_grid(dataclasses.replace(g, faces=faces, cells=cells))
    assert f"faces repeating a node: [{n + 3}]" in str(err.value)
    assert f"faces with the same nodes as another face: [{n}, {n + 2}]" in str(err.value)


def test_index_errors_and_orphans_are_caught():
    g = gl.cart_grid([2, 2])
    nb = np.array(g.faces.neighbors)
    nb[0] = [-1, 9]
    with pytest.raises(
        gl.GridError, match=r"faces.neighbors: index 9 outside \[-1, 4\) \(there are 4 cells\)"
    ):
        gl.check_grid(dataclasses.replace(g, faces=dataclasses.replace(g.faces, neighbors=nb)))
    extra = Nodes(np.vstack([g.nodes.coords, [[5.0, 5.0]]]))
    with pytest.raises(gl.GridError, match=r"nodes used by no face: \[9\]"):
        gl.check_grid(dataclasses.replace(g, nodes=extra))


def test_inverted_cell_is_caught():
    g = gl.cart_grid([2, 1])
    mirrored = Nodes(g.nodes.coords * [-1.0, 1.0])
    with pytest.raises(gl.GridError, match="cells with non-positive area: \\[0, 1\\]"):
        gl.check_grid(dataclasses.replace(g, nodes=mirrored))


def test_swapped_neighbours_on_a_surface_are_caught():
    pts = np.random.default_rng(1).uniform(size=(20, 2))
    g = gl.triangle_grid(np.column_stack([pts, pts[:, 0] ** 2]))
    nb = np.array(g.faces.neighbors)
    inner = int(np.flatnonzero((nb >= 0).all(axis=1))[0])
    nb[inner] = nb[inner, ::-1]
    bad = dataclasses.replace(g, faces=dataclasses.replace(g.faces, neighbors=nb))
    with pytest.raises(gl.GridError, match="2-D cell boundaries are not oriented cycles"):
        gl.check_grid(bad)


def test_geometry_of_another_grid_is_caught():
    with pytest.raises(gl.GridError, match="the geometry has 9 cells and 24 faces, the grid 4 and 12"):
        gl.check_grid(gl.cart_grid([2, 2]), gl.compute_geometry(gl.cart_grid([3, 3])))


def test_dangling_edge_in_a_cell_is_caught():
    from gridlib.connectivity import cell_node_cycles_2d

    tri = gl.triangle_grid([[0, 0], [1, 0], [0, 1]])
    extra = Nodes(np.vstack([tri.nodes.coords, [[2.0, 2.0]]]))
    faces = Faces(
        np.arange(0, 9, 2),
        np.concatenate([tri.faces.nodes, [3, 1]]),
        np.vstack([tri.faces.neighbors, [[0, -1]]]),
    )
    cells = Cells([0, 4], [0, 1, 2, 3])
    g = gl.Grid(cells, faces, extra, 2)
    with pytest.raises(gl.GridError, match=r"cell 0: a node (starts|ends) two edges"):
        cell_node_cycles_2d(g)


# --- a deck's grid: broken is an error, degenerate is kept (check_deck_grid) ---------------------------


def test_wedges_beside_a_fault_are_degenerate_not_broken():
    """Thin wedges (three of four corners collapsed) beside a fault: two cells' polyhedral volumes
    are below zero while their ECLIPSE bulk volumes (Flow's) are positive. check_grid refuses
    them, check_deck_grid keeps and names them."""
    from wedge_decks import wedge_deck

    from gridlib.checks import check_deck_grid
    from gridlib.cornerpoint.process import process_grdecl

    r = process_grdecl(wedge_deck())
    geo = gl.compute_geometry(r.grid)
    with pytest.raises(gl.GridError, match=r"cells with non-positive volume: \[53, 55\]"):
        gl.check_grid(r.grid, geo)
    cells = check_deck_grid(r.grid, geo)
    assert cells.non_positive_volume.tolist() == [53, 55] and cells.not_closed.size == 0
    assert (geo.cell_volumes[cells.cells] < 0).all() and (r.bulk_volumes[cells.cells] > 0).all()
    assert cells.flags(r.grid.num_cells).tolist() == [0] * 53 + [1, 0, 1] + [0] * 44
    (note,) = cells.notes(r.grid)
    assert (
        note.startswith("2 cells with a non-positive polyhedral volume") and "(3, 7, 2), (3, 8, 2) (" in note
    )


def test_faces_that_do_not_close_are_degenerate():
    """A face normal tilted by 1e-3 of its area: its two cells no longer close."""
    g = gl.cart_grid([3, 1, 1], [300.0, 100.0, 10.0])
    geo = gl.compute_geometry(g)
    normals = np.array(geo.face_normals)
    normals[1] += [0.0, 0.0, 1e-3 * geo.face_areas[1]]  # the face between cells 0 and 1
    tilted = dataclasses.replace(geo, face_normals=normals)
    from gridlib.checks import check_deck_grid

    cells = check_deck_grid(g, tilted)
    assert cells.not_closed.tolist() == [0, 1] and cells.non_positive_volume.size == 0
    surface = 4 * 100.0 * 10.0 + 2 * 100.0 * 100.0  # each cell's: four lateral faces, top, bottom
    np.testing.assert_allclose(cells.closure, 1e-3 * 1000.0 / surface, rtol=1e-9)
    with pytest.raises(gl.GridError, match=r"cells not closed .* \[0, 1\]"):
        gl.check_grid(g, tilted)


def test_a_broken_deck_grid_is_still_an_error():
    from gridlib.checks import check_deck_grid

    g = gl.cart_grid([2, 1, 1])
    nb = np.array(g.faces.neighbors)
    nb[1] = [0, 0]
    message = r"faces with the same cell on both sides: \[1\] \(cells \(1, 1, 1\)\); .* \(cells \(2, 1, 1\)\)"
    with pytest.raises(gl.GridError, match=message):  # a grid with logical indices names the cells
        check_deck_grid(dataclasses.replace(g, faces=dataclasses.replace(g.faces, neighbors=nb)))
