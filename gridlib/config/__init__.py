"""Case files: loading, validation against the case schema, provenance.

A case is a YAML file validated against ``gridlib/schemas/case.schema.yaml``
(the same file the workflow uses as ``workflow/schemas/case.schema.yaml``).
Every problem is reported as one :class:`~gridlib.errors.InputError` naming the
file and the key path, e.g. ``config/cases/x.yaml: grid.dims[1]: 0 is less
than the minimum of 1``.
"""

from __future__ import annotations

import copy
import functools
import hashlib
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

import jsonschema
import yaml

from .errors import InputError
from .version import __version__

T = TypeVar("T")

SCHEMA_FILE = "case.schema.yaml"


def load_schema(name: str = SCHEMA_FILE) -> dict[str, Any]:
    """The JSON schema shipped with gridlib (as a dict; a copy of the one parsed per process)."""
    return copy.deepcopy(shared_schema(name))


@functools.cache
def shared_schema(name: str) -> dict[str, Any]:
    """The schema parsed once per process and shared (do not modify it; :func:`load_schema`
    gives a copy): a study validates every variant, and each stage its case."""
    text = resources.files("gridlib").joinpath("schemas", name).read_text(encoding="utf-8")
    return yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


@dataclass(frozen=True)
class Case:
    """A validated case: its data (with defaults filled in) and provenance."""

    name: str
    path: Path
    sha256: str
    data: dict[str, Any] = field(repr=False)

    @property
    def seed(self) -> int:
        return int(self.data["seed"])

    @property
    def grid_type(self) -> str:
        """``grid.type``: cartesian, tensor, layered, cornerpoint, pebi or deck."""
        return self.data["grid"]["type"]

    @property
    def has_horizons(self) -> bool:
        return "horizons" in self.data

    @property
    def writes_grdecl(self) -> bool:
        """Corner-point and deck grids are also written as GRDECL for simulators."""
        return self.grid_type in ("cornerpoint", "deck")

    @property
    def has_petrophysics(self) -> bool:
        """The case has rock: a `petrophysics` section, given or, for a deck grid whose deck gives
        PORO and PERMX, implied (:func:`check_case_data` adds an empty one: the deck's rock)."""
        return "petrophysics" in self.data

    @property
    def has_coarsening(self) -> bool:
        return "coarsen" in self.data

    @property
    def has_transmissibility(self) -> bool:
        """The transmissibility stage runs: it needs the case's rock properties."""
        return self.has_petrophysics

    @property
    def keeps_stage_files(self) -> bool:
        """``outputs.stage_files``: the per-stage netCDF files stay beside ``{case}.nc``."""
        return bool(self.data["outputs"]["stage_files"])

    @property
    def writes_vtu(self) -> bool:
        """``outputs.vtu``: the grid with its cell data as ``{case}.vtu``."""
        return bool(self.data["outputs"]["vtu"])

    @property
    def is_3d(self) -> bool:
        """The grid has depth: every type but 2-D cartesian and tensor grids."""
        grid = self.data["grid"]
        if grid["type"] == "cartesian":
            return len(grid["dims"]) == 3
        if grid["type"] == "tensor":
            return "z" in grid
        return True

    @property
    def has_simulation(self) -> bool:
        """The case says what its OPM Flow deck simulates (wells, report steps)."""
        return "simulation" in self.data

    @property
    def writes_flow_deck(self) -> bool:
        """Cases with rock on a 3-D grid get an OPM Flow deck (flow/<NAME>.DATA)."""
        return self.has_petrophysics and self.is_3d

    @property
    def flow_name(self) -> str:
        """The deck's name: the case name in upper case (flow/<NAME>.DATA)."""
        return self.name.upper()

    def provenance(self) -> dict[str, object]:
        """Attributes every output of this case carries."""
        return {
            "gridlib_version": __version__,
            "case_name": self.name,
            "case_file": str(self.path),
            "case_sha256": self.sha256,
            "seed": self.seed,
        }


def _key_path(error: jsonschema.ValidationError) -> str:
    parts = []
    for p in error.absolute_path:
        parts.append(f"[{p}]" if isinstance(p, int) else f".{p}")
    return "".join(parts).lstrip(".") or "(top level)"


