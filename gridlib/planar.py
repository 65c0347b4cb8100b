"""Small 2-D primitives shared by the planar builders: cross products, circumcentres, merging
points that lie within a tolerance of each other.

Points are ``(..., 2)`` float arrays (x, y in the last axis). Everything here is plain numpy /
scipy with no state, so results are the same bits whoever calls it.

>>> cross2(np.array([1.0, 0.0]), np.array([0.0, 2.0]))
np.float64(2.0)
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

__all__ = ["circumcentres", "cross2", "group_pairs", "merge_close_points"]


def cross2(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The z component of the cross product of 2-D vectors: ``u_x v_y - u_y v_x``.

    Positive when ``v`` turns counter-clockwise from ``u``; twice the signed area of the
    triangle (0, u, v). Broadcasts over the leading axes.

    >>> cross2(np.array([[1.0, 0.0], [1.0, 1.0]]), np.array([[0.0, 1.0], [2.0, 2.0]])).tolist()
    [1.0, 0.0]
    """
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def circumcentres(xy: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Centres (m, 2) of the circles through the corners of triangles ``tri`` (m, 3) of points ``xy``.

    Computed relative to the first corner (fewer digits lost far from the origin). A degenerate
    (collinear) triangle gives inf or nan, silently: callers check.

    >>> xy = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    >>> circumcentres(xy, np.array([[0, 1, 2]])).tolist()
    [[1.0, 1.0]]
    """
    a = xy[tri[:, 0]]
    b = xy[tri[:, 1]] - a
    c = xy[tri[:, 2]] - a
    d = 2.0 * cross2(b, c)
    b2, c2 = (b * b).sum(axis=1), (c * c).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = (c[:, 1] * b2 - b[:, 1] * c2) / d
        uy = (b[:, 0] * c2 - c[:, 0] * b2) / d
    return a + np.column_stack([ux, uy])


def group_pairs(n: int, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Groups of ``n`` items joined, directly or through others, by the index ``pairs`` (k, 2).

    Returns ``(representative, inverse)``: the lowest item of every group, groups numbered in
    the order of their lowest items, and the group of every item
    (``representative[inverse]`` is the representative of every item).

    >>> rep, inv = group_pairs(5, np.array([[3, 1], [4, 0]]))
    >>> rep.tolist(), inv.tolist()
    ([0, 1, 2], [0, 1, 2, 1, 0])
    """
    pairs = np.asarray(pairs).reshape(-1, 2)
    if pairs.size:
        graph = sparse.coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, label = csgraph.connected_components(graph, directed=False)
    else:
        label = np.arange(n)
    _, representative, inverse = np.unique(label, return_index=True, return_inverse=True)
    return representative, inverse


def merge_close_points(xy: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 2) closer than ``tol`` to each other, directly or through a chain of points, as one.

    Returns ``(representative, inverse)`` as :func:`group_pairs`: ``xy[representative]`` are
    the merged points (the lowest-numbered point of every group stands for it) and
    ``inverse`` (n,) the merged point of every input point.

    >>> xy = np.array([[0.0, 0.0], [5.0, 0.0], [0.05, 0.0], [0.1, 0.0]])
    >>> rep, inv = merge_close_points(xy, 0.06)
    >>> rep.tolist(), inv.tolist()
    ([0, 1], [0, 1, 0, 0])
    """
    pairs = cKDTree(xy).query_pairs(tol, output_type="ndarray")
    return group_pairs(xy.shape[0], pairs)
