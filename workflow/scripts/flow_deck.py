"""Snakemake script for rule flow_deck (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_flow_deck

run_logged(
    snakemake.log[0],
    stage_flow_deck,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.input.geometry,
    snakemake.input.petrophysics,
    snakemake.input.transmissibility,
    snakemake.output.deck,
    snakemake.input.get("grdecl"),
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
