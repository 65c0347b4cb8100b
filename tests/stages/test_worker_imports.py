"""gridlib.stages.worker_imports: the study workers' fork server starts them with every stage's
modules and libraries and the study table's, without dask (not used by a variant), and with
the imports' objects frozen out of the garbage collector's scans."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from gridlib import artifacts
from gridlib.stages.job_server import STAGE_LIBRARIES
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
