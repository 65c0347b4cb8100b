"""The pillar engine shared by corner-point and 2.5D grids (``docs/pillar-grids.md``).

``pillar_points`` (unique points per pillar as integer ranks), ``lateral`` (faces between the two
columns of a pillar pair, subdivided where fault throw makes corners mismatch), ``conformal``
(crossing nodes in the edges of top/bottom faces), ``nnc`` (non-neighbour connections),
``fault_traces`` (fault traces and the hanging-wall displacement), ``fault_surface`` (inclined
fault surfaces from a dip or from fault sticks), ``columns`` (the engine on the
columns of any areal 2-D grid, in phases: ``column_inputs``, ``column_nodes``, ``column_lateral``,
``column_top_bottom``, ``column_assembly``) and ``extrude`` (its front end: layers between
horizons, with faults). Shared by both front ends: ``horizon_maps`` (gridded horizons),
``ordering`` (the depth order of a horizon stack: check, erode, onlap) and ``zones`` (layers per
zone). The corner-point front end is :mod:`gridlib.cornerpoint.process`.
"""
