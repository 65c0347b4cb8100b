"""Studies: variants of one base case, built like cases (``config/studies/<study>.yaml``).

A study file names a base case, dotted keys into it with lists of values (``vary``),
how the lists combine (``product`` or ``zip``), and how many random-field realisations
each combination gets::

    name: throw_sweep
    base: ../cases/faulted_pebi.yaml    # relative to the study file
    vary:
      faults.0.throw: [0, 10, 20, 40]   # list items by their 0-based index
      grid.cell_size: [50, 80]
    combine: product
    realisations: 3
    seed: 5

Every variant is the base case with its values, its own name and seed, validated like a
case; a problem is one InputError line naming the study file, the key and the variant.

**Variant names** (:func:`variant_name`): for each varied key its label (the last
component of the dotted key that is not an index; the whole dotted key where two keys
share it), a ``-``, the value (integers as written, other numbers as Python's ``repr``,
strings as they are; the value's position in its list, ``#0``, ``#1``..., written ``v0``,
``v1``..., where the text would hold other characters than letters, digits, ``.``, ``_``
and ``-``), joined by ``_``; then ``_r`` and the realisation: ``throw-10_cell_size-50_r0``.

**Alternatives** (:class:`Alternative`): a varied key's values may be whole mappings, each
with a ``label`` (letters, digits, ``.``, ``_``, ``-``), set in place of the base case's value
at the key without the label: a grid question (a corner-point against a PEBI ``grid``
section) is a key whose values are grid sections. The label stands for the mapping in the
variant's name (``grid-pebi_r0``) and in the study's table. Either every value of a key has
a label or none (:func:`_alternatives`).

**Seeds**: realisation ``r`` (0-based) of every combination gets the case seed
``seed + 3 r``: a case's random fields use its seed (porosity), seed + 1 (permeability)
and seed + 2 (NTG), so realisations never share a field's seed, and the combinations of
one realisation share theirs (differences between combinations come from the values,
not from the noise). ``seed`` defaults to the base case's.

**Simulation** (:class:`StudySimulation`, :func:`study_simulation`): ``simulate: true`` runs every
variant's OPM Flow deck (the base case needs its ``simulation`` section); ``responses.times``
(report days of the base case) and ``responses.water_cut`` say what the table adds of each run,
``on_failure`` whether a failed run is reported (``report``) or an error (``stop``).

**Pictures**: ``pictures: false`` gives every variant ``outputs.pictures: false`` (no PNG of
its own, every other file the same: half of a small variant's build); default true, a
variant's pictures being how one looks at the variant that stands out in the table.
"""

from __future__ import annotations

import copy
import itertools
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from .artifacts import case_artifacts
from .config import (
    Case,
    check_case_data,
    load_named,
    parse_yaml,
    shared_schema,
    validate,
    with_deck_rock,
    with_defaults,
)
from .config.key_units import KeyQuantity, key_quantity
from .errors import InputError
from .io.atomic import atomic_path
from .io.datasets import damaged

STUDY_SCHEMA = "study.schema.yaml"
SEED_STEP = 3  # a case's fields use seed, seed + 1, seed + 2
DEFAULT_WATER_CUT = 0.01  # a producer's water breakthrough: its water cut first exceeds this
_SAFE = re.compile(r"^[A-Za-z0-9._-]+$")
# Keys of a case that name files relative to the case file (rewritten for the variant's folder;
# "*": every item of a list or value of a mapping).
_WELL_FILES = (("trajectory",), ("trajectory", "file"), ("survey", "file"))
_FILE_KEYS = (
    ("horizons", "surfaces", "*", "points"),
    ("horizons", "surfaces", "*", "surface"),
    ("grid", "file"),
    ("grid", "parameters", "*"),
    ("faults", "*", "sticks"),
    *(("wells", "*", *keys) for keys in _WELL_FILES),
    *(("wells", "*", "branches", "*", *keys) for keys in _WELL_FILES),
)


