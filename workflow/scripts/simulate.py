"""Snakemake script for rule simulate_case (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_simulate

run_logged(
    snakemake.log[0],
    stage_simulate,
    snakemake.input.case,
    snakemake.input.deck,
    snakemake.input.grid,
    snakemake.input.transmissibility,
    {key: snakemake.output[key] for key in ("summary", "wells", "vtu")},
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
