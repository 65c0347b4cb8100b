"""Snakemake script for rule export (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_export

keys = ("nc", "vtu", "faults", "png", "histograms", "summary")
outputs = {key: snakemake.output[key] for key in keys if key in snakemake.output.keys()}  # vtu: outputs.vtu
run_logged(
    snakemake.log[0],
    stage_export,
    snakemake.input.case,
    snakemake.input.grid,
    snakemake.input.geometry,
    outputs,
    snakemake.input.get("petrophysics"),
    snakemake.input.get("coarse"),
    snakemake.input.get("transmissibility"),
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
