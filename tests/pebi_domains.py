"""Domains with re-entrant corners for the PEBI property tests, in cell sizes (before rotation).

Shared by ``voronoi/test_pebi_grid_robust.py`` and ``voronoi/test_pebi_boundary_faults.py``:
rectangles, L-, U- and star-shaped polygons (counter-clockwise) with the indices of their
reflex corners, and the small vector helpers their generators use.
"""

from __future__ import annotations

import numpy as np

UTM = np.array([5.3e5, 6.7e6])  # m: a typical UTM origin, to check the local frame


def rot(a: float) -> np.ndarray:
    """The rotation by ``a`` radians."""
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def unit(a: float) -> np.ndarray:
    """The unit vector at ``a`` radians."""
    return np.array([np.cos(a), np.sin(a)])


def domain(rng, shape: str) -> tuple[np.ndarray, list[int]]:
    """A ``shape`` ("rect", "L", "U" or "star") domain in cell sizes and its reflex corners."""
    if shape == "rect":
        w, h = rng.uniform(12, 18), rng.uniform(10, 14)
        return np.array([(0, 0), (w, 0), (w, h), (0, h)]), []
    if shape == "L":
        w, h = rng.uniform(14, 18), rng.uniform(12, 16)
        a, b = rng.uniform(0.35, 0.6) * h, rng.uniform(0.35, 0.6) * w
        return np.array([(0, 0), (w, 0), (w, a), (b, a), (b, h), (0, h)]), [3]
    if shape == "U":
        w, h = rng.uniform(16, 20), rng.uniform(12, 16)
        c = rng.uniform(0.35, 0.55) * h
        x0 = rng.uniform(0.25, 0.35) * w
        x1 = w - rng.uniform(0.25, 0.35) * w
        return np.array([(0, 0), (w, 0), (w, h), (x1, h), (x1, c), (x0, c), (x0, h), (0, h)]), [4, 5]
    n = int(rng.integers(5, 8))  # a star
    r_out, r_in = 10.0, rng.uniform(0.5, 0.7) * 10.0
    th = rng.uniform(0, 2 * np.pi) + np.pi * np.arange(2 * n) / n
    r = np.where(np.arange(2 * n) % 2 == 0, r_out, r_in) * rng.uniform(0.9, 1.1, 2 * n)
    return np.column_stack([r * np.cos(th), r * np.sin(th)]), list(range(1, 2 * n, 2))


def inward(poly: np.ndarray, k: int) -> np.ndarray:
    """The direction into the domain bisecting the (reflex) corner k of a counter-clockwise polygon."""
    a, b = poly[k - 1] - poly[k], poly[(k + 1) % len(poly)] - poly[k]
    u = a / np.linalg.norm(a) + b / np.linalg.norm(b)
    return -u / np.linalg.norm(u)  # at a reflex corner the edges' bisector points outwards