@dataclass(frozen=True)
class Alternative:
    """A labelled value of a varied key: a whole mapping (a section such as ``grid``, a list
    item such as ``faults.0``) that replaces the base case's value at the key; ``label`` names
    it in variant names and in the study's table (``values`` of a :class:`Variant`)."""

    label: str
    value: dict[str, Any]


@dataclass(frozen=True)
class Variant:
    """One variant: the base case with ``values`` (dotted key -> value; an
    :class:`Alternative`'s label for a key of whole sections), in realisation ``realisation``
    with case seed ``seed``; ``data`` is its case (as written to its file)."""

    name: str
    values: dict[str, Any]
    realisation: int
    seed: int
    data: dict[str, Any] = field(repr=False)
    artifacts: tuple[str, ...] = ()

    def case_text(self) -> str:
        """The variant's case file (YAML)."""
        return yaml.safe_dump(self.data, sort_keys=False, default_flow_style=None, width=100)


@dataclass(frozen=True)
class StudySimulation:
    """The study's keys ``simulate``, ``responses`` and ``on_failure``: whether every variant's
    OPM Flow deck runs (one job per variant), the days (report days of the base case) at which
    the field responses are also tabulated, the water cut (fraction of the liquid rate) a
    producer's breakthrough exceeds, and whether a failed Flow run is reported (``report``: the
    variant is marked failed, the others go on) or an error (``stop``)."""

    simulate: bool = False
    times: tuple[float, ...] = ()
    water_cut: float = DEFAULT_WATER_CUT
    on_failure: str = "report"

    def manifest(self) -> dict[str, Any]:
        """As the study's variant table (variants.yaml) records it."""
        return {
            "times": [_plain_number(t) for t in self.times],
            "water_cut": self.water_cut,
            "on_failure": self.on_failure,
        }


def _plain_number(value: float) -> int | float:
    """A day as YAML and JSON write it: an integer where it is one."""
    return int(value) if float(value).is_integer() else float(value)


@dataclass(frozen=True)
class Study:
    """A validated study: its base case file, the varied keys and every variant."""

    name: str
    path: Path
    base: Path
    keys: tuple[str, ...]
    combine: str
    realisations: int
    seed: int
    variants: tuple[Variant, ...]
    # what each varied key measures (its unit follows from the base case's unit system)
    key_quantities: dict[str, KeyQuantity] = field(default_factory=dict)
    # whether and how the variants are simulated in OPM Flow (keys simulate, responses, on_failure)
    simulation: StudySimulation = field(default_factory=StudySimulation)

    def folder(self, results: str | os.PathLike) -> Path:
        return Path(results) / self.name

    def case_file(self, results: str | os.PathLike, variant: str) -> Path:
        """``results/<study>/<variant>/<variant>.yaml``: the variant's case file."""
        return self.folder(results) / variant / f"{variant}.yaml"


def _read_yaml(path: Path) -> Any:
    return parse_yaml(path.read_bytes(), path)


def _parts(key: str) -> list[str | int]:
    return [int(p) if p.isdigit() else p for p in key.split(".")]


def _bracketed(key: str) -> str:
    """``faults.0.throw`` as the case validation names it: ``faults[0].throw``."""
    return "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in _parts(key)).lstrip(".")


def _lookup_problem(data: Any, key: str) -> str | None:
    """Why ``key`` does not name a value of the base case, or None."""
    node, walked = data, []
    for part in _parts(key):
        here = ".".join(walked) or "the case"
        if isinstance(part, int):
            if not isinstance(node, list):
                return f"{here} is not a list (no item {part})"
            if part >= len(node):
                return f"{here} has {len(node)} item(s), no item {part}"
        else:
            if not isinstance(node, dict):
                return f"{here} is not a mapping (no key '{part}')"
            if part not in node:
                known = ", ".join(sorted(map(str, node))) or "none"
                return f"the base case has no key '{part}' in {here} (keys: {known})"
        node = node[part]
        walked.append(str(part))
    return None


def _set(data: Any, key: str, value: Any) -> None:
    *head, last = _parts(key)
    node = data
    for part in head:
        node = node[part]
    node[last] = copy.deepcopy(value)


