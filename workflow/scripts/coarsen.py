"""Snakemake script for rule coarsen (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_coarsen

run_logged(
    snakemake.log[0],
    stage_coarsen,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.input.geometry,
    snakemake.input.get("petrophysics"),
    snakemake.output.coarse,
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
