"""Fixtures of the workflow tests only: the SLURM cluster of test_slurm.py."""

from __future__ import annotations

import os

import pytest


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