def _labels(keys: list[str]) -> dict[str, str]:
    """Each key's label in variant names: its last non-index component, unless shared."""
    short = {k: next(str(p) for p in reversed(_parts(k)) if isinstance(p, str)) for k in keys}
    counts = {label: list(short.values()).count(label) for label in short.values()}
    return {k: (label if counts[label] == 1 else k) for k, label in short.items()}


def _value_text(value: Any, position: int) -> str:
    if isinstance(value, bool):
        text = str(value).lower()
    elif isinstance(value, int):
        text = str(value)
    elif isinstance(value, float):
        text = repr(value)
    elif isinstance(value, str):
        text = value
    elif isinstance(value, Alternative):
        text = value.label
    else:
        text = ""
    return text if _SAFE.match(text) else f"v{position}"


def variant_name(labels: dict[str, str], values: dict[str, tuple[int, Any]], realisation: int) -> str:
    """``<label>-<value>_..._r<realisation>`` (see the module's docstring); ``values``: key ->
    (position in its list, value)."""
    parts = [f"{labels[k]}-{_value_text(v, i)}" for k, (i, v) in values.items()]
    return "_".join(parts + [f"r{realisation}"])


def _alternatives(study: Path, key: str, values: list[Any]) -> list[Any]:
    """The values of varied ``key`` as listed, or, where they are mappings with a ``label``,
    as :class:`Alternative` s (the mapping without its label). Either every value of the key
    is a labelled mapping or none is; labels are names (:data:`_SAFE`) and differ; else one
    InputError naming the study file, the key and the item."""
    labelled = [isinstance(v, dict) and "label" in v for v in values]
    if not any(labelled):
        return values
    where, first_labelled = f"{study}: vary.{key}", labelled.index(True)
    for k, value in enumerate(values):
        if not labelled[k]:
            what = (
                "this mapping has no label"
                if isinstance(value, dict)
                else f"{_one_line(value)} is not a mapping"
            )
            raise InputError(
                f"{where}[{k}]: {what}, and item {first_labelled} is a mapping with a label: the values "
                "of a key are all mappings with a label (whole sections or list items) or none is"
            )
        label = value["label"]
        if not isinstance(label, str) or not _SAFE.match(label):
            raise InputError(
                f"{where}[{k}].label: {_one_line(label)} must be text of letters, digits, '.', '_' and '-' "
                "(it names the variants)"
            )
        first = next(j for j in range(k + 1) if values[j]["label"] == label)
        if first != k:
            raise InputError(f"{where}[{k}].label: '{label}' is also the label of item {first}")
    return [Alternative(v["label"], {n: x for n, x in v.items() if n != "label"}) for v in values]


def _set_values(data: dict[str, Any], values: dict[str, Any]) -> None:
    """Set each varied key's value in the case ``data``, the keys with fewer components first:
    a key inside a varied section (``grid.layers`` beside ``grid``) then changes the section
    the variant has, whatever the order the study lists them in."""
    for key in sorted(values, key=lambda k: len(_parts(k))):
        _set(data, key, _case_value(values[key]))


def _one_line(value: Any) -> str:
    """``value`` as one line of YAML flow style (for messages)."""
    return yaml.safe_dump(value, default_flow_style=True, width=10**6).strip().removesuffix("...").strip()


def _table_value(value: Any) -> Any:
    """A varied value as the study's table holds it: an :class:`Alternative` by its label."""
    return value.label if isinstance(value, Alternative) else value


def _case_value(value: Any) -> Any:
    """A varied value as the variant's case holds it: an :class:`Alternative`'s mapping."""
    return value.value if isinstance(value, Alternative) else value


