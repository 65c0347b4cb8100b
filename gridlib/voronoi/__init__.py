"""Voronoi (PEBI) grids: the dual of a triangulation (``pebi``).

The package is named ``voronoi`` so that ``gridlib.pebi`` stays the MRST-named
function and ``import gridlib.voronoi.dual`` works.
"""

from .dual import pebi

__all__ = ["pebi"]
