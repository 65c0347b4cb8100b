"""Snakemake script for rule export_vtu (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_export

run_logged(
    snakemake.log[0],
    stage_export,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.input.geometry,
    snakemake.output.vtu,
)
