"""Configuration, case discovery and validation (runs when the workflow is parsed).

A broken configuration or case file stops the run before any job: every problem of every
case file is printed, one line each naming the file and the key, without a traceback.
"""

import glob
import re
import shutil
import sys
from dataclasses import dataclass
from importlib import import_module
from pathlib import Path

import yaml
from snakemake.utils import validate

from gridlib import artifacts
from gridlib.config import load_cases
from gridlib.config import validate as check_schema
from gridlib.errors import InputError
from gridlib.study import artifact_groups, load_studies, materialise


def check_config(data, source):
    """The configuration against its schema: an InputError naming the key. A boolean given on
    the command line as YAML writes it (``--config simulate=true``; Snakemake reads only
    Python's True and False) is taken as that boolean."""
    with open(
        Path(workflow.basedir) / "workflow" / "schemas" / "config.schema.yaml"
    ) as f:
        schema = yaml.safe_load(f)
    for key, spec in schema["properties"].items():
        value = data.get(key)
        if spec.get("type") == "boolean" and isinstance(value, str):
            data[key] = {"true": True, "false": False}.get(value.lower(), value)
    check_schema(data, schema, source)


def stop(message):
    """End the parse with ``message`` (one line per problem) and no traceback."""
    print(message, file=sys.stderr)
    sys.exit(1)


try:
    check_config(config, "config")  # one line naming the key
except InputError as exc:
    stop(str(exc))
validate(config, "../schemas/config.schema.yaml")  # fills in the defaults


RESULTS = config.get("results", "results")
for _plugin in config.get("plugins", []):  # modules that register stages of their own
    try:
        import_module(_plugin)
    except ImportError as exc:
        stop(f"config: plugins: cannot import {_plugin!r} ({exc}); nothing was run")
STAGES = artifacts.STAGES


onstart:
    start_job_server()


# The stage of each stage rule (workflow/rules/stages.smk adds them as it makes them).
STAGE_RULES = {}


def start_job_server():
    """The stage jobs this process runs hand their stages to one warm process (gridlib/stages/
    job_server.py) that imports what their stages use, started when two or more stage jobs
    are about to run here (one runs as fast in its own process): those of a local run (from
    onstart) and those of a cluster job of several stages (the SLURM profile's job of a case:
    the Snakemake process the job starts on its node runs them without hooks, so its first
    stage job starts the server, stage_job). Jobs run in their own processes where this
    process submits them to a cluster, in a conda environment or container, and where the
    configuration's job_server is false."""
    if not (
        config.get("job_server", True)
        and workflow.local_exec
        and not workflow.deployment_settings.deployment_method
    ):
        return
    try:
        jobs = [job.rule.name for job in workflow.dag.needrun_jobs()]
    except AttributeError:
        # a Snakemake without this DAG method: assume every stage runs
        jobs = list(STAGE_RULES)
    stages = [STAGE_RULES[name] for name in jobs if name in STAGE_RULES]
    if len(stages) < 2:
        return
    from gridlib.stages.job_server import serve_this_run

    if not serve_this_run(config.get("plugins", []), stages):
        print(
            "gridlib: the job server did not start; every job runs in its own process",
            file=sys.stderr,
        )
        return


