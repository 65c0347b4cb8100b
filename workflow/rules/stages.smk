# A case's stages (gridlib/artifacts.py STAGES: horizons, grid, geometry, petrophysics,
# coarsen, transmissibility, wells, export, pictures, flow_deck, simulate), one rule each, generated from
# the table: its inputs, its outputs where the case has them, temp() where the case drops its
# stage files (outputs.stage_files: false). Cases whose outputs of a stage differ (grid.grdecl
# or not, the VTU or not, kept or temporary) get a rule of their own, named after the stage and
# the difference (grid_without_grdecl, export_without_vtu, geometry_temp, ...). Every stage
# job is a `run:` job (stage_job in common.smk): in a local run a thread of the Snakemake
# process hands the stage to the run's job server (a warm process, no Python start-up per job).


for _stage in STAGES:
    for _rule in stage_rules(_stage):
        STAGE_RULES[_rule.name] = _stage.name

        rule:
            name:
                _rule.name
            input:
                unpack(stage_input_paths(_stage)),
                case=case_file,
            output:
                **_rule.outputs,
            log:
                _rule.log_file,
            benchmark:
                _rule.benchmark_file
            wildcard_constraints:
                **_rule.constraints,
            group:
                STAGE_GROUP
            threads: _stage.threads
            resources:
                mem_mb=_stage.mem_mb,
            params:
                stage=_stage.name,
            run:
                stage_job(
                    params.stage,
                    input,
                    output,
                    threads,
                    resources,
                    log[0],
                    wildcards,
                    bench_record,
                )


rule simulate:
    """Every case with a `simulation` section through OPM Flow: `snakemake simulate` (or
    `simulate: true` in the configuration, which adds them to `all`)."""
    input:
        requested_outputs(),