def _relocate_files(data: dict[str, Any], base_dir: Path, folder: Path) -> None:
    """Rewrite the base case's file references (relative to the base case file) relative to
    ``folder``, where the variant's case file lives."""

    def visit(node: Any, path: tuple[str, ...]) -> None:
        if not path:
            return
        head, rest = path[0], path[1:]
        if head == "*":
            keys = (
                range(len(node)) if isinstance(node, list) else list(node) if isinstance(node, dict) else []
            )
        else:
            keys = [head] if isinstance(node, dict) and head in node else []
        for key in keys:
            if rest:
                visit(node[key], rest)
            elif isinstance(node[key], str) and not Path(node[key]).is_absolute():
                node[key] = os.path.relpath(base_dir / node[key], folder)

    for keys in _FILE_KEYS:
        visit(data, keys)


def load_study(
    path: str | os.PathLike,
    results: str | os.PathLike = "results",
    check: bool = True,
    max_memory_gb: float | None = None,
) -> Study:
    """Read and validate a study file and every variant of it (as a case that would live in
    ``results/<study>/<variant>/``). Problems raise one InputError line naming the study file
    and the key (and the variant, for a value that makes a variant invalid). ``check=False``
    skips validating the base case and each variant as a case (a job's process: the process
    that planned the run has checked them). ``max_memory_gb``: the memory limit of the size
    check, as :func:`gridlib.config.load_case`."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: study file not found")
    spec = _read_yaml(p)
    if not isinstance(spec, dict):
        raise InputError(f"{p}: a study must be a mapping of keys (name, base, vary, ...)")
    validate(spec, shared_schema(STUDY_SCHEMA), str(p))
    if spec["name"] != p.stem:
        raise InputError(f"{p}: name: '{spec['name']}' must equal the file name '{p.stem}'")
    base = p.parent / spec["base"]
    if not base.is_file():
        raise InputError(f"{p}: base: case file '{spec['base']}' not found (looked for {base})")
    base_data = _read_yaml(base)
    if not isinstance(base_data, dict):
        raise InputError(f"{p}: base: {base} is not a case (a mapping of keys)")
    try:
        if check:
            check_case_data(base_data, base, str(base), max_memory_gb)
    except InputError as exc:
        raise InputError(f"{p}: base: {exc}") from None

    vary: dict[str, list[Any]] = {k: _alternatives(p, k, v) for k, v in spec["vary"].items()}
    keys = list(vary)
    for key in keys:
        if key in ("name", "seed"):
            raise InputError(
                f"{p}: vary.{key}: not varied by a study (variants are named by it; seeds by realisations)"
            )
        problem = _lookup_problem(base_data, key)
        if problem is not None:
            raise InputError(f"{p}: vary.{key}: {problem}")
    combine = spec.get("combine", "product")
    lists = [list(enumerate(vary[k])) for k in keys]
    if combine == "zip":
        lengths = {k: len(vary[k]) for k in keys}
        if len(set(lengths.values())) > 1:
            sizes = ", ".join(f"{k} has {n}" for k, n in lengths.items())
            raise InputError(f"{p}: combine: zip needs lists of equal length ({sizes})")
        combos = list(zip(*lists, strict=True))
    else:
        combos = list(itertools.product(*lists))
    realisations = int(spec.get("realisations", 1))
    pictures = bool(spec.get("pictures", True))
    seed = int(spec["seed"]) if "seed" in spec else int(base_data.get("seed", 0))
    labels = _labels(keys)
    results_dir = Path(results) / spec["name"]

    variants: list[Variant] = []
    seen: dict[str, str] = {}
    for combo in combos:
        values = dict(zip(keys, combo, strict=True))
        plain = {k: _table_value(v) for k, (_, v) in values.items()}
        for r in range(realisations):
            name = variant_name(labels, values, r)
            if name in seen:
                raise InputError(
                    f"{p}: vary: variants {seen[name]} and {plain} share the name '{name}' "
                    "(a value listed twice?)"
                )
            seen[name] = str(plain)
            data = copy.deepcopy(base_data)
            data["name"] = name
            data["seed"] = seed + SEED_STEP * r
            if not pictures:
                data["outputs"] = {**data.get("outputs", {}), "pictures": False}
            _set_values(data, {key: value for key, (_, value) in values.items()})
            folder = results_dir / name
            _relocate_files(data, base.parent, folder)
            where = folder / f"{name}.yaml"
            if check:
                checked = _check_variant(data, where, p, keys, name, max_memory_gb)
            else:  # unchecked, the variant still needs its defaults and the section its deck implies
                checked = with_deck_rock(with_defaults(data), where)
            variants.append(Variant(name, plain, r, data["seed"], data, artifacts_of(checked)))
    return Study(
        name=spec["name"],
        path=p,
        base=base,
        keys=tuple(keys),
        combine=combine,
        realisations=realisations,
        seed=seed,
        variants=tuple(variants),
        key_quantities=_key_quantities(p, keys, base_data),
        simulation=study_simulation(p, spec, base_data, variants),
    )


def artifact_groups(study: Study) -> list[tuple[tuple[str, ...], tuple[Variant, ...]]]:
    """The study's variants grouped by the artifacts they keep (:attr:`Variant.artifacts`), in
    the order the groups first appear: one group where the variants share their artifacts, more
    where a varied key changes them (a corner-point grid keeps a GRDECL and a ROFF file, a PEBI
    grid neither); the workflow declares each group's outputs in a rule of its own."""
    groups: dict[tuple[str, ...], list[Variant]] = {}
    for v in study.variants:
        groups.setdefault(v.artifacts, []).append(v)
    return [(keys, tuple(members)) for keys, members in groups.items()]


