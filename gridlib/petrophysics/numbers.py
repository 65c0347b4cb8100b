"""Checking the numeric options of the petrophysics functions (variogram, porosity, permeability)."""

from __future__ import annotations

import math
import numbers
from typing import Any

from ..errors import InputError

__all__ = ["finite_number"]


def finite_number(value: Any, option: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    """``value`` as a float, or an :class:`InputError` naming ``option`` if it is not a finite real
    number (booleans are not), or not positive / not >= 0 when asked.

    >>> finite_number(2, "kv_kh"), finite_number(0.0, "std", nonnegative=True)
    (2.0, 0.0)
    >>> finite_number(True, "mean")
    Traceback (most recent call last):
    ...
    gridlib.errors.InputError: mean: expected a finite number, got True
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise InputError(f"{option}: expected a finite number, got {value!r}")
    v = float(value)
    if positive and not v > 0:
        raise InputError(f"{option}: must be positive, got {value!r}")
    if nonnegative and v < 0:
        raise InputError(f"{option}: must be >= 0, got {value!r}")
    return v
