"""Configuration, case discovery and validation (runs when the workflow is parsed)."""

import glob
from pathlib import Path

from snakemake.utils import validate

from gridlib.config import load_case

validate(config, "../schemas/config.schema.yaml")

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
    if not paths:
        raise ValueError(f"config: cases: no case file matches {spec!r}")
    cases = {}
    for path in paths:
        case = load_case(path)  # raises naming the file and key on any schema error
        if case.name in cases:
            raise ValueError(
                f"{path}: name: '{case.name}' is also used by {cases[case.name].path}"
            )
        cases[case.name] = case
    return cases


CASES = discover_cases(config["cases"])


wildcard_constraints:
    case="|".join(sorted(CASES)),


def case_file(wildcards):
    return str(CASES[wildcards.case].path)


def all_outputs():
    return expand(
        [
            f"{RESULTS}/{{case}}/grid.nc",
            f"{RESULTS}/{{case}}/geometry.nc",
            f"{RESULTS}/{{case}}/{{case}}.vtu",
        ],
        case=sorted(CASES),
    )
