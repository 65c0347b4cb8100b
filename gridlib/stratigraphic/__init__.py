"""The pillar engine shared by corner-point and 2.5D PEBI grids: points, lateral and vertical faces."""
