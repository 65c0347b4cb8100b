"""PEBI (Voronoi) grids: the dual of a triangulation, and (later) site-based builders."""

from .dual import pebi

__all__ = ["pebi"]
