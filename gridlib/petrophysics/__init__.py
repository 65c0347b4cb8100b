"""Petrophysics: porosity, permeability and net-to-gross per cell, in depositional coordinates.

Why depositional coordinates: a field sampled at *physical* cell centroids is
shifted by the throw across every fault, so layers deposited together get
uncorrelated values (the MRST book's exercise 3.5.1). Here fields are sampled at
**depositional coordinates** u = (x_r, y_r, w) (:func:`depositional_coordinates`):

* (x_r, y_r), the areal position before faulting, is the position of the
  cell's *column* (logical (i, j) of a corner-point grid, the areal cell of a
  layered grid), the same for every layer of it and independent of the throw
  (faults are vertical; for lateral heave pass restored ``column_xy``);
* w, the stratigraphic coordinate, is the position of the cell's *layer* in a
  reference column of layer thicknesses ``dz_ref`` (m): w = 0 at the top of
  layer 0 and w_k = dz_0 + ... + dz_{k-1} + dz_k / 2 at the middle of layer
  k. One number gives w = (k + 1/2) dz_ref; one per layer describes zones
  (e.g. each zone's mean thickness divided by its number of layers, with
  ``numpy.repeat``).

Two cells in the same layer on either side of a fault are thus as close as
lateral neighbours, whatever the throw, and a grid with throw gets exactly the
values of the same grid without it. The layer index is proportional layering
(``horizons_to_grdecl``, ``make_layered_grid``); where a zone is eroded or
onlaps, its truncated layers keep their w (they are pinched, not renumbered),
which is w measured from the zone's conformable surface as long as the
layering was built from it.

Functions are pure (arrays in, arrays out); a :class:`Rock` holds the result.
The package, one concept a module: :mod:`~gridlib.petrophysics.variogram`
(:class:`Variogram`), :mod:`~gridlib.petrophysics.depositional` (:class:`Depositional`,
:func:`depositional_coordinates`, :func:`layer_index`),
:mod:`~gridlib.petrophysics.random_fields` (:func:`gaussian_field`),
:mod:`~gridlib.petrophysics.rock` (the transforms and :class:`Rock`) and
:mod:`~gridlib.petrophysics.cubes` (:class:`PropertyCube`); every public name is
importable from ``gridlib.petrophysics``.

Units: metres, **z is depth (positive down)**, porosity and NTG as fractions,
permeability in **millidarcy** (mD; 1 mD = 9.869232667160130e-16 m2, :data:`gridlib.units.MILLIDARCY`).

Gaussian random fields
----------------------
:func:`gaussian_field` draws a stationary Gaussian field with a
:class:`Variogram` (gstools' Exponential, Gaussian or Matern covariance,
anisotropic correlation lengths, rotation angles) by gstools' randomisation
method (``gstools.SRF``, Heße et al. 2014): the sum of ``mode_no`` cosine
modes with random wave vectors drawn from the covariance's spectrum, seeded.
The same variogram, seed and positions give the same values, bit for bit (on
one machine and numpy build), and other positions see the same underlying field
to round-off (so a refined or coarsened grid sees the same geology).

At depositional coordinates the positions are a product, columns x layers, and
the modes factorise: cos(k.u) = cos(k_xy.x_r + k_w w) splits into column and
layer terms, so the sum over modes becomes a matrix product of a (columns x
2 modes) by a (2 modes x layers) matrix; when the columns lie on a lattice
(vertical pillars on a rectilinear mesh) k_xy.x_r splits once more into x and
y terms and only the distinct x, y and w need trigonometry. This is gstools'
field exactly (to round-off, checked by the tests) at a cost of O((columns +
layers) modes) or O((nx + ny + layers) modes) trigonometric evaluations
instead of O(cells x modes): 8e5 cells of 200 x 200 columns take about 1 s with
gstools' default of 1000 modes, where gstools' own summation takes 30 to 50 s
on two cores (``bench/petrophysics.py``). Fewer modes are faster and less
accurate (the realised variance scatters by about 1/sqrt(mode_no)); 1000 is
kept. At arbitrary points (an (n, 3) array, e.g. physical centroids) gstools
sums directly.

Porosity and permeability
-------------------------
:func:`normal_porosity` (mean + std Z, clipped), :func:`lognormal_permeability`
(median exp(sigma Z)), :func:`carman_kozeny` (the MRST book's relation, K =
phi^3 d^2 / (72 tau (1 - phi)^2) with grain diameter d = 10 micrometres and
tortuosity factor tau = 0.81: 2.143e-14 m2 = 21.7 mD at phi = 0.2),
:func:`per_layer` (constant, per layer or per zone values) and cubes on a
regular grid (:class:`PropertyCube`, :func:`sample_cube`) sampled at centroids or at
depositional coordinates (their files: :mod:`gridlib.io.cube_files`).

>>> import gridlib as gl
>>> import numpy as np
>>> g = gl.cart_grid([20, 10, 5], [200.0, 100.0, 10.0])
>>> u = depositional_coordinates(g, dz_ref=2.0)
>>> v = Variogram("exponential", var=1.0, len_scale=[100.0, 100.0, 4.0])
>>> z = gaussian_field(u, v, seed=42)
>>> poro = normal_porosity(z, mean=0.2, std=0.03)
>>> rock = make_rock(poro, carman_kozeny(poro), kv_kh=0.1)
>>> rock.num_cells, bool(np.array_equal(z, gaussian_field(u, v, seed=42)))
(1000, True)
>>> round(float(carman_kozeny(0.2)), 2)  # mD
21.72
"""

from .cubes import PropertyCube, sample_cube
from .depositional import Depositional, depositional_coordinates, layer_index
from .random_fields import gaussian_field
from .rock import (
    MILLIDARCY,
    Rock,
    carman_kozeny,
    lognormal_permeability,
    make_rock,
    normal_porosity,
    per_layer,
)
from .variogram import VARIOGRAM_MODELS, Variogram

__all__ = [
    "MILLIDARCY",
    "VARIOGRAM_MODELS",
    "Depositional",
    "PropertyCube",
    "Rock",
    "Variogram",
    "carman_kozeny",
    "depositional_coordinates",
    "gaussian_field",
    "layer_index",
    "lognormal_permeability",
    "make_rock",
    "normal_porosity",
    "per_layer",
    "sample_cube",
]
