"""The pillar engine shared by corner-point and 2.5D grids.

``points`` (unique points per pillar as integer ranks), ``lateral`` (faces between the two columns
of a pillar pair, subdivided where fault throw makes corners mismatch), ``vertical`` and
``conformal`` (top/bottom faces, crossing nodes in their edges), ``faults`` (fault traces and the
hanging-wall displacement), ``columns`` (the engine on the columns of any areal 2-D grid) and
``extrude`` (its front end: layers between horizons, with faults).
"""