def _describe(error: jsonschema.ValidationError) -> str:
    if error.validator == "additionalProperties":
        allowed = sorted(error.schema.get("properties", {}))
        return f"{error.message}; allowed keys: {', '.join(allowed)}"
    return error.message


def validate(data: Any, schema: dict[str, Any], source: str) -> None:
    """Raise InputError naming ``source`` and the key path of the most relevant error."""
    validator = jsonschema.Draft202012Validator(schema)
    errors = list(validator.iter_errors(data))
    if not errors:
        return
    best = jsonschema.exceptions.best_match(errors)
    # Prefer the deepest error: it names the offending key rather than a oneOf/if branch.
    deepest = max(errors, key=lambda e: (len(list(e.absolute_path)), e is best))
    chosen = deepest if len(list(deepest.absolute_path)) > len(list(best.absolute_path)) else best
    while chosen.context:  # descend into oneOf/anyOf to the specific failure
        chosen = max(chosen.context, key=lambda e: len(list(e.absolute_path)))
    raise InputError(f"{source}: {_key_path(chosen)}: {_describe(chosen)}")


def with_defaults(data: dict[str, Any]) -> dict[str, Any]:
    """A copy of a case's ``data`` with the schema's defaults filled in (as :func:`load_case`
    does after validating it)."""
    schema = shared_schema(SCHEMA_FILE)
    return _fill_defaults(copy.deepcopy(data), schema, schema)


def section_defaults(name: str) -> dict[str, Any]:
    """A section of the case schema (``$defs``: ``simulation``, ``coarsen``, ...) as its
    defaults alone fill it: what a case without the section means."""
    schema = shared_schema(SCHEMA_FILE)
    return _fill_defaults({}, schema["$defs"][name], schema)


def _fill_defaults(data: Any, schema: dict[str, Any], root: dict[str, Any]) -> Any:
    """Fill ``default`` values of object properties, also in the items of arrays (following
    $ref, allOf/if/then)."""
    if "$ref" in schema:
        ref = schema["$ref"].split("/")[-1]
        schema = {**root["$defs"][ref], **{k: v for k, v in schema.items() if k != "$ref"}}
    if isinstance(data, list) and isinstance(schema.get("items"), dict):
        for item in data:
            _fill_defaults(item, schema["items"], root)
        return data
    if not isinstance(data, dict):
        return data
    for key, sub in schema.get("properties", {}).items():
        if not isinstance(sub, dict):
            continue
        if key not in data and "default" in sub:
            data[key] = copy.deepcopy(sub["default"])
        if key in data:
            data[key] = _fill_defaults(data[key], sub, root)
    for branch in schema.get("allOf", []):
        cond = branch.get("if")
        if cond is None or jsonschema.Draft202012Validator(cond).is_valid(data):
            if "then" in branch:
                _fill_defaults(data, branch["then"], root)
    return data


def parse_yaml(raw: bytes, path: Path) -> Any:
    """The YAML document ``raw`` read from ``path``; InputError naming the file and line."""
    try:
        return yaml.safe_load(raw)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}:{where}: not valid YAML ({getattr(exc, 'problem', exc)})") from exc


