"""Rock transforms (a standard normal field to porosity, to lognormal permeability; porosity to
permeability by Carman-Kozeny; per-layer and per-zone values) and the :class:`Rock` they make."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray
from ..reproducible import exp
from ..units import MILLIDARCY
from .numbers import finite_number

__all__ = [
    "MILLIDARCY",
    "Rock",
    "carman_kozeny",
    "lognormal_permeability",
    "make_rock",
    "normal_porosity",
    "per_layer",
]


def normal_porosity(
    z: ArrayLike, *, mean: float, std: float, bounds: tuple[float, float] = (0.0, 1.0)
) -> FloatArray:
    """Porosity (fraction) from a standard normal field ``z``: clip(mean + std z, bounds).

    >>> normal_porosity([-10.0, 0.0, 1.0], mean=0.2, std=0.05, bounds=(0.05, 0.4)).tolist()
    [0.05, 0.2, 0.25]
    """
    mean = finite_number(mean, "porosity mean")
    std = finite_number(std, "porosity std", nonnegative=True)
    lo, hi = (finite_number(b, "porosity bounds") for b in bounds)
    if not 0.0 <= lo <= hi <= 1.0:
        raise InputError(f"porosity bounds: expected 0 <= low <= high <= 1, got {bounds!r}")
    return np.clip(mean + std * np.asarray(z, dtype=np.float64), lo, hi)


def lognormal_permeability(z: ArrayLike, *, median: float, sigma: float) -> FloatArray:
    """Lognormal permeability (mD) from a standard normal field ``z``: median exp(sigma z).

    ``median`` (mD) is the geometric mean; ``sigma`` the standard deviation of
    ln K (the arithmetic mean is median exp(sigma^2 / 2)).

    >>> import math
    >>> lognormal_permeability([0.0, 1.0], median=100.0, sigma=math.log(10.0)).round(9).tolist()
    [100.0, 1000.0]
    """
    median = finite_number(median, "permeability median (mD)", positive=True)
    sigma = finite_number(sigma, "permeability sigma (of ln K)", nonnegative=True)
    return median * exp(sigma * np.asarray(z, dtype=np.float64))


def carman_kozeny(poro: ArrayLike, *, grain_diameter: float = 10e-6, tortuosity: float = 0.81) -> FloatArray:
    """Permeability (mD) from porosity by the Carman-Kozeny relation used in the MRST book:
    K = phi^3 d^2 / (72 tau (1 - phi)^2), ``grain_diameter`` d = 10 micrometres (m) and
    ``tortuosity`` factor tau = 0.81 (the book's ``0.81*72``); converted from m2 by
    1 mD = 9.869232667160130e-16 m2 (:data:`gridlib.units.MILLIDARCY`). Porosity must lie in [0, 1).

    >>> k = carman_kozeny(0.2)
    >>> round(float(k), 1), f"{float(k) * MILLIDARCY:.4g} m2"
    (21.7, '2.143e-14 m2')
    """
    d = finite_number(grain_diameter, "grain_diameter (m)", positive=True)
    tau = finite_number(tortuosity, "tortuosity", positive=True)
    phi = np.asarray(poro, dtype=np.float64)
    if np.isnan(phi).any() or (phi < 0).any() or (phi >= 1).any():
        raise InputError("carman_kozeny: porosity must lie in [0, 1)")
    return phi * phi * phi * (d * d) / (72.0 * tau * ((1.0 - phi) * (1.0 - phi))) / MILLIDARCY


def per_layer(layer: ArrayLike, values: float | ArrayLike, *, zones: ArrayLike | None = None) -> FloatArray:
    """Cell values from a constant, one value per layer, or one per zone.

    ``layer`` (nc,): every cell's layer (:func:`layer_index`). ``values``: a
    number, or one per layer, or with ``zones`` (the number of layers of each
    zone, top first) one per zone.

    >>> per_layer([0, 1, 2, 3], [0.1, 0.3], zones=[1, 3]).tolist()
    [0.1, 0.3, 0.3, 0.3]
    """
    lay = np.asarray(layer, dtype=np.int64)
    v = np.asarray(values, dtype=np.float64)
    if not np.isfinite(v).all():
        raise InputError("per_layer: values must be finite")
    if v.ndim == 0:
        return np.full(lay.shape, float(v))
    if v.ndim != 1:
        raise InputError(f"per_layer: values must be a number or a list, got shape {v.shape}")
    if zones is not None:
        zn = np.asarray(zones)
        if zn.ndim != 1 or zn.size != v.size or not np.issubdtype(zn.dtype, np.integer) or (zn < 1).any():
            raise InputError(
                f"per_layer: zones must be one positive layer count per value ({v.size}), got {zones!r}"
            )
        v = np.repeat(v, zn)
    if lay.size and (lay.min() < 0 or lay.max() >= v.size):
        what = "the zones' layers" if zones is not None else "values"
        raise InputError(f"per_layer: layer {int(lay.max())} has no value ({v.size} {what})")
    return v[lay]


@dataclass(frozen=True, eq=False)
class Rock:
    """Rock properties per cell: ``poro`` and ``ntg`` (fractions), ``permx``, ``permy``,
    ``permz`` (mD). Arrays are copied, checked (finite, >= 0) and read-only. Fractions above 1
    are allowed, as OPM Flow and ECLIPSE allow them in a deck (:mod:`.ranges`: a note)."""

    poro: FloatArray
    permx: FloatArray
    permy: FloatArray
    permz: FloatArray
    ntg: FloatArray

    def __post_init__(self) -> None:
        n = None
        for name in ("poro", "permx", "permy", "permz", "ntg"):
            arr = np.array(getattr(self, name), dtype=np.float64)
            if arr.ndim != 1:
                raise InputError(f"rock.{name}: expected one value per cell (1-D), got shape {arr.shape}")
            n = arr.size if n is None else n
            if arr.size != n:
                raise InputError(f"rock.{name}: {arr.size} values, expected {n} (as poro)")
            if not np.isfinite(arr).all():
                raise InputError(f"rock.{name}: values must be finite")
            if arr.size and arr.min() < 0.0:
                raise InputError(f"rock.{name}: values must be >= 0")
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @property
    def num_cells(self) -> int:
        return self.poro.size

    def cell_data(self) -> dict[str, FloatArray]:
        """The properties by name, e.g. for ``write_netcdf(..., cell_data=rock.cell_data())``."""
        return {k: getattr(self, k) for k in ("poro", "permx", "permy", "permz", "ntg")}


def make_rock(
    poro: float | ArrayLike,
    permx: float | ArrayLike,
    *,
    permy: float | ArrayLike | None = None,
    permz: float | ArrayLike | None = None,
    kv_kh: float = 0.1,
    ntg: float | ArrayLike = 1.0,
    num_cells: int | None = None,
) -> Rock:
    """A :class:`Rock`; numbers are broadcast to every cell (``num_cells``, or the arrays' length).
    ``permy`` defaults to ``permx``, ``permz`` to ``kv_kh`` times ``permx`` (mD).

    >>> r = make_rock(0.25, [100.0, 200.0])
    >>> r.permz.tolist(), r.ntg.tolist()
    ([10.0, 20.0], [1.0, 1.0])
    """
    kv_kh = finite_number(kv_kh, "kv_kh", nonnegative=True)
    arrays = [np.asarray(a, dtype=np.float64) for a in (poro, permx, ntg) if a is not None]
    for a in (permy, permz):
        if a is not None:
            arrays.append(np.asarray(a, dtype=np.float64))
    sizes = {a.size for a in arrays if a.ndim > 0}
    if num_cells is not None:
        sizes.add(int(num_cells))
    if len(sizes) > 1:
        raise InputError(f"make_rock: the properties have different lengths {sorted(sizes)}")
    n = sizes.pop() if sizes else 1

    def full(a: Any) -> FloatArray:
        return np.broadcast_to(np.asarray(a, dtype=np.float64), (n,)).copy()

    kx = full(permx)
    ky = kx.copy() if permy is None else full(permy)
    kz = kv_kh * kx if permz is None else full(permz)
    return Rock(full(poro), kx, ky, kz, full(ntg))
