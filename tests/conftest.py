"""Shared fixtures."""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from seed_points import honeycomb_points

# OPM Flow runs as a single process here (no mpirun). Open MPI 4 then starts its runtime daemon
# and probes the network transports before Flow reads the deck: 0.3 s of waiting per run, most of
# a small deck's dry run. Isolated and with the ob1 messaging layer it starts in 0.07 s (measured
# with Flow 2022.10 and Open MPI 4.1.4); the results are the same (one rank, no messages). Set
# for the tests' own Flow runs (gridlib's run_flow sets the same for its runs, each with a
# session base of its own: gridlib.stages.simulate.flow_environment); other MPIs ignore these.
os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")
os.environ.setdefault("OMPI_MCA_pml", "ob1")
# Every isolated singleton is job family 0: its session directory is always
# <tmpdir>/ompi.<host>.<uid>/jf.0/1, which each run creates at start and removes at its end. Two
# Flow runs at once (one per pytest-xdist worker) then race on that one directory, and a run now
# and then stops in MPI_Init ("unable to create the desired directory ... jf.0/1"). Each test
# process gets a session base of its own (its Flow runs are one after the other); assigned, not
# defaulted, since the workers inherit the controller's environment.
os.environ["OMPI_MCA_orte_tmpdir_base"] = tempfile.mkdtemp(prefix="ompi-session-")
atexit.register(shutil.rmtree, os.environ["OMPI_MCA_orte_tmpdir_base"], ignore_errors=True)

# The longest test modules (their fixtures run the workflow), first in this order, so that under
# pytest-xdist (make test: -n auto --dist loadfile) they start at once on their workers and the
# short modules fill the time around them; run one by one, the order changes nothing.
# test_slurm second: most of its time is waiting for SLURM's status checks, which the other worker
# fills. Then the modules of 8 s of CPU or more (one long test each, some of them): started last,
# one of them would keep its worker busy after the other has finished. Measured CPU seconds per
# module: bench/test_durations.md.
LONGEST_FIRST = (
    "workflow/test_workflow.py",
    "workflow/test_slurm.py",
    "workflow/test_study_simulation.py",
    "workflow/test_study.py",
    "workflow/test_determinism.py",
    "transmissibility/test_real_decks_large.py",
    "voronoi/test_pebi_splays.py",
    "stages/test_artifact_table.py",
    "io/test_damaged_artifacts.py",
    "stages/test_pipeline.py",
    "stages/test_simulate.py",
    "stages/test_job_server.py",
    "voronoi/test_pebi_grid_robust.py",
    "petrophysics/test_petrophysics.py",
)


def pytest_configure(config) -> None:
    # pytest-xdist (3.x) sorts --dist loadfile's modules by their number of tests, most first,
    # unless told not to: the longest modules, which have few tests and long fixtures, would then
    # start last and finish long after the rest (the critical path of make test). Keep our order.
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(session, config, items) -> None:
    def rank(item) -> int:
        path = item.path.as_posix()
        return next((i for i, m in enumerate(LONGEST_FIRST) if path.endswith(m)), len(LONGEST_FIRST))

    items.sort(key=rank)  # stable: the order within each group stays


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
