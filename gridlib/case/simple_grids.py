"""Build the grid a validated case describes (the ``grid`` and ``domain`` keys) for the
cartesian, tensor and layered (areal pebi) grid types."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..config import Case
from ..errors import GridError, InputError
from ..geometry import compute_geometry
from ..grid import Grid
from ..layered import make_layered_grid
from ..structured import cart_grid, tensor_grid, translate_grid, twister
from ..subgrid import remove_cells
from ..unstructured import triangle_grid
from ..voronoi import pebi
from .axes import axis
from .sites import areal_sites


def _grid_from_spec(spec: dict[str, Any]) -> Grid:
    kind = spec["type"]
    if kind == "cartesian":
        dims = spec["dims"]
        g = cart_grid(dims, spec.get("lengths"))
        if spec["twist"]:
            g = twister(g, spec["twist"])
        if spec.get("origin") is not None:
            if len(spec["origin"]) != len(dims):
                raise GridError(f"origin has {len(spec['origin'])} values but dims has {len(dims)}")
            g = translate_grid(g, spec["origin"])
        return g
    if kind == "tensor":
        axes = [axis(spec[a]) for a in ("x", "y", "z") if a in spec]
        return tensor_grid(*axes)
    sites = areal_sites(spec["areal"]["sites"])
    areal = pebi(triangle_grid(sites))
    layers = spec["layers"]
    thickness = layers.get("thickness") or [1.0] * int(layers["num_layers"])
    top = float(layers["top"])
    depths = top + np.concatenate([[0.0], np.cumsum(thickness)])
    return make_layered_grid(areal, depths=depths)


def _apply_domain(grid: Grid, domain: dict[str, Any]) -> Grid:
    centroids = compute_geometry(grid).cell_centroids
    keep = np.ones(grid.num_cells, dtype=bool)
    d = grid.dim
    if "ellipsoid" in domain:
        e = domain["ellipsoid"]
        if len(e["center"]) != d or len(e["semi_axes"]) != d:
            raise GridError(f"domain.ellipsoid: center and semi_axes need {d} values for this grid")
        r = ((centroids - e["center"]) / np.asarray(e["semi_axes"])) ** 2
        keep &= r.sum(axis=1) <= 1.0
    if "box" in domain:
        b = domain["box"]
        if len(b["min"]) != d or len(b["max"]) != d:
            raise GridError(f"domain.box: min and max need {d} values for this grid")
        keep &= np.all((centroids >= b["min"]) & (centroids <= b["max"]), axis=1)
    if not keep.any():
        raise GridError("domain: no cell centroid lies inside the domain")
    return remove_cells(grid, ~keep) if not keep.all() else grid


def build_grid(case: Case) -> Grid:
    """The grid of a validated case. Errors name the case file and the key."""
    try:
        grid = _grid_from_spec(case.data["grid"])
        if case.data.get("domain"):
            grid = _apply_domain(grid, case.data["domain"])
    except GridError as exc:
        raise InputError(f"{case.path}: grid: {exc}") from exc
    return grid
