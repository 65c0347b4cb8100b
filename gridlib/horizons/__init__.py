"""Horizons: depth surfaces from points, grids or formulas, per fault block, ordered, as a Dataset.

The horizons stage of a case: every horizon becomes a depth
map on one areal lattice, the stack is checked or repaired so that depths never
decrease downwards, and the result is an :class:`xarray.Dataset` with dims
``(horizon, y, x)`` written as ``horizons.nc``. Each horizon of it is a
:class:`~gridlib.pillars.horizon_maps.Horizon` for ``horizons_to_grdecl``
(:func:`to_horizons`). Files are read and written by :mod:`gridlib.io.horizon_files`
(and :mod:`gridlib.io.irap`), which sit above this package.

Conventions: x, y and z in metres; **z is depth, positive downwards**; NaN means
undefined (no data there). A lattice is given by its increasing 1-D axes ``x``
(nx,) and ``y`` (ny,) and maps are ``z[j, i]`` at ``(x[i], y[j])``.

Picks of already-faulted surfaces (the throw is in them):
:func:`gridlib.io.horizon_files.build_horizons` with ``faults=...,
per_block=True`` interpolates every fault block from its own picks
over the whole lattice, and :func:`horizons_to_grdecl_by_block` gives each
corner-point cell the corners of its own block, so the offset is exact at the
trace (:mod:`.by_block`).

Inputs
------
* scattered picks: :func:`~gridlib.io.horizon_files.read_points` (CSV or whitespace x y z text), then
  :func:`interpolate_points` (onto a lattice) or :func:`interpolate_points_at`
  (at any points, e.g. the areal nodes of a PEBI grid);
* gridded surfaces: :class:`Surface` (a regular, possibly rotated lattice), read
  from IRAP classic ASCII (:func:`gridlib.io.irap.read_irap`) or netCDF
  (:func:`~gridlib.io.horizon_files.read_surface_netcdf`) and resampled with :meth:`Surface.sample`;
* formulas: :func:`plane` (dip and azimuth), :func:`dome`, :func:`peaks`
  (MATLAB's, as in the MRST book's ``convertHorizonsToGrid`` example).

Interpolation of points (:func:`interpolate_points_at`)
-------------------------------------------------------
``method``: ``"linear"`` (Delaunay, C0; scipy's ``griddata`` linear),
``"cubic"`` (Clough-Tocher, C1), ``"rbf"`` (thin-plate spline with a
linear polynomial: scipy's ``RBFInterpolator`` interpolant, solved by
:mod:`gridlib.horizons.rbf` so that it has the same bits on every machine;
optional ``smoothing``, local ``neighbors`` for large point sets) or ``"nearest"``. Planes are reproduced
exactly by ``linear`` and ``rbf`` (to round-off), data points by every method
with ``smoothing=0``. Before any of them, x and y are shifted to the points'
mean and divided by the larger side of their bounding box, so results
(``smoothing`` in particular) do not depend on the units or on UTM offsets.

Extrapolation policy, the same for every method: a node is *inside* when it
lies in the convex hull of the points used (of its fault block); outside,
``extrapolation`` decides:

* ``"nan"`` (default): undefined. ``horizons_to_grdecl`` makes cells with an
  undefined corner inactive, so the grid shrinks to where data are;
* ``"nearest"``: the interpolated value at the nearest point of the hull
  (constant along the outward normal, continuous at the hull);
* ``"trend"``: that value continued with the gradient of the least-squares
  plane through the points: z(p) = f(q) + g . (p - q), q the nearest hull
  point. Continuous at the hull and exact for planes.

The RBF's own extrapolation (which can be wild) is therefore never used.

Fault blocks
------------
With ``faults`` (polylines in plan view: (n, 2) arrays or
:class:`~gridlib.cornerpoint.between_horizons.FaultTrace`), the area (``extent``, by
default the bounding box of the points and the targets) is cut by the traces
into blocks (shapely's polygonize of the traces clipped to the area, their ends
extended by 1e-7 of its diagonal so that a trace ending on another one or on
the boundary closes a block); points and targets are classified by exact
point-in-polygon, and every block is interpolated from its own points only, so
a throw is never smeared across a trace. Points on a trace (within 1e-9 of the
diagonal) belong to no block and are not used; targets on a trace take the
block with the lowest id among those touching them (blocks are numbered by
their centroids, x then y); anything outside the area takes the nearest block.
A trace that ends inside the area without meeting another trace or the
boundary separates nothing (polygonize drops it): it is reported in ``notes``
and the throw is interpolated across it. Let traces run to or beyond the
lattice's edge, as for ``horizons_to_grdecl``.

Ordering
--------
:func:`order_horizons` (and :func:`horizon_dataset`): horizons are listed top
(youngest) first. Where a horizon is shallower than the nearest defined one
above it, the two *cross*. ``"error"`` raises :class:`HorizonCrossingError`
naming each crossing pair, its node count and area (the nodes' tributary
areas), its first node (lowest y, then x) and its largest overlap;
``"erode"`` (younger wins: z_k = max(z_k, z_j) for all j above, a top-down
running maximum) and ``"onlap"`` (older wins: z_k = min(z_k, z_j) for all j
below, a bottom-up running minimum) repair it, so that no thickness is
negative. Never by sorting, which moves volume between zones.
"""

from ._constants import EXTRAPOLATIONS, METHODS, ORDERINGS
from .analytic import dome, peaks, plane
from .blocks import FaultBlocks, fault_blocks
from .build import HorizonSource, check_lattice, horizons_from_sources
from .by_block import block_horizons, horizons_to_grdecl_by_block
from .dataset import horizon_dataset, to_horizons
from .interpolate import interpolate_points, interpolate_points_at
from .ordering import Crossing, HorizonCrossingError, find_crossings, order_horizons
from .surface import Surface

__all__ = [
    "EXTRAPOLATIONS",
    "METHODS",
    "ORDERINGS",
    "Crossing",
    "FaultBlocks",
    "HorizonCrossingError",
    "HorizonSource",
    "Surface",
    "block_horizons",
    "check_lattice",
    "dome",
    "fault_blocks",
    "find_crossings",
    "horizon_dataset",
    "horizons_from_sources",
    "horizons_to_grdecl_by_block",
    "interpolate_points",
    "interpolate_points_at",
    "order_horizons",
    "peaks",
    "plane",
    "to_horizons",
]
