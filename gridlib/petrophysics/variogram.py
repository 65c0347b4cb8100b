"""Variogram (covariance) models of the Gaussian random fields: gstools' exponential, Gaussian and
Matern covariances with anisotropic correlation lengths and rotation angles."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any

from ..errors import InputError
from .numbers import finite_number

__all__ = ["VARIOGRAM_MODELS", "Variogram"]

VARIOGRAM_MODELS = ("exponential", "gaussian", "matern")


@dataclass(frozen=True)
class Variogram:
    """A covariance model for :func:`gaussian_field` (gstools' definitions).

    ``model``: ``"exponential"`` (C(r) = var exp(-r / l)), ``"gaussian"``
    (var exp(-pi r^2 / (4 l^2)), gstools' scaling: l is the integral scale) or
    ``"matern"`` (smoothness ``nu``; 0.5 is exponential). ``var``: the
    variance (the property's unit squared). ``len_scale`` (m): one length, or
    one per axis of the rotated frame (x, y, w): anisotropy, e.g.
    ``[500, 250, 5]``. ``angles`` (degrees): gstools' rotation of that frame,
    the first about the vertical (counter-clockwise from +x towards +y, i.e.
    from east towards north), then the tilts. ``nu``: Matern only.

    >>> Variogram("spherical")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    gridlib.errors.InputError: variogram.model: unknown model 'spherical'; expected one of exponential, ...
    """

    model: str = "exponential"
    var: float = 1.0
    len_scale: float | tuple[float, ...] = 1.0
    angles: tuple[float, ...] = ()
    nu: float = 1.0

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if not isinstance(self.model, str) or self.model.lower() not in VARIOGRAM_MODELS:
            raise InputError(
                f"variogram.model: unknown model {self.model!r}; "
                f"expected one of {', '.join(VARIOGRAM_MODELS)}"
            )
        set_(self, "model", self.model.lower())
        set_(self, "var", finite_number(self.var, "variogram.var", nonnegative=True))
        ls = self.len_scale
        if isinstance(ls, numbers.Real) and not isinstance(ls, bool):
            set_(self, "len_scale", finite_number(ls, "variogram.len_scale", positive=True))
        else:
            try:
                values = tuple(ls)  # type: ignore[arg-type]
            except TypeError:
                raise InputError(
                    f"variogram.len_scale: expected a length or a list of lengths (m), got {ls!r}"
                ) from None
            if not 1 <= len(values) <= 3:
                raise InputError(f"variogram.len_scale: expected 1 to 3 lengths (m), got {len(values)}")
            set_(
                self,
                "len_scale",
                tuple(finite_number(v, "variogram.len_scale", positive=True) for v in values),
            )
        try:
            angles = tuple(self.angles)
        except TypeError:
            angles = (self.angles,)  # type: ignore[assignment]
        if len(angles) > 3:
            raise InputError(f"variogram.angles: at most 3 rotation angles (degrees), got {len(angles)}")
        set_(self, "angles", tuple(finite_number(a, "variogram.angles") for a in angles))
        set_(self, "nu", finite_number(self.nu, "variogram.nu", positive=True))

    def covmodel(self, dim: int = 3):
        """The gstools covariance model in ``dim`` dimensions."""
        import gstools as gs

        ls = self.len_scale
        if isinstance(ls, tuple) and len(ls) not in (1, dim):
            raise InputError(f"variogram.len_scale: {len(ls)} lengths for a {dim}-D field (give 1 or {dim})")
        n_angles = dim * (dim - 1) // 2
        if len(self.angles) > n_angles:
            raise InputError(f"variogram.angles: a {dim}-D field has at most {n_angles} angles")
        kwargs: dict[str, Any] = {
            "dim": dim,
            "var": self.var,
            "len_scale": list(ls) if isinstance(ls, tuple) else ls,
            "angles": [math.radians(a) for a in self.angles] or 0.0,
        }
        if self.model == "exponential":
            return gs.Exponential(**kwargs)
        if self.model == "gaussian":
            return gs.Gaussian(**kwargs)
        return gs.Matern(nu=self.nu, **kwargs)
