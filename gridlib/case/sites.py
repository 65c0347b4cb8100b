"""The areal sites of a case's layered pebi grid (``grid.areal.sites``): hexagonal, square,
radial patterns or the listed points."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..reproducible import exp


def hexagonal_sites(counts: list[int], spacing: float, origin: list[float] | None) -> np.ndarray:
    """The MRST book's honeycomb sites: columns at x = 2 i cos30, rows y = j, plus the
    same shifted by (cos30, sin30); all scaled by ``spacing`` (nearest-neighbour distance)."""
    c = np.cos(np.pi / 6)
    i, j = np.meshgrid(np.arange(counts[0]), np.arange(counts[1]), indexing="ij")
    x, y = (2 * c * i).ravel(), j.astype(float).ravel()
    pts = np.column_stack([np.concatenate([x, x + c]), np.concatenate([y, y + np.sin(np.pi / 6)])])
    return pts * spacing + np.asarray(origin or [0.0, 0.0])


def radial_sites(center: list[float] | None, radii: Any, sectors: int) -> np.ndarray:
    """Rings of ``sectors`` sites at the given radii around ``center``, plus the centre."""
    if isinstance(radii, dict):
        logs = np.arange(radii["log_start"], radii["log_stop"] + 1e-9 * radii["log_step"], radii["log_step"])
        r = exp(logs)
    else:
        r = np.asarray(radii, dtype=np.float64)
    theta = np.arange(sectors) / sectors * 2 * np.pi
    rings = (r[:, None, None] * np.stack([np.cos(theta), np.sin(theta)], axis=-1)[None]).reshape(-1, 2)
    pts = np.unique(np.concatenate([rings, [[0.0, 0.0]]]), axis=0)
    return pts + np.asarray(center or [0.0, 0.0])


def areal_sites(spec: dict[str, Any]) -> np.ndarray:
    """The sites of ``grid.areal.sites``: its ``pattern``, or its ``xy`` points."""
    pattern = spec["pattern"]
    if pattern == "hexagonal":
        return hexagonal_sites(spec["counts"], spec["spacing"], spec.get("origin"))
    if pattern == "square":
        nx, ny = spec["counts"]
        x, y = np.meshgrid(np.arange(nx) * spec["spacing"], np.arange(ny) * spec["spacing"])
        return np.column_stack([x.ravel(), y.ravel()]) + np.asarray(spec.get("origin") or [0.0, 0.0])
    if pattern == "radial":
        return radial_sites(spec.get("center"), spec["radii"], spec["sectors"])
    return np.asarray(spec["xy"], dtype=np.float64)