def job_benchmarks():
    """A `run:` job's benchmark file gets what the job's own process used, which the job
    records (record_usage), instead of samples of this Snakemake process and every process
    under it. Snakemake samples a `run:` job as this process's tree: the job server and all
    its children, a study's workers and every OPM Flow run, whatever job they work for. Each
    sample reads their memory maps (smaps_rollup: about 10 ms per 600 MB process, in the
    kernel): on the sample workflow 9 of its 100 s of CPU, for figures that were not the job's.
    A `run:` job's `s` column (its wall time) is measured as before; its other columns are the
    job's own CPU time, peak memory and bytes read and written where it records them (the
    stage jobs, a study's variants and tables), else NA (a study's Flow job). A `shell:` or
    `script:` job (the summary table) is a process of its own, sampled as Snakemake does, every
    30 s from its start instead of every 0.5 s in its first 15 s. Set when the workflow is
    parsed, in every Snakemake process that runs jobs (a local run's, a cluster job's).
    """
    import contextlib
    import time

    import snakemake.benchmark as benchmark

    if getattr(
        benchmark.benchmarked, "records_jobs", False
    ):  # parsed twice in one process
        return
    sampled = benchmark.benchmarked

    @contextlib.contextmanager
    def benchmarked(
        pid=None, benchmark_record=None, interval=benchmark.BENCHMARK_INTERVAL
    ):
        if pid is not None:  # a shell: or script: job's process
            with sampled(pid, benchmark_record, interval) as record:
                yield record
            return
        record = benchmark_record or benchmark.BenchmarkRecord()
        record.process_gone = True  # no sample: NA unless the job records its usage
        start = time.time()
        try:
            yield record
        finally:
            record.running_time = time.time() - start

    benchmarked.records_jobs = True
    benchmark.benchmarked = benchmarked
    benchmark.BENCHMARK_INTERVAL_SHORT = benchmark.BENCHMARK_INTERVAL


job_benchmarks()


def whole_console_lines():
    """Each message Snakemake prints reaches the console in one write. Its console handler
    writes a message, then its line end, with two writes: the message's lines are flushed at
    once (stderr is line-buffered), the line end after them. A job's own line (a note, a
    failure) written by another process in between (the job server's child, another job's
    process, a cluster job's Snakemake) then ends Snakemake's message and starts a line that
    is neither's: "...non-zero exit status 1.gridlib: noted: grid: note: ...". The handler
    writes the line end with its message instead. Set when the workflow is parsed, in every
    Snakemake process that prints (its handlers are made after the parse)."""
    from snakemake.logging import ColorizingTextHandler

    if getattr(
        ColorizingTextHandler, "whole_lines", False
    ):  # parsed twice in one process
        return
    decorate = ColorizingTextHandler.decorate

    def decorate_line(self, record, message):
        return decorate(self, record, message) + "\n"

    ColorizingTextHandler.decorate = decorate_line
    ColorizingTextHandler.terminator = ""
    ColorizingTextHandler.whole_lines = True


whole_console_lines()


def cluster_jobs_in_threads():
    """A cluster job's Snakemake (--mode remote, on the node: the SLURM profile's job of a
    case's stages, of a study's variant or of its Flow run) runs its `run:` jobs in its own
    threads, as a local run with --force-use-threads (the default profile) does. Otherwise it
    starts another Snakemake process for each `run:` job, which imports Snakemake and parses
    the workflow again (about 2 s of CPU a stage): the cluster executor plugins do not pass
    --force-use-threads on to the job. Its stage jobs then hand their stages to one job server
    on the node (stage_job), its variants and tables to warm workers (build_variant). Set when the workflow is parsed, before Snakemake
    makes the run's execution settings: on them, when the run starts."""
    if not (workflow.remote_exec and workflow.local_exec):
        return
    execute = workflow.execute

    def execute_in_threads(*args, **kwargs):
        workflow.execution_settings.use_threads = True
        return execute(*args, **kwargs)

    workflow.execute = execute_in_threads


cluster_jobs_in_threads()


def record_usage(bench_record, usage):
    """Put what a `run:` job's process used (gridlib.stages.job_usage.JobUsage, or None: not
    known) into the job's benchmark record (None: no benchmark file): max_rss in MiB,
    io_in and io_out in MiB, cpu_time in s, mean_load in % of a core; max_vms, max_uss and
    max_pss are not measured ("-")."""
    if bench_record is None or usage is None:
        return
    bench_record.data_collected = True
    bench_record.max_rss = usage.max_rss_mib
    bench_record.io_in = usage.read_mib
    bench_record.io_out = usage.written_mib
    bench_record.cpu_time = usage.cpu_seconds
    bench_record.cpu_usage = (
        100 * usage.cpu_seconds
    )  # mean_load: this over the wall time


