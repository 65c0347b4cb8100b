"""Snakemake script for rule transmissibility (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_transmissibility

run_logged(
    snakemake.log[0],
    stage_transmissibility,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.input.geometry,
    snakemake.input.petrophysics,
    snakemake.output.transmissibility,
    snakemake.input.get("grdecl"),
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
