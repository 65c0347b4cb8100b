"""gridlib workflow: every case in config/cases becomes a folder of staged artifacts.

    snakemake --cores all --workflow-profile workflow/profiles/default

Stages per case (wildcard {case}): grid -> geometry -> export. See README.md.
"""

from snakemake.utils import min_version

min_version("8.0")


configfile: f"{workflow.basedir}/config/config.yaml"


include: "workflow/rules/common.smk"


rule all:
    default_target: True
    input:
        all_outputs(),


include: "workflow/rules/grid.smk"
include: "workflow/rules/geometry.smk"
include: "workflow/rules/export.smk"
