"""Numbers of a case as a user reads them: finite, spelt as YAML spells them, named by their key."""

from __future__ import annotations

import math
from typing import Any


def key_path(keys: tuple[str | int, ...]) -> str:
    """``("wells", 3, "name")`` -> ``wells[3].name`` (the key as the case file spells it)."""
    text = "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in keys)
    return text.lstrip(".") or "(top level)"


def yaml_number(value: float) -> str:
    """A number as a case file would give it: ``.nan``, ``.inf``, ``-.inf``, ``0.25``, ``1e+20``;
    never a numpy repr.

    >>> yaml_number(float("nan")), yaml_number(-math.inf), yaml_number(0.25), yaml_number(3)
    ('.nan', '-.inf', '0.25', '3')
    """
    value = float(value)
    if math.isnan(value):
        return ".nan"
    if math.isinf(value):
        return ".inf" if value > 0 else "-.inf"
    return f"{value:g}" if value != int(value) or abs(value) >= 1e16 else f"{int(value)}"


# No number of a case is larger: coordinates up to 1e12 m keep sub-millimetre steps in float64
# (1e12 x 2.2e-16 = 2e-4 m), and no value in a case's units (mD, bar, days, sm3/day) comes near.
# Counts are integers: their size is the size check's (gridlib.config.size).
MAX_MAGNITUDE = 1e12


def non_finite_problem(data: Any, keys: tuple[str | int, ...] = ()) -> str | None:
    """``key: .nan is not a finite number`` for the first NaN or infinite number anywhere in
    ``data`` (YAML's ``.nan``, ``.inf``; JSON schemas take them for numbers, and every
    comparison with NaN is false, so ``minimum`` lets it through), or a float beyond
    ``MAX_MAGNITUDE``; None if there is none.

    >>> non_finite_problem({"faults": [{"throw": float("nan")}]})
    'faults[0].throw: .nan is not a finite number'
    >>> print(non_finite_problem({"grid": {"origin": [0.0, 1e300]}}))
    grid.origin[1]: 1e+300 is beyond 1e+12 in magnitude (no length in m or value in the case's units is)
    """
    if isinstance(data, float) and not math.isfinite(data):
        return f"{key_path(keys)}: {yaml_number(data)} is not a finite number"
    if isinstance(data, float) and abs(data) > MAX_MAGNITUDE:
        return (
            f"{key_path(keys)}: {yaml_number(data)} is beyond {MAX_MAGNITUDE:g} in magnitude "
            "(no length in m or value in the case's units is)"
        )
    if isinstance(data, dict):
        for key, value in data.items():
            problem = non_finite_problem(value, (*keys, str(key)))
            if problem is not None:
                return problem
    elif isinstance(data, list):
        for k, value in enumerate(data):
            problem = non_finite_problem(value, (*keys, k))
            if problem is not None:
                return problem
    return None