def load_case(path: str | os.PathLike) -> Case:
    """Read and validate a case file; defaults are filled in."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: case file not found")
    raw = p.read_bytes()
    data = parse_yaml(raw, p)
    if not isinstance(data, dict):
        raise InputError(f"{p}: a case must be a mapping of keys (name, grid, ...)")
    checked = check_case_data(data, p, str(p))
    return Case(name=data["name"], path=p, sha256=hashlib.sha256(raw).hexdigest(), data=checked)


def check_case_data(data: dict[str, Any], path: Path, source: str) -> dict[str, Any]:
    """A case's data validated as :func:`load_case` does, as if read from ``path`` (the file
    name must be the case's name; files are looked for beside it); returns a copy with the
    defaults filled in. Problems raise an InputError starting with ``source``."""
    schema = load_schema()
    validate(data, schema, source)
    if data["name"] != path.stem:
        raise InputError(f"{source}: name: '{data['name']}' must equal the file name '{path.stem}'")
    data = with_defaults(data)
    try:
        data = with_deck_rock(data, path)
    except InputError as exc:
        raise InputError(f"{source}: grid.file: {exc}") from None
    problem = _consistency_problem(data, path)
    if problem is not None:
        raise InputError(f"{source}: {problem}")
    return data


def named_file(case_file: Path, name: str | os.PathLike) -> Path:
    """A file a case names: ``name`` relative to the case file's folder (or absolute), its ``..``
    resolved by the path's text, not by the file system: a study's variant is checked before its
    folder results/<study>/<variant>/ exists, and names its base case's files from there.

    >>> named_file(Path("results/sweep/fine_r0/fine_r0.yaml"), "../../../config/cases/top.csv").as_posix()
    'config/cases/top.csv'
    """
    return Path(os.path.normpath(Path(case_file).parent / name))


DECK_ROCK = ("PORO", "PERMX")  # what a deck must give for its case to have rock without a section


def with_deck_rock(data: dict[str, Any], path: Path) -> dict[str, Any]:
    """``data`` (a case read from ``path``) with an empty ``petrophysics`` section where the
    case is a deck grid without one and its deck gives PORO and PERMX: such a case has the
    deck's rock (:func:`gridlib.case.rock.case_rock`), and its transmissibilities and OPM Flow
    deck, as a user of the deck expects. Other data are returned as they are."""
    grid = data.get("grid", {})
    if grid.get("type") != "deck" or "petrophysics" in data:
        return data
    deck = named_file(path, grid["file"])
    if not deck.is_file():
        return data  # _consistency_problem names the missing file
    if not set(DECK_ROCK) <= deck_cell_keywords(deck, grid["unknown_keywords"]):
        return data
    return {**data, "petrophysics": {}}


def deck_cell_keywords(path: Path, unknown_keywords: str = "error") -> frozenset[str]:
    """The cell keywords (PORO, PERMX, MULTZ, ...) the deck file ``path`` gives; a text deck is
    read with ``unknown_keywords`` (a deck case's ``grid.unknown_keywords``)."""
    p = path.resolve()
    stat = p.stat()
    return _deck_cell_keywords(p, stat.st_mtime_ns, stat.st_size, unknown_keywords)


@functools.lru_cache(maxsize=8)
def _deck_cell_keywords(path: Path, mtime_ns: int, size: int, unknown_keywords: str) -> frozenset[str]:
    # Cached per process on the file's identity: every stage and every variant of a study loads
    # the case again. (An INCLUDEd file edited in the same process is not seen: runs are new
    # processes.)
    from .io.registry import find_format, read  # deferred: the workflow's parse imports config only

    options = {"unknown_keywords": unknown_keywords} if find_format(path, "deck").name == "grdecl" else {}
    return frozenset(read(path, kind="deck", **options).cell_data)


def load_cases(paths: Sequence[str | os.PathLike]) -> dict[str, Case]:
    """Every case file read and validated, keyed by case name.

    All problems are collected before raising: one :class:`InputError` whose message has
    one line per broken file (each naming the file and the key, as :func:`load_case`)
    and per name used twice, so a run with several broken case files names all of them.

    >>> load_cases(["no/such/a.yaml", "no/such/b.yaml"])
    Traceback (most recent call last):
    ...
    gridlib.errors.InputError: no/such/a.yaml: case file not found
    no/such/b.yaml: case file not found
    """
    return load_named(paths, load_case)


def load_named(paths: Sequence[str | os.PathLike], load: Callable[[str | os.PathLike], T]) -> dict[str, T]:
    """``load(path)`` of every path (a value with ``name`` and ``path``), keyed by name: one
    InputError with one line per problem (a broken file, a name used twice), all files read."""
    loaded: dict[str, T] = {}
    problems: list[str] = []
    for path in paths:
        try:
            value = load(path)
        except InputError as exc:
            problems.append(" ".join(str(exc).split("\n")))
            continue
        name = value.name  # type: ignore[attr-defined]
        if name in loaded:
            problems.append(f"{path}: name: '{name}' is also used by {loaded[name].path}")  # type: ignore[attr-defined]
            continue
        loaded[name] = value
    if problems:
        raise InputError("\n".join(problems))
    return loaded


def _axis_range(spec: Any) -> tuple[float, float]:
    if isinstance(spec, dict):
        return float(spec["start"]), float(spec["stop"])
    return float(min(spec)), float(max(spec))


def _num_layers(data: dict[str, Any]) -> int | None:
    grid = data["grid"]
    kind = grid["type"]
    if kind in ("cornerpoint", "pebi"):
        layers = grid["layers"]
        zones = len(data["horizons"]["surfaces"]) - 1
        return int(layers) * zones if isinstance(layers, int) else int(sum(layers))
    if kind == "layered":
        lay = grid["layers"]
        return len(lay["thickness"]) if "thickness" in lay else int(lay["num_layers"])
    if kind == "cartesian" and len(grid["dims"]) == 3:
        return int(grid["dims"][2])
    return None


def _consistency_problem(data: dict[str, Any], path: Path) -> str | None:
    """What the schema cannot say: references between keys, files, faults and wells in the domain.

    Checked when the case is loaded (so the workflow stops before any job runs
    and leaves nothing behind); returns "key: message" or None.
    """
    grid = data["grid"]
    kind = grid["type"]
    horizons = data.get("horizons")
    if kind in ("cornerpoint", "pebi") and horizons is None:
        return f"grid.type: a {kind} grid is built between horizons: the case needs `horizons`"
    if horizons is not None:
        for k, surface in enumerate(horizons["surfaces"]):
            for key in ("points", "surface"):
                if key in surface and not named_file(path, surface[key]).is_file():
                    name, where = surface[key], named_file(path, surface[key])
                    return f"horizons.surfaces[{k}].{key}: file '{name}' not found (looked for {where})"
        zones = len(horizons["surfaces"]) - 1
        layers = grid.get("layers")
        if kind in ("cornerpoint", "pebi") and isinstance(layers, list) and len(layers) != zones:
            return f"grid.layers: {len(layers)} values for {zones} zones (one per pair of horizons)"
    if horizons is not None and horizons["per_fault_block"]:
        if kind != "cornerpoint":
            return f"horizons.per_fault_block: supported for cornerpoint grids (grid.type is {kind})"
        if not data.get("faults"):
            return "horizons.per_fault_block: needs faults (their traces cut the area into blocks)"
        for k, fault in enumerate(data["faults"]):
            if fault["throw"] != 0:
                return (
                    f"faults[{k}].throw: with horizons.per_fault_block the offset is in the picks; "
                    f"fault '{fault['name']}' must not have a throw as well"
                )
    if kind == "deck" and not named_file(path, grid["file"]).is_file():
        return f"grid.file: '{grid['file']}' not found (looked for {named_file(path, grid['file'])})"
    problem = _features_outside(data, kind, horizons)
    if problem is not None:
        return problem
    rock = data.get("petrophysics")
    if rock is not None and kind != "deck" and "porosity" not in rock:
        return "petrophysics.porosity: required (only a deck grid's rock defaults to its deck's PORO)"
    n_layers = _num_layers(data)
    for prop in ("porosity", "permeability", "ntg"):
        spec = (data.get("petrophysics") or {}).get(prop) or {}
        if "layers" in spec and n_layers is not None and len(spec["layers"]) != n_layers:
            return f"petrophysics.{prop}.layers: {len(spec['layers'])} values for {n_layers} layers"
        if "deck" in spec and kind != "deck":
            return f"petrophysics.{prop}.deck: only deck grids have deck keywords"
    coarsen = data.get("coarsen")
    if coarsen is not None and coarsen["method"] == "uniform":
        want = len(grid["dims"]) if kind == "cartesian" else (None if kind == "tensor" else 3)
        if want is not None and len(coarsen["dims"]) != want:
            return f"coarsen.dims: {len(coarsen['dims'])} values for a grid with {want} axes"
    return _simulation_problem(data)


WELL_NAME_LENGTH = 8  # ECLIPSE's well names


def _simulation_problem(data: dict[str, Any]) -> str | None:
    """The `simulation` section against the rest of the case: rock, depth, wells, days."""
    sim = data.get("simulation")
    if sim is None:
        return None
    grid = data["grid"]
    if "petrophysics" not in data:
        return "simulation: needs petrophysics (the deck's pore volumes and permeabilities)"
    if (grid["type"] == "cartesian" and len(grid["dims"]) == 2) or (
        grid["type"] == "tensor" and "z" not in grid
    ):
        return "simulation: a 2-D grid has no depth (give the grid a third axis or layers)"
    days = sim["report_days"]
    for k in range(1, len(days)):
        if days[k] <= days[k - 1]:
            return (
                f"simulation.report_days[{k}]: {days[k]:g} does not come after {days[k - 1]:g} "
                "(days must increase)"
            )
    if sim["fluid"] == "water" and "owc" in sim.get("initial", {}):
        return "simulation.initial.owc: the water preset has no oil and no oil-water contact"
    case_wells = {w["name"]: w for w in data.get("wells", [])}
    seen: set[str] = set()
    for k, well in enumerate(sim.get("wells", [])):
        name = well["name"]
        if name not in case_wells:
            known = ", ".join(case_wells) or "none"
            return f"simulation.wells[{k}].name: '{name}' is not among the case's wells (wells: {known})"
        if name in seen:
            return f"simulation.wells[{k}].name: well '{name}' is listed twice"
        seen.add(name)
        if len(name) > WELL_NAME_LENGTH or not name.isascii() or any(c in name for c in " '/"):
            return (
                f"simulation.wells[{k}].name: '{name}': a simulated well's name has at most "
                f"{WELL_NAME_LENGTH} ASCII characters, without spaces, quotes or slashes"
            )
        if "point" not in case_wells[name]:
            return (
                f"simulation.wells[{k}].name: well '{name}' is a path; vertical wells (a point) are simulated"
            )
    return None


def _features_outside(data: dict[str, Any], kind: str, horizons: dict[str, Any] | None) -> str | None:
    """Faults must reach into the model's area and wells lie inside it."""
    import shapely

    area = None
    if kind == "pebi":
        domain = data["grid"]["domain"]
        if isinstance(domain, dict):
            x0, y0, x1, y1 = domain["rectangle"]
            if not (x1 > x0 and y1 > y0):
                return "grid.domain.rectangle: needs xmin < xmax and ymin < ymax"
            area = shapely.box(x0, y0, x1, y1)
        else:
            area = shapely.Polygon(domain)
            if not area.is_valid or area.area <= 0:
                return "grid.domain: the polygon is not simple (its sides cross) or has no area"
        if horizons is not None:
            (hx0, hx1), (hy0, hy1) = (_axis_range(horizons["lattice"][a]) for a in ("x", "y"))
            if not shapely.box(hx0, hy0, hx1, hy1).buffer(1e-9 * max(hx1 - hx0, hy1 - hy0)).covers(area):
                return (
                    f"grid.domain: reaches beyond the horizons' lattice (x in [{hx0:g}, {hx1:g}], "
                    f"y in [{hy0:g}, {hy1:g}])"
                )
    elif kind == "cornerpoint" and horizons is not None:
        (hx0, hx1), (hy0, hy1) = (_axis_range(horizons["lattice"][a]) for a in ("x", "y"))
        area = shapely.box(hx0, hy0, hx1, hy1)
    elif kind == "cartesian":
        spec = data["grid"]
        dims = spec["dims"]
        lengths = spec.get("lengths", [float(d) for d in dims])
        x0, y0 = (spec.get("origin") or [0.0, 0.0])[:2]
        area = shapely.box(x0, y0, x0 + lengths[0], y0 + lengths[1])
    elif kind == "tensor":
        (x0, x1), (y0, y1) = (_axis_range(data["grid"][a]) for a in ("x", "y"))
        area = shapely.box(x0, y0, x1, y1)
    if area is None:
        return None
    for k, fault in enumerate(data.get("faults", [])):
        if not shapely.LineString(fault["trace"]).intersects(area):
            return f"faults[{k}].trace: fault '{fault['name']}' lies entirely outside the domain"
    for k, well in enumerate(data.get("wells", [])):
        points = [well["point"]] if "point" in well else well["path"]
        for point in points:
            if not area.contains(shapely.Point(point)):
                key = "point" if "point" in well else "path"
                at = f"({point[0]:g}, {point[1]:g})"
                return f"wells[{k}].{key}: well '{well['name']}' at {at} lies outside the domain"
    return None
