"""gridlib workflow: every case in config/cases becomes a folder of staged artifacts.

    snakemake --cores all --workflow-profile workflow/profiles/default

Stages per case (wildcard {case}, the table gridlib/artifacts.py; workflow/rules/stages.smk
makes their rules): horizons -> grid -> geometry -> petrophysics -> coarsen and
transmissibility -> wells (trajectory and survey wells: wells.nc) -> export -> pictures and flow_deck (the
OPM Flow deck), then summary.csv over all cases
(see README.md). OPM Flow runs the decks of the cases with a `simulation`
section with `snakemake simulate` (or `--config simulate=true`). A report of the pictures:

    snakemake --report results/report.zip
"""

from snakemake.utils import min_version

min_version("8.0")


configfile: f"{workflow.basedir}/config/config.yaml"


include: "workflow/rules/common.smk"


rule all:
    default_target: True
    input:
        all_outputs(),


include: "workflow/rules/stages.smk"
include: "workflow/rules/summary.smk"
include: "workflow/rules/study.smk"
