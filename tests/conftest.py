"""Shared fixtures."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from seed_points import honeycomb_points


@pytest.fixture
def honeycomb() -> np.ndarray:
    return honeycomb_points()


DECKS = Path(__file__).parent / "data" / "decks"


@pytest.fixture(scope="session")
def decks_dir() -> Path:
    """Real ECLIPSE decks vendored with their licences (tests/data/decks/README.md)."""
    return DECKS


@pytest.fixture(scope="session")
def reek_dir() -> Path:
    return DECKS / "reek"


@pytest.fixture(scope="session")
def flow_reference() -> dict[str, np.ndarray]:
    """What OPM Flow computed for every vendored deck (make_flow_reference.py)."""
    with np.load(DECKS / "flow_reference.npz") as f:
        return {k: f[k] for k in f.files}