def stage_job(
    stage, input, output, threads, resources, log_file, wildcards, bench_record
):
    """A stage rule's job (workflow/rules/stages.smk): the stage ``stage`` of the job's case
    with the rule's inputs and outputs (keyword arguments named after the artifacts' keys)
    and the environment Snakemake gives a script job of ``threads`` and ``resources``,
    in the run's job server where it has one (a local run: gridlib/stages/job_server.py),
    else in a new Python process (a cluster job, a conda or container job, job_server:
    false). Its notes reach the console once, prefixed with the case and the stage; a failure
    is one line there (gridlib.stages.run_logged), the traceback of an unexpected one in the
    rule's log, and fails the job. What the job's process used goes into ``bench_record``.
    """
    from gridlib.stages.job_server import StageJob, job_environment, run_stage_job

    paths = {key: str(path) for key, path in input.items() if key != "case"}
    paths |= {key: str(path) for key, path in output.items()}
    job = StageJob(
        stage=stage,
        case=str(input.case),
        paths=paths,
        threads=threads,
        log=log_file,
        outputs=tuple(str(path) for path in output),
        name=f"stage_{stage}",
        label=f"{wildcards.get('case', input.case)}: {stage}",
        plugins=tuple(config.get("plugins", [])),
    )
    # a cluster job's Snakemake runs without hooks (no onstart): its first stage job starts it
    if not workflow.is_main_process:
        start_job_server()
    # the environment Snakemake gives a script job (thread counts, TMPDIR)
    env = job_environment(threads, resources.get("tmpdir"))
    end = run_stage_job(job, env)
    record_usage(bench_record, end.usage)
    if end.status != 0:
        # The reason is the one gridlib: line above (the traceback of an unexpected error is in
        # the log). Fail as a script job fails, through Snakemake's shell: Snakemake reports an
        # exception raised here with the rule's Python frames, a traceback on the console.
        shell("exit 1")


# Snakemake's job group of every stage rule: on a cluster (workflow/profiles/slurm) a case's
# stages run one after the other in one job; no effect on local runs.
STAGE_GROUP = "case" if config.get("one_job_per_case", True) else None


def discover_cases(spec):
    """Validated cases keyed by name, from a glob or a list of case files.

    Relative paths are relative to the repository (the Snakefile's folder), so the
    workflow also runs with --directory elsewhere.
    """
    base = Path(workflow.basedir)
    if isinstance(spec, str):
        pattern = spec if Path(spec).is_absolute() else str(base / spec)
        paths = sorted(glob.glob(pattern))
    else:
        paths = [p if Path(p).is_absolute() else str(base / p) for p in spec]
    if not paths and isinstance(spec, str):
        stop(f"config: cases: no case file matches {spec!r}")
    try:
        return load_cases(paths, config.get("max_memory_gb"))
    except InputError as exc:
        problems = str(exc).splitlines()
        stop(
            "\n".join(problems)
            + f"\n{len(problems)} problem(s) in the case files; nothing was run"
        )


CASES = discover_cases(config["cases"])


wildcard_constraints:
    case="|".join(sorted(CASES)) or "(?!)",


def artifact_path(key, case):
    """The path of the artifact ``key`` of ``case`` (gridlib.artifacts: results/<case>/...)."""
    path = artifacts.artifacts()[key].path.format(case=case.name, NAME=case.flow_name)
    return f"{RESULTS}/{case.name}/{path}"


def stage_input_paths(stage):
    """An input function: the artifacts ``stage`` reads that the job's case has."""

    def inputs(wildcards):
        case = CASES[wildcards.case]
        return {
            key: artifact_path(key, case) for key in artifacts.stage_inputs(stage, case)
        }

    return inputs


@dataclass(frozen=True)
class StageRule:
    """What one generated rule of a stage declares. Its name, its outputs (patterns, temp()
    or report() where due), log, benchmark and wildcard constraints (the cases it builds).
    """

    name: str
    outputs: dict
    log_file: str
    benchmark_file: str
    constraints: dict


