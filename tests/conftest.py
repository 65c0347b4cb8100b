"""Shared fixtures."""

from __future__ import annotations

import numpy as np
import pytest
from seed_points import honeycomb_points


@pytest.fixture
def honeycomb() -> np.ndarray:
    return honeycomb_points()
