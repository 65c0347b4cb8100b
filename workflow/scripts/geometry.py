"""Snakemake script for rule geometry (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_geometry

run_logged(
    snakemake.log[0],
    stage_geometry,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.output.geometry,
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
