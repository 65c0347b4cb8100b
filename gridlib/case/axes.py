"""Coordinate axes given in a case: a list of values or ``{start, stop, num}`` (evenly spaced)."""

from __future__ import annotations

from typing import Any

import numpy as np


def axis(spec: Any) -> np.ndarray:
    """The values of an axis spec: ``{start, stop, num}`` as ``np.linspace``, else the list itself.

    >>> axis({"start": 0.0, "stop": 1.0, "num": 3}).tolist()
    [0.0, 0.5, 1.0]
    >>> axis([0, 2, 5]).tolist()
    [0.0, 2.0, 5.0]
    """
    if isinstance(spec, dict):
        return np.linspace(spec["start"], spec["stop"], spec["num"])
    return np.asarray(spec, dtype=np.float64)
