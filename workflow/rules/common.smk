"""Configuration, case discovery and validation (runs when the workflow is parsed).

A broken configuration or case file stops the run before any job: every problem of every
case file is printed, one line each naming the file and the key, without a traceback.
"""

import glob
import re
import shutil
import sys
from pathlib import Path

import yaml
from snakemake.utils import validate

from gridlib.config import load_cases
from gridlib.config import validate as check_schema
from gridlib.errors import InputError
from gridlib.study import load_studies, materialise


def check_config(data, source):
    """The configuration against its schema: an InputError naming the key."""
    with open(
        Path(workflow.basedir) / "workflow" / "schemas" / "config.schema.yaml"
    ) as f:
        check_schema(data, yaml.safe_load(f), source)


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
        return load_cases(paths)
    except InputError as exc:
        problems = str(exc).splitlines()
        stop(
            "\n".join(problems)
            + f"\n{len(problems)} problem(s) in the case files; nothing was run"
        )


CASES = discover_cases(config["cases"])


wildcard_constraints:
    case="|".join(sorted(CASES)) or "(?!)",


def _cases_where(test):
    names = sorted(name for name, case in CASES.items() if test(case))
    return "|".join(names) if names else "(?!)"  # (?!) matches nothing


WITH_FLOW_DECK = _cases_where(lambda c: c.writes_flow_deck)
WITH_SIMULATION = _cases_where(lambda c: c.writes_flow_deck and c.has_simulation)
KEPT = _cases_where(
    lambda c: c.keeps_stage_files
)  # outputs.stage_files: true (default)
DROPPED = _cases_where(lambda c: not c.keeps_stage_files)  # stage files are temp()


def stage_cases(test, kept):
    """The cases where ``test(case)`` whose stage files are kept (``kept``) or dropped."""
    return _cases_where(lambda c: test(c) and c.keeps_stage_files == kept)


FLOW_NAMES = "|".join(sorted(c.flow_name for c in CASES.values())) or "(?!)"
EXPORTS = ("nc", "vtu", "faults", "png", "histograms", "summary")
WITH_VTU = _cases_where(lambda c: c.writes_vtu)
WITHOUT_VTU = _cases_where(lambda c: not c.writes_vtu)


def case_file(wildcards):
    return str(CASES[wildcards.case].path)


def out(name):
    """The path pattern of a case artifact (see gridlib.stages.case_outputs)."""
    return {
        "horizons": f"{RESULTS}/{{case}}/horizons.nc",
        "grid": f"{RESULTS}/{{case}}/grid.nc",
        "grdecl": f"{RESULTS}/{{case}}/grid.grdecl",
        "geometry": f"{RESULTS}/{{case}}/geometry.nc",
        "petrophysics": f"{RESULTS}/{{case}}/petrophysics.nc",
        "coarse": f"{RESULTS}/{{case}}/coarse.nc",
        "transmissibility": f"{RESULTS}/{{case}}/transmissibility.nc",
        "nc": f"{RESULTS}/{{case}}/{{case}}.nc",
        "vtu": f"{RESULTS}/{{case}}/{{case}}.vtu",
        "faults": f"{RESULTS}/{{case}}/{{case}}_faults.vtp",
        "png": f"{RESULTS}/{{case}}/{{case}}.png",
        "histograms": f"{RESULTS}/{{case}}/{{case}}_histograms.png",
        "summary": f"{RESULTS}/{{case}}/summary.json",
    }[name]


def deck_of(wildcards):
    """The case's OPM Flow deck: flow/<NAME>.DATA, NAME the case name in upper case."""
    case = CASES[wildcards.case]
    return f"{RESULTS}/{case.name}/flow/{case.flow_name}.DATA"


