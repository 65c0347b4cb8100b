"""compute_geometry keeps its bits: faster code must do the same floating-point operations in
the same order, so that artifacts and goldens never move when only the speed changes."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import gridlib as gl
from gridlib import geometry

FIELDS = ("cell_volumes", "cell_centroids", "face_areas", "face_normals", "face_centroids")


def _warped_pebi_prisms() -> gl.Grid:
    """12,000 PEBI prisms with jittered nodes: faces of 3 to 11 nodes, interleaved (quads in
    several blocks of index-gathered faces), none of them planar."""
    areal = gl.pebi(gl.triangle_grid(np.random.default_rng(7).uniform(size=(1500, 2)) * 100))
    prisms = gl.make_layered_grid(areal, thickness=[2.0, 3.0, 1.0, 2.5, 1.5, 2.0, 1.0, 3.0])
    coords = np.array(prisms.nodes.coords)
    coords += np.random.default_rng(3).uniform(-0.2, 0.2, size=coords.shape)
    return gl.Grid(prisms.cells, prisms.faces, gl.Nodes(coords), 3)


def _faulted_corner_point() -> gl.Grid:
    """A small faulted anticline (make_model3): quads in one run, faces on one side only."""
    return gl.process_grdecl(gl.make_model3([20, 16, 6])).grid


def _digest(geo: gl.Geometry) -> str:
    h = hashlib.sha256()
    for name in FIELDS:
        h.update(np.ascontiguousarray(getattr(geo, name)).tobytes())
    return h.hexdigest()


@pytest.mark.parametrize(
    ("build", "sizes", "digest"),
    [
        # The digests of commit 6270751 (before the per-face buffers): every bit is kept.
        (
            _warped_pebi_prisms,
            [0, 0, 0, 108, 37705, 3843, 3888, 2574, 999, 369, 72, 54],
            "3046d436b55ae48a69fa19a8b96587a092a19cbb1131afd70dc7b9e07ed7f8ed",
        ),
        (
            _faulted_corner_point,
            [0, 0, 0, 0, 5113],
            "bdda0429185ed538c15039cebe2122e62b41dc189fd56044402f426330a184ad",
        ),
    ],
)
def test_geometry_has_the_bits_of_the_published_path(build, sizes, digest):
    g = build()
    assert np.bincount(np.diff(g.faces.node_pos)).tolist() == sizes  # the mix the digest covers
    assert _digest(gl.compute_geometry(g)) == digest


def test_face_arithmetic_does_not_depend_on_how_many_faces_share_an_operation(monkeypatch):
    """Sub-blocks of 5 faces (instead of thousands) give the same bits: every per-face value is
    computed face by face, whatever the block layout and face size."""
    g = _warped_pebi_prisms()
    reference = gl.compute_geometry(g)
    monkeypatch.setattr(geometry, "_SUB", 5)
    small = gl.compute_geometry(g)
    for name in FIELDS:
        assert np.array_equal(getattr(small, name), getattr(reference, name)), name
