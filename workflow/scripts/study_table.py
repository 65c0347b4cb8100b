"""Snakemake script for rule study_table (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged
from gridlib.stages.study import stage_study

run_logged(
    snakemake.log[0],
    stage_study,
    snakemake.input.manifest,
    snakemake.input.summaries,
    snakemake.output,
    threads=snakemake.threads,
    outputs=list(snakemake.output),
)
