"""Snakemake script for rule summary (a thin wrapper around gridlib.stages)."""

from gridlib.stages import run_logged, stage_summary

run_logged(snakemake.log[0], stage_summary, list(snakemake.input), snakemake.output.csv)