def study_simulation(
    study: Path, spec: dict[str, Any], base: dict[str, Any], variants: Sequence[Variant]
) -> StudySimulation:
    """The study's ``simulate``, ``responses`` and ``on_failure`` (schema-checked ``spec``),
    checked against the base case ``base``: ``simulate: true`` needs its ``simulation`` section
    and an OPM Flow deck for every variant (``flow`` among its artifacts), and every
    ``responses.times`` entry must be one of its ``simulation.report_days``. A problem is one
    InputError naming the study file and the key."""
    responses = spec.get("responses", {})
    out = StudySimulation(
        simulate=bool(spec.get("simulate", False)),
        times=tuple(float(t) for t in responses.get("times", ())),
        water_cut=float(responses.get("water_cut", DEFAULT_WATER_CUT)),
        on_failure=str(spec.get("on_failure", "report")),
    )
    if not out.simulate:
        return out
    if "simulation" not in base:
        raise InputError(
            f"{study}: simulate: the base case {spec['base']} has no simulation section "
            "(wells, report days: what OPM Flow would simulate)"
        )
    deckless = next((v for v in variants if "flow" not in v.artifacts), None)
    if deckless is not None:
        raise InputError(
            f"{study}: simulate: variant '{deckless.name}' of {spec['base']} gets no OPM Flow deck "
            "(a deck needs rock on a 3-D grid)"
        )
    days = [float(d) for d in base["simulation"].get("report_days", [])]
    for k, t in enumerate(out.times):
        if t not in days:
            listed = ", ".join(f"{_plain_number(d)}" for d in days) or "none"
            raise InputError(
                f"{study}: responses.times[{k}]: {_plain_number(t)} is not a report day of the base case "
                f"(simulation.report_days: {listed})"
            )
    return out


def _key_quantities(study: Path, keys: list[str], base: dict[str, Any]) -> dict[str, KeyQuantity]:
    """What each varied key of the base case measures (:func:`gridlib.config.key_units.key_quantity`)."""
    try:
        return {key: key_quantity(key, base) for key in keys}
    except InputError as exc:
        raise InputError(f"{study}: vary.{exc}") from None


def artifacts_of(data: dict[str, Any]) -> tuple[str, ...]:
    """The keys of the artifacts a case with (validated, defaults filled in) ``data`` keeps
    (:func:`gridlib.artifacts.case_artifacts`; ``flow``: the folder of its OPM Flow deck)."""
    case = Case(name=data["name"], path=Path(f"{data['name']}.yaml"), sha256="", data=data)
    kept = [a.key for a in case_artifacts(case) if not a.temporary(case)]
    return tuple("flow" if key == "flow_deck" else key for key in kept)


