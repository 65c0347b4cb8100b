"""Snakemake script for rules study_table and study_table_simulated (a thin wrapper around
gridlib.stages)."""

from gridlib.io.dask_on_demand import defer_dask_import
from gridlib.stages import run_logged
from gridlib.stages.study import stage_study

defer_dask_import()  # study.nc from numpy arrays: no need to import dask

run_logged(
    snakemake.log[0],
    stage_study,
    snakemake.input.manifest,
    snakemake.input.summaries,
    dict(snakemake.output.items()),  # by name: csv, nc, png (and profiles, tornado)
    snakemake.input.get("simulations", []),
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
