"""Choices and limits shared by the surfaces modules, and the check of a choice."""

from collections.abc import Sequence
from typing import Any

from ..errors import InputError
from ..pillars.depth_order import ORDERINGS

__all__ = ["EXTRAPOLATIONS", "METHODS", "ORDERINGS", "RBF_GLOBAL_MAX", "RBF_NEIGHBORS", "check_choice"]

METHODS = ("linear", "cubic", "rbf", "nearest")
EXTRAPOLATIONS = ("nan", "nearest", "trend")
RBF_GLOBAL_MAX = 2000  # beyond this many points (per block) the RBF is local by default
RBF_NEIGHBORS = 64  # ... with this many neighbours


def check_choice(value: Any, choices: Sequence[str], option: str) -> str:
    """``value`` if it is one of ``choices``, else an :class:`~gridlib.errors.InputError` naming
    ``option``."""
    if not isinstance(value, str) or value not in choices:
        raise InputError(f"{option}: unknown value {value!r}; expected one of {', '.join(choices)}")
    return value