def simulation_outputs():
    """The targets of `snakemake simulate`: every case with a `simulation` section through OPM Flow;
    nothing (with a warning) where `flow` is not installed."""
    names = [
        n for n, c in sorted(CASES.items()) if c.writes_flow_deck and c.has_simulation
    ]
    if names and shutil.which("flow") is None:
        print(
            "gridlib: simulate: OPM Flow ('flow') is not installed: no case is simulated "
            "(Debian/Ubuntu: apt-get install libopm-simulators-bin)",
            file=sys.stderr,
        )
        return []
    return [
        f"{RESULTS}/{n}/flow/{item}"
        for n in names
        for item in ("summary.json", f"{n}_wells.png", f"{n}_flow.vtu")
    ]


def optional(name, wanted):
    """An input function: the artifact ``name`` for cases where ``wanted(case)``, else nothing."""

    def inputs(wildcards):
        if wanted(CASES[wildcards.case]):
            return {name: out(name).format(case=wildcards.case)}
        return {}

    return inputs


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
        studies = load_studies(paths, RESULTS, check=workflow.is_main_process)
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
STUDY_ARTIFACTS = {n: s.variants[0].artifacts for n, s in STUDIES.items()}


def variant_out(name):
    """The path pattern of a variant's artifact: the case layout under results/<study>/<variant>/."""
    if name == "flow":
        return f"{RESULTS}/{{study}}/{{variant}}/flow"
    return (
        out(name)
        .replace("{case}/", "{study}/{variant}/")
        .replace("{case}", "{variant}")
    )


def build_variant(case_file, summary, log_file):
    """Build a variant (every stage, gridlib.stages.run_case) into the folder of ``summary``:
    in the Snakemake process that parsed the workflow (run: jobs in its threads), in a pool
    of warm worker processes, one per core; in a job's own process (a spawned or cluster
    job) right there."""
    from gridlib.stages.workers import run_in_process, run_in_worker

    folder = Path(summary).parent
    if workflow.is_main_process:
        run_in_worker(case_file, folder, log_file, workflow.cores or 1)
    else:
        run_in_process(case_file, folder, log_file)


def study_variant_files(name):
    """The outputs of a variant of study ``name`` (its study_<name> jobs): the variant's
    artifacts, the OPM Flow deck as the folder flow/ (the deck is named after the variant in
    upper case, which a pattern cannot say)."""
    artifacts = STUDY_ARTIFACTS[name]
    files = {k: variant_out(k) for k in artifacts if k != "flow"}
    if "flow" in artifacts:
        files["flow"] = directory(variant_out("flow"))
    return files


def study_variant_outputs(name):
    """Every declared artifact of every variant of the study ``name``."""
    study = STUDIES[name]
    return [
        variant_out(k).format(study=name, variant=v.name)
        for v in study.variants
        for k in STUDY_ARTIFACTS[name]
    ]


def study_table_inputs(wildcards):
    study = STUDIES[wildcards.study]
    return {
        "manifest": f"{RESULTS}/{study.name}/variants.yaml",
        "summaries": [
            f"{RESULTS}/{study.name}/{v.name}/summary.json" for v in study.variants
        ],
    }


def all_outputs():
    files = [f"{RESULTS}/summary.csv"] if CASES else []  # cases: [] builds studies only
    for name in sorted(STUDIES):
        files += study_variant_outputs(name)
        files += [f"{RESULTS}/{name}/study.{ext}" for ext in ("csv", "nc", "png")]
    for name, case in sorted(CASES.items()):
        files += [
            out(k).format(case=name) for k in EXPORTS if k != "vtu" or case.writes_vtu
        ]
        if case.writes_grdecl and (case.keeps_stage_files or not case.writes_flow_deck):
            files.append(out("grdecl").format(case=name))
        if case.has_transmissibility and case.keeps_stage_files:
            files.append(out("transmissibility").format(case=name))
        if case.writes_flow_deck:
            files.append(f"{RESULTS}/{name}/flow/{case.flow_name}.DATA")
    if config.get("simulate", False):
        files += simulation_outputs()
    return files