def stage_rules(stage):
    """The rules of ``stage``: one per set of outputs its cases have (which of the stage's
    outputs, which of them temporary), named after the stage and what differs."""
    kinds = {}
    for name, case in sorted(CASES.items()):
        present = stage.outputs_of(case)
        if present:
            kind = tuple((a.key, a.temporary(case)) for a in present)
            kinds.setdefault(kind, []).append(case)
    return [
        _stage_rule(stage, dict(kind), cases) for kind, cases in sorted(kinds.items())
    ]


def _stage_rule(stage, temporary, cases):
    absent = [a.key for a in stage.outputs if a.key not in temporary]
    temps = [key for key, is_temp in temporary.items() if is_temp]
    without = "".join(f"_without_{key}" for key in absent)
    name = f"{stage.rule_name}{without}"
    if temps:
        name += "_temp" if len(temps) == len(temporary) else f"_temp_{'_'.join(temps)}"
    outputs = {}
    wildcards = set()
    for a in stage.outputs:
        if a.key not in temporary:
            continue
        pattern = f"{RESULTS}/{{case}}/{a.path}"
        wildcards |= set(a.wildcards)
        if a.directory:  # a folder of files the case decides (written whole)
            pattern = directory(pattern)
        if temporary[a.key]:
            pattern = temp(pattern)
        elif a.report is not None:
            pattern = report(
                pattern,
                caption=f"../report/{a.report.caption}",
                category=a.report.category,
                subcategory="{case}",
            )
        outputs[a.key] = pattern
    constraints = {"case": "|".join(re.escape(c.name) for c in cases)}
    if "NAME" in wildcards:  # flow/<NAME>.DATA: the case name in upper case
        constraints["NAME"] = "|".join(re.escape(c.flow_name) for c in cases)
    tag = "".join(f".{{{w}}}" for w in sorted(wildcards - {"case"}))
    return StageRule(
        name,
        outputs,
        f"{RESULTS}/logs/{{case}}/{stage.name}{tag}.log",
        f"{RESULTS}/benchmarks/{{case}}/{stage.name}{tag}.tsv",
        constraints,
    )


def case_file(wildcards):
    return str(CASES[wildcards.case].path)


def requested_outputs():
    """The targets of `snakemake simulate`: the artifacts of the stages run on request (every
    case with a `simulation` section through OPM Flow); nothing (with a warning) where `flow`
    is not installed."""
    files = [
        artifact_path(a.key, case)
        for _, case in sorted(CASES.items())
        for a in artifacts.case_artifacts(case, on_request=True)
        if artifacts.producers()[a.key].on_request
    ]
    if files and shutil.which("flow") is None:
        print(
            "gridlib: simulate: OPM Flow ('flow') is not installed: no case is simulated "
            "(Debian/Ubuntu: apt-get install libopm-simulators-bin)",
            file=sys.stderr,
        )
        return []
    return files


def rule_name(study):
    """The name of a study's variant rule: study_<study>, other characters than letters,
    digits and _ as _."""
    return re.sub(r"\W", "_", study)


def discover_studies(spec):
    """Validated studies keyed by name, from a glob (no match: no study) or a list of study
    files; each variant's case file (and the study's variants.yaml) written under
    results/<study>/ where its content changed, so that Snakemake reruns only the variants a
    change of the study file adds or changes."""
    base = Path(workflow.basedir)
    if isinstance(spec, str):
        pattern = spec if Path(spec).is_absolute() else str(base / spec)
        paths = sorted(glob.glob(pattern))
    else:
        paths = [p if Path(p).is_absolute() else str(base / p) for p in spec]
    try:
        # A job's process (spawned, or on a cluster node) trusts the checks of the process
        # that planned the run: parsing then costs little more with many variants.
        studies = load_studies(
            paths,
            RESULTS,
            check=workflow.is_main_process,
            max_memory_gb=config.get("max_memory_gb"),
        )
    except InputError as exc:
        problems = str(exc).splitlines()
        stop(
            "\n".join(problems)
            + f"\n{len(problems)} problem(s) in the study files; nothing was run"
        )
    rules = {}
    for name, study in studies.items():
        if name in CASES or name in ("logs", "benchmarks", "summary.csv", "report"):
            stop(
                f"{study.path}: name: '{name}' is taken by a case or by {RESULTS}/{name}; "
                "nothing was run"
            )
        other = rules.setdefault(rule_name(name), study)
        if other is not study:
            stop(
                f"{study.path}: name: '{name}' and '{other.name}' give the same rule "
                f"study_{rule_name(name)}; rename one; nothing was run"
            )
    if workflow.is_main_process:
        for study in studies.values():
            materialise(study, RESULTS)
    return studies


