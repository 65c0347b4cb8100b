"""The pillar engine shared by corner-point and 2.5D grids.

``points`` (unique points per pillar as integer ranks), ``lateral`` (faces between the two columns
of a pillar pair, subdivided where fault throw makes corners mismatch), ``conformal`` (crossing
nodes in the edges of top/bottom faces), ``nnc`` (non-neighbour connections), ``faults`` (fault
traces and the hanging-wall displacement), ``columns`` (the engine on the columns of any areal
2-D grid) and ``extrude`` (its front end: layers between horizons, with faults). The corner-point
front end is :mod:`gridlib.cornerpoint.process`.
"""
