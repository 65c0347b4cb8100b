"""gridlib workflow: every case in config/cases becomes a folder of staged artifacts.

    snakemake --cores all --workflow-profile workflow/profiles/default

Stages per case (wildcard {case}): horizons -> grid -> geometry -> petrophysics -> coarsen
and transmissibility -> export (with flow_deck: the OPM Flow deck), then summary.csv over
all cases (see README.md). OPM Flow runs the decks of the cases with a `simulation`
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


include: "workflow/rules/horizons.smk"
include: "workflow/rules/grid.smk"
include: "workflow/rules/geometry.smk"
include: "workflow/rules/petrophysics.smk"
include: "workflow/rules/coarsen.smk"
include: "workflow/rules/transmissibility.smk"
include: "workflow/rules/export.smk"
include: "workflow/rules/flow.smk"
include: "workflow/rules/summary.smk"
include: "workflow/rules/study.smk"