STUDIES = discover_studies(config.get("studies", "config/studies/*.yaml"))
STUDY_NAMES = "|".join(re.escape(n) for n in sorted(STUDIES)) or "(?!)"


def variant_out(name):
    """The path pattern of a variant's artifact: the case layout under results/<study>/<variant>/
    (``flow``: the folder of its OPM Flow deck)."""
    if name == "flow":
        return f"{RESULTS}/{{study}}/{{variant}}/flow"
    path = artifacts.artifacts()[name].path.replace("{case}", "{variant}")
    return f"{RESULTS}/{{study}}/{{variant}}/{path}"


def build_variant(case_file, summary, log_file, bench_record):
    """Build a variant (every stage, gridlib.stages.run_case) into the folder of ``summary``:
    from a thread of a Snakemake process, which may run other jobs in its other threads (a
    local run's with --force-use-threads, a cluster job's: cluster_jobs_in_threads), in a pool
    of warm worker processes, one per core (a variant's log and threads are its process's); in
    a job's own Snakemake process (a spawned job) right there. What it used of that process
    goes into ``bench_record``."""
    from gridlib.stages.workers import run_in_process, run_in_worker

    folder = Path(summary).parent
    if workflow.subprocess_exec:
        usage = run_in_process(case_file, folder, log_file)
    else:
        usage = run_in_worker(case_file, folder, log_file, workflow.cores or 1)
    record_usage(bench_record, usage)


def study_table_job(input, output, log_file, bench_record):
    """A study's table job (rules study_table, study_table_simulated): its table and pictures
    (gridlib.stages.study.stage_study) in the warm workers, as build_variant builds a variant:
    where the variants are built there (run: jobs in this process's threads), else here.
    What it used of that process goes into ``bench_record``.
    """
    from gridlib.stages.workers import study_table

    usage = study_table(
        input.manifest,
        list(input.summaries),
        dict(output.items()),
        list(input.get("simulations", [])),
        log_file,
        workers=None if workflow.subprocess_exec else (workflow.cores or 1),
    )
    record_usage(bench_record, usage)


def study_rules(name):
    """The rules of study ``name``'s variants: (rule name, artifact keys, variants), one per
    group of variants that keep the same artifacts (gridlib.study.artifact_groups): study_<name>,
    then study_<name>__2, ... where a varied key changes the artifacts (corner-point and PEBI
    grids)."""
    base = f"study_{rule_name(name)}"
    return [
        (base if k == 0 else f"{base}__{k + 1}", keys, variants)
        for k, (keys, variants) in enumerate(artifact_groups(STUDIES[name]))
    ]


def study_variant_files(keys):
    """The outputs of a variant that keeps the artifacts ``keys`` (a study_<name> job): the
    variant's artifacts, the OPM Flow deck as the folder flow/ (the deck is named after the
    variant in upper case, which a pattern cannot say)."""
    table = artifacts.artifacts()
    files = {
        k: directory(variant_out(k)) if table[k].directory else variant_out(k)
        for k in keys
        if k != "flow"
    }
    if "flow" in keys:
        files["flow"] = directory(variant_out("flow"))
    return files


def study_variant_outputs(name):
    """Every declared artifact of every variant of the study ``name``."""
    return [
        variant_out(k).format(study=name, variant=v.name)
        for v in STUDIES[name].variants
        for k in v.artifacts
    ]


def study_table_inputs(wildcards):
    """The study table's inputs: the variant table, the variants' summary.json and, for a
    simulated study, their simulation/ folders (each with its responses.json)."""
    study = STUDIES[wildcards.study]
    inputs = {
        "manifest": f"{RESULTS}/{study.name}/variants.yaml",
        "summaries": [
            f"{RESULTS}/{study.name}/{v.name}/summary.json" for v in study.variants
        ],
    }
    if study.simulation.simulate:
        inputs["simulations"] = study_simulation_outputs(study.name)
    return inputs