def _check_variant(
    data: dict[str, Any], where: Path, study: Path, keys: list[str], name: str, max_memory_gb: float | None
) -> dict[str, Any]:
    """The variant's case validated like a case file at ``where``; a problem names the study
    file, the varied key it concerns (all of them where it is not one key's) and the variant."""
    try:
        return check_case_data(data, where, "", max_memory_gb)
    except InputError as exc:
        message = str(exc).removeprefix(": ")
        concerned = [k for k in keys if message.startswith(_bracketed(k)) or message.startswith(k)]
        key = f"vary.{concerned[0]}" if concerned else "vary"
        raise InputError(f"{study}: {key}: variant '{name}': {message}") from None


def load_studies(
    paths: list[str | os.PathLike],
    results: str | os.PathLike = "results",
    check: bool = True,
    max_memory_gb: float | None = None,
) -> dict[str, Study]:
    """Every study file read and validated, keyed by name; one InputError with one line per
    problem (as :func:`gridlib.config.load_cases`); ``check`` and ``max_memory_gb`` as
    :func:`load_study`."""
    return load_named(paths, lambda path: load_study(path, results, check, max_memory_gb))


def write_if_changed(path: str | os.PathLike, text: str) -> bool:
    """Write ``text`` to ``path`` atomically unless it already holds it (its mtime then stays,
    so Snakemake reruns only what a changed file feeds). True if written."""
    target = Path(path)
    if target.is_file() and target.read_text(encoding="utf-8") == text:
        return False
    with atomic_path(target) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return True


def manifest_text(study: Study) -> str:
    """The study's variant table (YAML): what each varied key measures (``key_quantities``:
    its quantity, null for none, and the unit system where it has its own), then name, values,
    realisation and seed of each variant, in order; the input of the study's table (study.csv,
    study.nc, study.png)."""
    quantities = {
        k: {"quantity": q.quantity} | ({"unit_system": q.unit_system} if q.unit_system else {})
        for k, q in study.key_quantities.items()
    }
    doc = {
        "study": study.name,
        "keys": list(study.keys),
        "key_quantities": quantities,
        "combine": study.combine,
    }
    if study.simulation.simulate:  # the table then reads each variant's responses
        doc["simulation"] = study.simulation.manifest()
    doc |= {
        "variants": [
            {"name": v.name, "values": v.values, "realisation": v.realisation, "seed": v.seed}
            for v in study.variants
        ],
    }
    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100)


def read_manifest(path: str | os.PathLike) -> dict[str, Any]:
    """The variant table :func:`manifest_text` wrote (results/<study>/variants.yaml), read back;
    one InputError naming the file where it is missing, not YAML or not such a table
    (:func:`gridlib.io.datasets.damaged`)."""
    try:
        doc = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise damaged(path, "no such file") from None
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        raise damaged(path, f"not YAML: {' '.join(str(exc).split())}") from None
    variant_keys = {"name", "values", "realisation", "seed"}
    if (
        not isinstance(doc, dict)
        or not {"study", "keys", "combine", "variants"} <= set(doc)
        or not isinstance(doc["keys"], list)
        or not isinstance(doc["variants"], list)
        or not all(isinstance(v, dict) and variant_keys <= set(v) for v in doc["variants"])
        or not all(
            isinstance(v["values"], dict) and set(doc["keys"]) <= set(v["values"]) for v in doc["variants"]
        )
    ):
        raise damaged(
            path, "not a study's variant table (study, keys, combine, variants with name and values)"
        )
    return doc


def materialise(study: Study, results: str | os.PathLike) -> list[Path]:
    """Write each variant's case file and the study's manifest under ``results/<study>/``
    where their content changed; returns the files written."""
    written = []
    for v in study.variants:
        target = study.case_file(results, v.name)
        if write_if_changed(target, v.case_text()):
            written.append(target)
    manifest = study.folder(results) / "variants.yaml"
    if write_if_changed(manifest, manifest_text(study)):
        written.append(manifest)
    return written
