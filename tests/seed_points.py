"""Point sets of the MRST book's chapter 3 examples (the seed), as the book builds them."""

from __future__ import annotations

import numpy as np


def honeycomb_points() -> np.ndarray:
    """§3.2.2: [x,y] = meshgrid((0:4)*2*cos(pi/6), 0:3) plus the same shifted by (cos, sin)(pi/6)."""
    x, y = np.meshgrid(np.arange(5) * 2 * np.cos(np.pi / 6), np.arange(4.0))
    x, y = x.ravel(order="F"), y.ravel(order="F")
    return np.column_stack(
        [np.concatenate([x, x + np.cos(np.pi / 6)]), np.concatenate([y, y + np.sin(np.pi / 6)])]
    )


def ring(radius: float, n: int) -> np.ndarray:
    """MATLAB's cylinder(r, n) first row without its duplicated closing point."""
    theta = np.arange(n) / n * 2 * np.pi
    return np.column_stack([radius * np.cos(theta), radius * np.sin(theta)])


def radial_points() -> np.ndarray:
    """§3.3.2 Example 2: rings r = exp(-3.5:.25:0) of 16 points, plus the origin."""
    rings = [ring(r, 16) for r in np.exp(np.arange(-3.5, 1e-9, 0.25))]
    return np.unique(np.concatenate([*rings, [[0.0, 0.0]]]), axis=0)


def seven_points() -> np.ndarray:
    """§3.4 Example 2, rows sorted."""
    p = np.array([[0.0, 1.0, 0.9, 0.1, 0.6, 0.3, 0.75], [0.0, 0.0, 0.8, 0.9, 0.2, 0.6, 0.45]]).T
    return p[np.lexsort((p[:, 1], p[:, 0]))]
