"""Snakemake script of every stage rule (workflow/rules/stages.smk): the stage of
gridlib.artifacts.STAGES named by the rule's ``stage`` parameter, run on the case (loaded once)
with the rule's inputs and outputs (keyword arguments named after the artifacts' keys). Its notes
reach the console once, prefixed with the case and the stage; a failure is one line there
(gridlib.stages.run_logged), the traceback of an unexpected one in the rule's log."""

from importlib import import_module

from gridlib.io.dask_on_demand import defer_dask_import
from gridlib.stages import run_logged, run_stage

defer_dask_import()  # a job reads and writes numpy-backed datasets: dask's import is 0.2 s of it

for plugin in snakemake.config.get("plugins", []):  # modules that register stages of their own
    import_module(plugin)
paths = {key: path for key, path in snakemake.input.items() if key != "case"}
paths |= dict(snakemake.output.items())
run_logged(
    snakemake.log[0],
    run_stage,
    snakemake.params.stage,
    snakemake.input.case,
    paths,
    threads=snakemake.threads,
    outputs=list(snakemake.output),
    name=f"stage_{snakemake.params.stage}",
    label=f"{snakemake.wildcards.get('case', snakemake.input.case)}: {snakemake.params.stage}",
)
