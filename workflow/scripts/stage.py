"""Snakemake script of every stage rule (workflow/rules/stages.smk): the stage of
gridlib.artifacts.STAGES named by the rule's ``stage`` parameter, run on the case (loaded once)
with the rule's inputs and outputs (keyword arguments named after the artifacts' keys), in the
run's job server where it has one (a local run: gridlib/stages/job_server.py), else in this
process. Its notes reach the console once, prefixed with the case and the stage; a failure is
one line there (gridlib.stages.run_logged), the traceback of an unexpected one in the rule's
log."""

import sys

from gridlib.stages.job_server import StageJob, run_job

paths = {key: str(path) for key, path in snakemake.input.items() if key != "case"}
paths |= {key: str(path) for key, path in snakemake.output.items()}
job = StageJob(
    stage=snakemake.params.stage,
    case=str(snakemake.input.case),
    paths=paths,
    threads=snakemake.threads,
    log=str(snakemake.log[0]),
    outputs=tuple(str(path) for path in snakemake.output),
    name=f"stage_{snakemake.params.stage}",
    label=f"{snakemake.wildcards.get('case', snakemake.input.case)}: {snakemake.params.stage}",
    plugins=tuple(snakemake.config.get("plugins", [])),
)
sys.exit(run_job(job))