def study_simulation_outputs(name):
    """The simulation/ folders of the variants of study ``name`` (none unless it simulates)."""
    study = STUDIES[name]
    if not study.simulation.simulate:
        return []
    return [f"{RESULTS}/{name}/{v.name}/simulation" for v in study.variants]


def study_simulation_options(study):
    """What a study's Flow jobs take from the study file (their params: a change of one of
    them reruns them; the study file's path is not one, so that moving the project reruns
    nothing)."""
    sim = study.simulation
    return {
        "times": list(sim.times),
        "water_cut": sim.water_cut,
        "on_failure": sim.on_failure,
    }


def variant_report_days(study, variant):
    """The report days of a variant (its case's simulation.report_days)."""
    data = next(v.data for v in study.variants if v.name == variant)
    return [float(d) for d in data["simulation"].get("report_days", [])]


def simulate_variant_job(study, variant, flow_folder, output, log_file, params):
    """A study's Flow job (the rules study_simulate_<study>), the variant's deck through OPM Flow
    (gridlib.stages.study_simulate), here (a thread of the Snakemake process, or the job's
    own process on a cluster). A failure with on_failure: stop is one line naming the study
    file, the variant and Flow's reason."""
    from gridlib.stages.study_simulate import simulate_variant

    options = params.options
    try:
        simulate_variant(
            flow_folder,
            output,
            study_file=str(study.path),
            variant=variant,
            report_days=params.report_days,
            times=options["times"],
            water_cut=options["water_cut"],
            on_failure=options["on_failure"],
            log_file=log_file,
        )
    except InputError as exc:
        print(f"gridlib: {exc}", file=sys.stderr)
        raise


# A study's pictures beside study.png when it simulates (gridlib.io.study_pictures).
SIMULATED_STUDY_PICTURES = {
    "profiles": "study_profiles.png",
    "tornado": "study_tornado.png",
}


def study_names(simulated):
    """The studies (a regular expression of their names) that simulate, or that do not."""
    names = [
        n for n, s in sorted(STUDIES.items()) if s.simulation.simulate == simulated
    ]
    return "|".join(re.escape(n) for n in names) or "(?!)"


def study_table_files(simulated, study="{study}"):
    """The outputs of a study's table job (study_table, or study_table_simulated, the same
    job with the pictures of its simulations), by name; ``study`` a name or the wildcard.
    """
    files = {"csv": "study.csv", "nc": "study.nc", "png": "study.png"}
    if simulated:
        files |= SIMULATED_STUDY_PICTURES
    return {key: f"{RESULTS}/{study}/{name}" for key, name in files.items()}


def study_table_outputs(simulated):
    """:func:`study_table_files` with the report's captions: a subcategory per study under
    the studies' category, the table, then each picture with its caption
    (workflow/report/<name>.rst)."""
    out = {}
    for key, path in study_table_files(simulated).items():
        if key == "nc":
            out[key] = path
            continue
        caption = "study_table" if key == "csv" else Path(path).stem
        out[key] = report(
            path,
            caption=f"../report/{caption}.rst",
            category=artifacts.STUDIES,
            subcategory="{study}",
        )
    return out


def all_outputs():
    """Every case's artifacts that stay (not temporary; the stages run on request only with
    `simulate: true`), the summary table, every study's variants and tables."""
    files = [f"{RESULTS}/summary.csv"] if CASES else []  # cases: [] builds studies only
    for name in sorted(STUDIES):
        files += study_variant_outputs(name)
        files += study_simulation_outputs(name)
        files += list(
            study_table_files(STUDIES[name].simulation.simulate, name).values()
        )
    for name, case in sorted(CASES.items()):
        files += [
            artifact_path(a.key, case)
            for a in artifacts.case_artifacts(case)
            if not a.temporary(case)
        ]
    if config.get("simulate", False):
        files += requested_outputs()
    return files
