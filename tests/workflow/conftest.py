"""Fixtures of the workflow tests only: the SLURM cluster of test_slurm.py."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def slurm_cluster(tmp_path_factory):
    """A SLURM cluster on this host: the one running, else a single-node one started for the
    session and stopped after it (tests/slurm_cluster.py). Without SLURM (or root) the tests
    that use it fail (see system_tools.missing_tool)."""
    import slurm_cluster as slurm
    from system_tools import missing_tool

    try:
        cluster = slurm.cluster_for_tests(tmp_path_factory.mktemp("slurm"))
    except slurm.SlurmUnavailable as exc:
        missing_tool(str(exc))
    except slurm.ClusterError as exc:
        pytest.fail(str(exc), pytrace=False)
    yield cluster
    cluster.stop()
