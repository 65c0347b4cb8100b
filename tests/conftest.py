"""Shared fixtures."""

from __future__ import annotations

import os
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


@pytest.fixture(scope="session")
def slurm_cluster(tmp_path_factory):
    """A SLURM cluster on this host: the one running, else a single-node one started for the
    session and stopped after it (tests/slurm_cluster.py). Without SLURM (or root) the tests
    that use it skip, or fail when GRIDLIB_REQUIRE_SLURM=1 (CI sets it)."""
    import slurm_cluster as slurm

    try:
        cluster = slurm.cluster_for_tests(tmp_path_factory.mktemp("slurm"))
    except slurm.SlurmUnavailable as exc:
        if os.environ.get("GRIDLIB_REQUIRE_SLURM") == "1":
            pytest.fail(f"{exc} (GRIDLIB_REQUIRE_SLURM=1)", pytrace=False)
        pytest.skip(str(exc))
    except slurm.ClusterError as exc:
        pytest.fail(str(exc), pytrace=False)
    yield cluster
    cluster.stop()
