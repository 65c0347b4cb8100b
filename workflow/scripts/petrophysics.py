"""Snakemake script for rule petrophysics (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_petrophysics

run_logged(
    snakemake.log[0],
    stage_petrophysics,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.input.geometry,
    snakemake.output.petrophysics,
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
