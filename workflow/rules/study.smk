# Studies (config/studies/*.yaml): each variant is built like a case, all of its stages in one
# job (gridlib.stages.run_case writes the same staged artifacts as the per-stage rules), from
# its case file results/<study>/<variant>/<variant>.yaml, which common.smk rewrites at parse time
# only when its content changes; then one table over the study's variants. Variants that keep
# different artifacts (a varied grid type: corner-point keeps GRDECL and ROFF files, PEBI not)
# get a rule per group of variants that keep the same (study_rules).
#
# A variant's job runs in warm worker processes of the Snakemake process (see build_variant
# and gridlib/stages/workers.py) when Snakemake runs `run:` jobs in its own threads
# (--force-use-threads, set by workflow/profiles/default); else in the job's own process.


for _name in sorted(STUDIES):
    for _rule, _keys, _variants in study_rules(_name):

        rule:
            name:
                _rule
            input:
                case=f"{RESULTS}/{{study}}/{{variant}}/{{variant}}.yaml",
            output:
                **study_variant_files(_keys),
            log:
                f"{RESULTS}/logs/{{study}}/{{variant}}.log",
            benchmark:
                f"{RESULTS}/benchmarks/{{study}}/{{variant}}.tsv"
            wildcard_constraints:
                study=re.escape(_name),
                variant="|".join(re.escape(v.name) for v in _variants),
            group:
                "study"
            threads: 1
            resources:
                mem_mb=4000,
            run:
                build_variant(input.case, output.summary, log[0], bench_record)


# A simulated study (simulate: true): each variant's OPM Flow deck (its flow/ folder, from the
# variant's job above) runs as a job of its own, with one thread (Flow's results then do not
# depend on the machine), into the folder simulation/ (written whole) with responses.json.
# A `run:` job: with --force-use-threads it runs in a thread of the Snakemake process, which
# waits for Flow (a process of its own); on a cluster it is a SLURM job like the variants'.
for _name, _study in sorted(STUDIES.items()):
    if not _study.simulation.simulate:
        continue

    rule:
        name:
            f"study_simulate_{rule_name(_name)}"
        input:
            flow=f"{RESULTS}/{{study}}/{{variant}}/flow",
        output:
            simulation=directory(f"{RESULTS}/{{study}}/{{variant}}/simulation"),
        log:
            f"{RESULTS}/logs/{{study}}/{{variant}}.simulation.log",
        benchmark:
            f"{RESULTS}/benchmarks/{{study}}/{{variant}}.simulation.tsv"
        wildcard_constraints:
            study=re.escape(_name),
            variant="|".join(re.escape(v.name) for v in _study.variants),
        threads: 1
        resources:
            mem_mb=2000,
        params:
            options=study_simulation_options(_study),
            report_days=lambda wildcards, study=_study: variant_report_days(
                study, wildcards.variant
            ),
        run:
            simulate_variant_job(
                STUDIES[wildcards.study],
                wildcards.variant,
                input.flow,
                output.simulation,
                log[0],
                params,
            )


# A study's table: one job over its variants' summaries (and simulations), writing study.csv,
# study.nc and its pictures (study.png; for a simulated study also study_profiles.png and
# study_tornado.png). Two rules of one body, their outputs differing: study_table for the
# studies that do not simulate, study_table_simulated for those that do. A `run:` job, in the
# warm workers of the variants where they run (study_table_job).
for _simulated in (False, True):

    rule:
        """A study's variants in one table (study.csv, study.nc) and its pictures."""
        name:
            "study_table_simulated" if _simulated else "study_table"
        input:
            unpack(study_table_inputs),
        output:
            **study_table_outputs(_simulated),
        log:
            f"{RESULTS}/logs/{{study}}/study.log",
        benchmark:
            f"{RESULTS}/benchmarks/{{study}}/study.tsv"
        wildcard_constraints:
            study=study_names(_simulated),
        threads: 1
        resources:
            mem_mb=2000,
        run:
            study_table_job(input, output, log[0], bench_record)
