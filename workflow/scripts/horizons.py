"""Snakemake script for rule horizons (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_horizons

run_logged(
    snakemake.log[0],
    stage_horizons,
    snakemake.input.case,
    snakemake.output.horizons,
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
