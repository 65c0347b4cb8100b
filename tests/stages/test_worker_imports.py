"""gridlib.stages.worker_imports: the study workers' fork server starts them with every stage's
modules and libraries and the study table's, without dask (not used by a variant), and with
the imports' objects frozen out of the garbage collector's scans."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from gridlib import artifacts
from gridlib.stages.job_server import STAGE_LIBRARIES, WARM_DEFAULTS
from gridlib.stages.worker_imports import STUDY_TABLE
from gridlib.stages.workers import PRELOAD

ROOT = Path(__file__).resolve().parents[2]


def test_the_fork_server_preloads_what_a_variant_and_a_study_table_use():
    probe = (
        "import json, sys\n"
        f"sys.path.insert(0, {str(ROOT)!r})\n"
        f"for name in {list(PRELOAD)!r}:\n"
        "    __import__(name)\n"
        "import gc\n"
        "print(json.dumps([gc.get_freeze_count(), sorted(sys.modules)]))\n"
    )
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    frozen, modules = json.loads(run.stdout)
    loaded = set(modules)
    stage_modules = {s.function.partition(":")[0] for s in artifacts.STAGES if isinstance(s.function, str)}
    libraries = {name for names in STAGE_LIBRARIES.values() for name in names}
    expected = stage_modules | libraries | set(STUDY_TABLE) | {"xarray", "netCDF4", "gstools", "pyvista"}
    assert expected <= loaded, sorted(expected - loaded)
    assert "gridlib.stages.pictures" in loaded and "gridlib.stages.flow_deck" in loaded
    assert not any(name == "dask" or name.startswith("dask.") for name in loaded)
    assert frozen > 100_000  # the modules' objects (about 280,000 here), out of the collector's scans


def test_the_workers_blas_has_one_thread_unless_the_environment_says():
    """A variant's job has one thread: the fork server's BLAS starts without a thread pool of
    its own (which spins while it waits for work), unless the environment sets a count; pyvista
    is told it may plot (off screen), so that no job asks again."""
    import os

    probe = (
        "import json, os, sys\n"
        f"sys.path.insert(0, {str(ROOT)!r})\n"
        f"for name in {list(PRELOAD)!r}:\n"
        "    __import__(name)\n"
        "print(json.dumps([os.environ.get('OPENBLAS_NUM_THREADS'), len(os.listdir('/proc/self/task')),"
        " os.environ.get('ALLOW_PLOTTING')]))\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in WARM_DEFAULTS}
    runs = {
        given: json.loads(
            subprocess.run(
                [sys.executable, "-c", probe],
                capture_output=True,
                text=True,
                check=True,
                env=env | ({"OPENBLAS_NUM_THREADS": given} if given else {}),
            ).stdout
        )
        for given in (None, "2")
    }
    assert runs[None][0] == "1" and runs["2"][0] == "2", runs
    assert runs[None][1] < runs["2"][1], runs  # no BLAS thread of its own beside the main thread
    assert runs[None][2] == "true", runs
