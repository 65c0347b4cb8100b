"""gridlib.arrays: array arguments converted, checked and made read-only, or one clear error."""

import numpy as np
import pytest

from gridlib.arrays import frozen_array, point_array
from gridlib.errors import GridError, InputError
from gridlib.grid import Cells, Faces, Layering
from gridlib.structured import cart_grid


def test_frozen_array_adopts_a_fitting_array_and_copies_on_request():
    a = np.arange(4, dtype=np.int64)
    adopted = frozen_array(a, np.int64, "cells.faces", 1)
    assert np.shares_memory(adopted, a) and not a.flags.writeable  # adopted: the owner keeps it
    b = np.arange(4, dtype=np.int64)
    copied = frozen_array(b, np.int64, "x", 1, copy=True)
    assert not np.shares_memory(copied, b) and b.flags.writeable and not copied.flags.writeable
    converted = frozen_array([[1.0, 2.0]], np.int32, "x", 2)
    assert converted.dtype == np.int32 and converted.tolist() == [[1, 2]]
    assert frozen_array(np.arange(6.0)[::2], np.float64, "x", 1).flags.c_contiguous


@pytest.mark.parametrize(
    ("value", "kwargs", "error", "message"),
    [
        ([[1, 2]], {}, GridError, r"^w: expected a 1-D array, got shape \(1, 2\)$"),
        (["a", "b"], {}, GridError, r"^w: expected a 1-D array of int64 \(invalid literal"),
        ([[1, 2]], {"error": InputError}, InputError, r"^w: expected a 1-D array, got shape \(1, 2\)$"),
    ],
)
def test_frozen_array_errors_name_the_argument(value, kwargs, error, message):
    with pytest.raises(error, match=message):
        frozen_array(value, np.int64, "w", 1, **kwargs)


def test_point_array_values():
    got = point_array([(0, 1), (2, 3)], 2, "domain")
    assert got.dtype == np.float64 and got.tolist() == [[0.0, 1.0], [2.0, 3.0]]
    assert point_array(np.zeros((0, 3)), 3, "p", min_points=0).shape == (0, 3)


@pytest.mark.parametrize(
    ("value", "kwargs", "message"),
    [
        ([0.0, 1.0, 2.0], {}, r"^top: points: expected an \(n >= 1, 3\) array of x, y, z, got shape \(3,\)$"),
        ([(0, 0)], {"min_points": 2}, r"^top: points: expected an \(n >= 2, 3\) array of x, y, z, got"),
        (np.zeros((0, 3)), {}, r"got shape \(0, 3\)$"),
        ([(0, 0, 0), ("a", 1, 2)], {}, r"^top: points: expected an \(n >= 1, 3\) array .*could not convert"),
        ([(0, 0, 0), (1, 1, 1), (2, np.inf, 0)], {}, r"^top: points: point 2 is not finite$"),
        ([(0, 0, 0), (1, np.nan, 1)], {"point": "pick"}, r"^top: points: pick 1 is not finite$"),
    ],
)
def test_point_array_errors_name_the_argument_and_the_row(value, kwargs, message):
    with pytest.raises(InputError, match=message):
        point_array(value, 3, "top: points", **kwargs)


def test_point_array_error_class_is_the_callers():
    with pytest.raises(GridError, match=r"^domain: vertex 0 is not finite$"):
        point_array([(np.nan, 0), (1, 0), (1, 1)], 2, "domain", point="vertex", error=GridError)


def test_grid_parts_adopt_their_arrays_and_check_lengths():
    g = cart_grid((2, 1, 1))
    c = g.cells
    with pytest.raises(GridError, match=r"^cells\.face_tag must have one entry per half-face$"):
        Cells(c.face_pos, c.faces, face_tag=np.zeros(3, np.int8))
    with pytest.raises(GridError, match=r"^cells\.index_map must have one entry per cell$"):
        Cells(c.face_pos, c.faces, index_map=[0])
    with pytest.raises(GridError, match=r"^cells\.face_pos: offsets must start at 0 and end at 12"):
        Cells([0, 6, 11], c.faces)
    f = g.faces
    with pytest.raises(GridError, match=r"^faces\.tag must have one entry per face$"):
        Faces(f.node_pos, f.nodes, f.neighbors, tag=np.zeros(2, np.int32))
    with pytest.raises(GridError, match=r"^faces\.neighbors must have shape \(11, 2\), got \(10, 2\)$"):
        Faces(f.node_pos, f.nodes, f.neighbors[:10])
    faces = Faces(f.node_pos, f.nodes, f.neighbors)
    assert faces.tag.tolist() == [0] * 11 and not faces.tag.flags.writeable
    with pytest.raises(
        GridError, match=r"^layering\.layer must have one entry per cell of layering\.column$"
    ):
        Layering(g, [0, 1], [0], 1)
