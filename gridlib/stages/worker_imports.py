"""What the warm workers of a study (:mod:`gridlib.stages.workers`) start with.

The workers are forked from a fork server that imports this module before it forks the
first of them (``multiprocessing``'s forkserver preload takes module names only): importing
it defers xarray's dask import (:func:`~gridlib.io.dask_on_demand.defer_dask_import`, as
the stage jobs' entry points do) and imports what a variant's stages and a study's table use
(:func:`~gridlib.stages.job_server.preload_modules` of every stage, then
:data:`STUDY_TABLE`; absent ones skipped), and freezes what they made
(:func:`~gridlib.stages.job_server.freeze_imports`). Each worker then starts with them, instead of
importing them in its first job, which on this project's 2-core VM cost each worker about
1 s of CPU over a warm job (horizons 0.4 s, pictures 0.35 s, quality 0.12 s, ...).

A worker builds a variant on one thread (a study's variant job has one), so the BLAS and
OpenMP libraries get one thread too, unless the environment sets their counts
(:data:`~gridlib.stages.job_server.WARM_DEFAULTS`, as the stage jobs' job server has them):
their counts are fixed when numpy is imported, and a pool of BLAS threads that spin while they
wait for work cost each worker of the sample study about 1 s of CPU.
"""

from __future__ import annotations

import os

from .job_server import WARM_DEFAULTS, freeze_imports, import_present, preload_modules

__all__ = ["STUDY_TABLE", "import_worker_modules"]

# A study's table job (gridlib.stages.study.stage_study) beyond the stages' modules.
STUDY_TABLE = ("pandas", "gridlib.stages.study")


def import_worker_modules() -> list[str]:
    """Import what the workers use (the module's docstring), BLAS on one thread unless the
    environment says otherwise; returns the names tried."""
    for name, value in WARM_DEFAULTS.items():
        os.environ.setdefault(name, value)
    from ..io.dask_on_demand import defer_dask_import  # numpy's first import: after the counts

    defer_dask_import()
    names = list(dict.fromkeys([*preload_modules(None), *STUDY_TABLE]))
    import_present(names)
    freeze_imports()
    return names


import_worker_modules()
