"""Snakemake script for rules grid and grid_grdecl (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_grid

run_logged(
    snakemake.log[0],
    stage_grid,
    snakemake.input.case,
    snakemake.output.grid,
    snakemake.input.get("horizons"),
    snakemake.output.get("grdecl"),
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
