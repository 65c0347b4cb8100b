"""What the schema cannot say about a case: its keys against each other, its names, traces and
values, and the files it names. Each check returns ``"key: message"`` (the key as the case file
spells it, e.g. ``wells[3].name``) or None; :func:`gridlib.config.check_case_data` prefixes the
case file."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..io.grdecl.dimens import deck_dimensions
from ..reproducible import log as _reproducible_log
from .files import case_deck_keywords, fault_plan_trace, fault_sticks, named_file, pebi_outline
from .values import yaml_number
from .well_paths import deviated_wells_problem, is_deviated, well_paths


def _log(x: float) -> float:
    """The natural logarithm, the same on every machine (a limit must not depend on the libm)."""
    return float(_reproducible_log(x))


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
        return int(sum(layers)) if isinstance(layers, list) else int(layers) * zones
    if kind == "layered":
        lay = grid["layers"]
        return len(lay["thickness"]) if "thickness" in lay else int(lay["num_layers"])
    if kind == "cartesian" and len(grid["dims"]) == 3:
        return int(grid["dims"][2])
    return None


def _structure_problem(data: dict[str, Any], path: Path) -> str | None:
    """What the schema cannot say: references between keys, files, faults and wells in the domain.

    Checked when the case is loaded (so the workflow stops before any job runs
    and leaves nothing behind); returns "key: message" or None. The simulation section is
    checked by :func:`simulation_problem`, once a deck grid's implied rock is known.
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
    for keyword, name in (grid.get("parameters") or {}).items() if kind == "deck" else ():
        if not named_file(path, name).is_file():
            return f"grid.parameters.{keyword}: '{name}' not found (looked for {named_file(path, name)})"
    problem = _features_outside(data, path, kind, horizons)
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
    return None


WELL_NAME_LENGTH = 8  # ECLIPSE's well names


def simulation_problem(data: dict[str, Any]) -> str | None:
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
        case_well = case_wells[name]
        if "point" not in case_well and not TRAJECTORY_KEYS & case_well.keys():
            return (
                f"simulation.wells[{k}].name: well '{name}' is a plan-view path (it refines a pebi grid); "
                "simulated wells are vertical at a point or have a trajectory or survey"
            )
        given = sorted(key for key in ("radius", "skin") if key in well)
        if given and "point" not in case_well:
            at = list(case_wells).index(name)
            return (
                f"simulation.wells[{k}].{given[0]}: well '{name}' has a trajectory: its radius and skin "
                f"are the case well's (wells[{at}], used for the factors in wells.nc)"
            )
    return None


TRAJECTORY_KEYS = {"trajectory", "survey"}  # a case well's keys that give it a path in depth


def _features_outside(
    data: dict[str, Any], path: Path, kind: str, horizons: dict[str, Any] | None
) -> str | None:
    """Faults must reach into the model's area (a sticks fault: the polyline of its sticks'
    shallowest points) and wells lie inside it."""
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
        if not shapely.LineString(fault_plan_trace(path, fault)).intersects(area):
            key = "trace" if "trace" in fault else "sticks"
            return f"faults[{k}].{key}: fault '{fault['name']}' lies entirely outside the domain"
    for k, well in enumerate(data.get("wells", [])):
        if is_deviated(well):
            problem = _deviated_outside(path, well, f"wells[{k}]", area)
            if problem is not None:
                return problem
            continue
        points = [well["point"]] if "point" in well else well["path"]
        for point in points:
            if not area.contains(shapely.Point(point)):
                key = "point" if "point" in well else "path"
                at = f"({point[0]:g}, {point[1]:g})"
                return f"wells[{k}].{key}: well '{well['name']}' at {at} lies outside the domain"
    return None


def _deviated_outside(path: Path, well: dict[str, Any], key: str, area: Any) -> str | None:
    """A trajectory or survey well none of whose paths comes into the model's ``area`` in plan
    view (a well whose paths cannot be read is left to :func:`deviated_wells_problem`, which
    runs next and names the problem)."""
    import shapely

    try:
        paths = well_paths(path, well, key).paths
    except InputError:
        return None
    plan = shapely.MultiPoint(np.concatenate([p.xyz[:, :2] for p in paths]))
    lines = [shapely.LineString(p.xyz[:, :2]) for p in paths]
    if any(line.intersects(area) for line in lines) or plan.intersects(area):
        return None
    given = "trajectory" if "trajectory" in well else "survey"
    return f"{key}.{given}: well '{well['name']}' lies entirely outside the domain (in plan view)"


def case_problem(data: dict[str, Any], path: Path) -> str | None:
    """The first problem of a validated case (defaults filled in) that the schema cannot see:
    names given twice, broken traces, reversed ranges, the keys against each other and the
    files they name, trajectory and survey wells (:mod:`gridlib.config.well_paths`), rock
    values, coarse blocks against the grid, PEBI point wells' rings and fault_side."""
    for check in (_names_problem, _traces_problem, _ranges_problem, _section_problem):
        problem = check(data)
        if problem is not None:
            return problem
    return (
        _fault_surfaces_problem(data, path)
        or _structure_problem(data, path)
        or deviated_wells_problem(data, path)
        or _rock_values_problem(data)
        or _coarsen_problem(data, path)
        or _pebi_wells_problem(data, path)
    )


HEXAHEDRAL_GRIDS = ("cartesian", "tensor", "cornerpoint", "deck")  # grids of corner-point hexahedra


def qc_problem(data: dict[str, Any]) -> str | None:
    """Each rule of ``qc`` (checked once a deck grid's implied rock is known) names a measure
    of :data:`gridlib.quality.MEASURES` the case's grid
    has: ``k_orientation_error`` needs rock, xtgeo's hexahedral set a grid of hexahedra
    (3-D cartesian, tensor, cornerpoint, deck; not pebi or layered, whose cells are prisms)."""
    from ..quality import MEASURES

    known = {m.name: m for m in MEASURES}
    kind = data["grid"]["type"]
    for k, rule in enumerate(data.get("qc", [])):
        name = rule["quantity"]
        measure = known.get(name)
        if measure is None:
            return f"qc[{k}].quantity: unknown measure '{name}'; the measures are {', '.join(known)}"
        if name == "k_orientation_error" and "petrophysics" not in data:
            return f"qc[{k}].quantity: {name} needs the case's permeability (a petrophysics section)"
        flat = (kind == "cartesian" and len(data["grid"]["dims"]) == 2) or (
            kind == "tensor" and "z" not in data["grid"]
        )
        if measure.hexahedral_only and flat:
            return f"qc[{k}].quantity: {name} is defined on corner-point hexahedra, not on a 2-D grid's cells"
        if measure.hexahedral_only and kind not in HEXAHEDRAL_GRIDS:
            return (
                f"qc[{k}].quantity: {name} is defined on corner-point hexahedra only "
                f"({', '.join(HEXAHEDRAL_GRIDS)} grids), not on the prisms of a {kind} grid"
            )
    return None


def _section_problem(data: dict[str, Any]) -> str | None:
    """``pictures.section``: a 3-D grid's (a 2-D grid has no depth to cut), no point repeated
    by the next (a segment of no length has no plane)."""
    points = data.get("pictures", {}).get("section")
    if points is None:
        return None
    grid = data["grid"]
    planar = (grid["type"] == "cartesian" and len(grid["dims"]) == 2) or (
        grid["type"] == "tensor" and "z" not in grid
    )
    if planar:
        return "pictures.section: a 2-D grid has no cross-section (its plan view shows it)"
    for i in range(1, len(points)):
        if list(points[i]) == list(points[i - 1]):
            at = ", ".join(yaml_number(v) for v in points[i])
            return f"pictures.section[{i}]: ({at}) repeats the point before it; give each point once"
    return None


def _names_problem(data: dict[str, Any]) -> str | None:
    """Wells, faults and horizons are named once each: the deck's WELSPECS and FAULTS, and a
    well's rings, take them by name (the second INJ would silently win)."""
    lists = (("wells", data.get("wells", [])), ("faults", data.get("faults", [])))
    horizons = data.get("horizons")
    if horizons is not None:
        lists += (("horizons.surfaces", horizons["surfaces"]),)
    for key, items in lists:
        first: dict[str, int] = {}
        for k, item in enumerate(items):
            name = item["name"]
            if name in first:
                return f"{key}[{k}].name: '{name}' is also {key}[{first[name]}]; give each a name of its own"
            first[name] = k
    return None


def _traces_problem(data: dict[str, Any]) -> str | None:
    """Fault traces and well paths: no point repeated by the next, some length, no crossing
    of itself (a fault's two sides would be undefined)."""
    import shapely

    lines = [
        (f"faults[{k}]", f"fault '{f['name']}'", f["trace"])
        for k, f in enumerate(data.get("faults", []))
        if "trace" in f
    ]
    lines += [
        (f"wells[{k}]", f"well '{w['name']}'", w["path"])
        for k, w in enumerate(data.get("wells", []))
        if "path" in w
    ]
    for key, what, points in lines:
        field = "trace" if key.startswith("faults") else "path"
        for i in range(1, len(points)):
            if list(points[i]) == list(points[i - 1]):
                at = ", ".join(yaml_number(v) for v in points[i])
                return f"{key}.{field}[{i}]: ({at}) repeats the point before it; give each point once"
        if not shapely.LineString(points).is_simple:
            return f"{key}.{field}: {what}'s {field} crosses itself"
    return None


def _fault_surfaces_problem(data: dict[str, Any], path: Path) -> str | None:
    """Inclined faults: ``dip`` goes with a trace and ``sticks_format`` with sticks; a sticks
    file exists, reads and makes a surface (no sticks that coincide or cross); a ``side`` given
    for sticks is the side they dip towards (the hanging wall of any fault is the side above it);
    picks per fault block need traces."""
    horizons = data.get("horizons")
    for k, fault in enumerate(data.get("faults", [])):
        name = fault["name"]
        if "sticks" not in fault:
            if "sticks_format" in fault:
                return f"faults[{k}].sticks_format: fault '{name}' is given by its trace, not by sticks"
            continue
        if "dip" in fault:
            return f"faults[{k}].dip: fault '{name}' is given by sticks, which give its dip; remove dip"
        if horizons is not None and horizons["per_fault_block"]:
            return (
                f"faults[{k}].sticks: fault '{name}': horizons.per_fault_block cuts the area into "
                "blocks by fault traces; give the fault by its trace (and dip)"
            )
        file = named_file(path, fault["sticks"])
        if not file.is_file():
            return f"faults[{k}].sticks: file '{fault['sticks']}' not found (looked for {file})"
        try:
            surface = fault_sticks(path, fault).surface
            dips = None if surface.is_vertical else surface.dip_side()
        except InputError as exc:
            return f"faults[{k}].sticks: {exc}"
        side = fault.get("side")
        if dips is None and side is None:
            return f"faults[{k}].side: fault '{name}': its sticks are vertical; give the hanging wall's side"
        if dips is not None and side not in (None, dips):
            return (
                f"faults[{k}].side: fault '{name}' dips to the {dips} of its sticks walked from the "
                f"first, so its hanging wall (the side above the fault) is on the {dips}, not the {side}"
            )
    return None


def _increasing(values: list[float]) -> int | None:
    """The first index whose value does not exceed the one before it, or None."""
    return next((i for i in range(1, len(values)) if not values[i] > values[i - 1]), None)


def _axis_problem(spec: Any, key: str) -> str | None:
    if isinstance(spec, dict):
        if not spec["stop"] > spec["start"]:
            start, stop = yaml_number(spec["start"]), yaml_number(spec["stop"])
            return f"{key}: start {start} is not below stop {stop} (node coordinates increase)"
        return None
    i = _increasing(spec)
    if i is not None:
        value, before = yaml_number(spec[i]), yaml_number(spec[i - 1])
        return f"{key}[{i}]: {value} does not exceed {before} (node coordinates increase)"
    return None


def _ranges_problem(data: dict[str, Any]) -> str | None:
    """Every low/high pair the case gives is ordered: axes, boxes, rings, radial radii."""
    grid = data["grid"]
    axes = []
    if grid["type"] == "tensor":
        axes += [(grid[a], f"grid.{a}") for a in ("x", "y", "z") if a in grid]
    horizons = data.get("horizons")
    if horizons is not None:
        axes += [(horizons["lattice"][a], f"horizons.lattice.{a}") for a in ("x", "y")]
    for spec, key in axes:
        problem = _axis_problem(spec, key)
        if problem is not None:
            return problem
    box = (data.get("domain") or {}).get("box")
    if box is not None:
        for a, (lo, hi) in enumerate(zip(box["min"], box["max"], strict=False)):
            if lo > hi:
                return (
                    f"domain.box.min[{a}]: {yaml_number(lo)} is above domain.box.max[{a}] {yaml_number(hi)}"
                )
    for k, well in enumerate(data.get("wells", [])):
        rings = well.get("rings") or {}
        given = [key for key in ("outer", "growth", "count") if key in rings]
        if len(given) == 3:
            return f"wells[{k}].rings: give two of outer, growth and count, not all three"
        if rings and not ("outer" in rings or len(given) == 2 or rings.get("count") == 1):
            return f"wells[{k}].rings: give the outer radius, or the growth and the number of rings (count)"
        if "outer" in rings and rings["outer"] < rings["inner"]:
            return (
                f"wells[{k}].rings.outer: {yaml_number(rings['outer'])} is below rings.inner "
                f"{yaml_number(rings['inner'])} (radii of the last and first ring)"
            )
    problem = _domain_problem(data)
    if problem is not None:
        return problem
    if grid["type"] == "layered":
        sites = grid["areal"]["sites"]
        problem = _sites_problem(sites.get("xy"))
        if problem is not None:
            return problem
        radii = sites.get("radii")
        if isinstance(radii, dict) and radii["log_stop"] < radii["log_start"]:
            return (
                "grid.areal.sites.radii.log_stop: below log_start (radii = exp(log_start:log_step:log_stop))"
            )
        if isinstance(radii, list) and _increasing(radii) is not None:
            i = _increasing(radii)
            return (
                f"grid.areal.sites.radii[{i}]: {yaml_number(radii[i])} does not exceed the radius before it"
            )
    return None


def _sites_problem(xy: list[list[float]] | None) -> str | None:
    """Explicit sites of a layered grid: each given once, not all on one line."""
    import shapely

    if xy is None:
        return None
    first: dict[tuple[float, ...], int] = {}
    for k, point in enumerate(xy):
        at = first.setdefault(tuple(point), k)
        if at != k:
            shown = ", ".join(yaml_number(v) for v in point)
            return f"grid.areal.sites.xy[{k}]: ({shown}) is also xy[{at}]; give each site once"
    if shapely.MultiPoint(xy).convex_hull.area == 0:
        return "grid.areal.sites.xy: every site lies on one line: their triangulation has no triangle"
    return None


def _grid_box(grid: dict[str, Any]) -> tuple[list[float], list[float]] | None:
    """The (min, max) corners of a cartesian or tensor grid's box (m)."""
    if grid["type"] == "cartesian":
        dims = grid["dims"]
        lengths = grid.get("lengths", [float(d) for d in dims])
        origin = list(grid.get("origin") or [0.0] * len(dims))
        origin += [0.0] * (len(dims) - len(origin))
        return origin[: len(dims)], [o + n for o, n in zip(origin, lengths, strict=False)]
    if grid["type"] == "tensor":
        ranges = [_axis_range(grid[a]) for a in ("x", "y", "z") if a in grid]
        return [lo for lo, _ in ranges], [hi for _, hi in ranges]
    return None


def _domain_problem(data: dict[str, Any]) -> str | None:
    """A fictitious domain (box or ellipsoid) that does not reach the grid's box keeps no cell."""
    domain = data.get("domain")
    box = _grid_box(data["grid"])
    if not domain or box is None:
        return None
    for key, shape in domain.items():
        if key == "box":
            lo, hi = shape["min"], shape["max"]
        else:
            lo = [c - r for c, r in zip(shape["center"], shape["semi_axes"], strict=False)]
            hi = [c + r for c, r in zip(shape["center"], shape["semi_axes"], strict=False)]
        for a in range(min(len(lo), len(box[0]))):
            if hi[a] < box[0][a] or lo[a] > box[1][a]:
                span = f"[{yaml_number(box[0][a])}, {yaml_number(box[1][a])}]"
                axis = "xyz"[a]
                return (
                    f"domain.{key}: lies outside the grid along {axis} (the grid spans {span} m): "
                    "no cell is kept"
                )
    return None


FRACTION_PROPERTIES = ("porosity", "ntg")  # fractions: in [0, 1]
PERMEABILITY_SIGMAS = 8  # a field's extreme values, in standard deviations (1e-15 per cell)
LOG_FLOAT_MAX = _log(1e300)  # with room for the upscaling's sums


def _rock_values_problem(data: dict[str, Any]) -> str | None:
    """Porosity and net-to-gross are fractions in [0, 1], permeability (mD) is not negative, a
    lognormal field's median is positive, and every ``bounds`` is [low, high] with low <= high:
    what the petrophysics stage would refuse, refused before it runs."""
    rock = data.get("petrophysics")
    if rock is None:
        return None
    for prop in ("porosity", "permeability", "ntg"):
        spec = rock.get(prop)
        if spec is None or "carman_kozeny" in spec:
            continue
        base = f"petrophysics.{prop}"
        values = []
        if "constant" in spec:
            values.append((f"{base}.constant", spec["constant"]))
        values += [(f"{base}.layers[{k}]", v) for k, v in enumerate(spec.get("layers", []))]
        field = spec.get("field") or {}
        if "bounds" in field:
            lo, hi = field["bounds"]
            if lo > hi:
                return (
                    f"{base}.field.bounds: [{yaml_number(lo)}, {yaml_number(hi)}] is reversed "
                    "(give [low, high])"
                )
            values += [(f"{base}.field.bounds[{k}]", v) for k, v in enumerate(field["bounds"])]
        if prop == "permeability" and field.get("mean", 1) > 0:
            median, std = float(field.get("mean", 100.0)), float(field.get("std", 0.0))
            if _log(median) + PERMEABILITY_SIGMAS * std > LOG_FLOAT_MAX:
                return (
                    f"{base}.field.std: {yaml_number(std)}: median x exp({PERMEABILITY_SIGMAS} std) "
                    "is beyond any float (std is of ln k: 1 is a factor e)"
                )
        if "mean" in field:
            if prop == "permeability" and not field["mean"] > 0:
                return (
                    f"{base}.field.mean: {yaml_number(field['mean'])}: the median permeability "
                    "(mD) of the lognormal field must be positive"
                )
            values.append((f"{base}.field.mean", field["mean"]))
        for key, value in values:
            problem = _rock_value_problem(prop, key, value)
            if problem is not None:
                return problem
        problem = _no_flow_problem(data, prop, spec)
        if problem is not None:
            return problem
    return None


POSITIVE_UPSCALING = ("harmonic", "geometric", "harmonic-arithmetic")  # need every k > 0


def _no_flow_problem(data: dict[str, Any], prop: str, spec: dict[str, Any]) -> str | None:
    """A porosity or permeability of 0 in every cell (nothing to flow through), or a zero
    permeability where the coarse grid's upscaling divides by it."""
    base = f"petrophysics.{prop}"
    if prop in ("porosity", "permeability") and spec.get("constant") == 0:
        return f"{base}.constant: 0 in every cell: no pore volume or flow anywhere"
    if prop == "porosity" and spec.get("layers") and not any(spec["layers"]):
        return f"{base}.layers: 0 in every layer: no pore volume anywhere"
    coarsen = data.get("coarsen")
    if prop == "permeability" and coarsen is not None and coarsen["permeability"] in POSITIVE_UPSCALING:
        zeros = [k for k, v in enumerate(spec.get("layers", [])) if v == 0]
        if zeros:
            return (
                f"{base}.layers[{zeros[0]}]: 0: coarsen.permeability {coarsen['permeability']} "
                "averaging needs positive permeabilities (use arithmetic, or a small value)"
            )
    return None


def _rock_value_problem(prop: str, key: str, value: float) -> str | None:
    shown = yaml_number(value)
    if value < 0:
        unit = "mD, " if prop == "permeability" else ""
        return f"{key}: {shown} is negative ({unit}{prop} is at least 0)"
    if prop in FRACTION_PROPERTIES and value > 1:
        hint = f"; give {yaml_number(value / 100)} for {shown} %" if value <= 100 else ""
        return f"{key}: {shown} is above 1 ({prop} is a fraction from 0 to 1{hint})"
    return None


def grid_cells_per_axis(data: dict[str, Any], path: Path) -> tuple[tuple[int, str], ...] | None:
    """The logical cells per axis (i, j[, k]) of the case's grid where the case (or its deck's
    DIMENS/SPECGRID) tells them, each with the key that gives it; None for PEBI and layered
    grids (areal cells have no logical axes) and decks whose dimensions are not found."""
    grid = data["grid"]
    kind = grid["type"]
    if kind == "cartesian":
        return tuple((int(n), f"grid.dims[{a}]") for a, n in enumerate(grid["dims"]))
    if kind == "tensor":
        return tuple((_axis_cells(grid[a]), f"grid.{a}") for a in ("x", "y", "z") if a in grid)
    if kind == "cornerpoint":
        layers = _num_layers(data) if "horizons" in data else None
        if layers is None:
            return None
        return (
            (int(grid["dims"][0]), "grid.dims[0]"),
            (int(grid["dims"][1]), "grid.dims[1]"),
            (layers, "grid.layers"),
        )
    if kind == "deck":
        deck = named_file(path, grid["file"])
        dims = deck_dimensions(deck) if deck.is_file() else None
        if dims is None:
            return None
        return tuple(
            (n, f"grid.file ({deck.name}: {word})") for n, word in zip(dims, ("NX", "NY", "NZ"), strict=True)
        )
    return None


def _axis_cells(spec: Any) -> int:
    return int(spec["num"]) - 1 if isinstance(spec, dict) else len(spec) - 1


def _coarsen_problem(data: dict[str, Any], path: Path) -> str | None:
    """Uniform blocks: at most one per cell along each logical axis (and per layer); METIS
    blocks: at most one per cell where the case gives an upper bound of its cells."""
    coarsen = data.get("coarsen")
    if coarsen is None:
        return None
    if coarsen["method"] == "metis":
        cells = grid_cells_per_axis(data, path)
        if cells is not None and coarsen["blocks"] > math.prod(n for n, _ in cells):
            total = math.prod(n for n, _ in cells)
            blocks = coarsen["blocks"]
            return f"coarsen.blocks: {blocks} blocks for at most {total} cells (one block per cell at most)"
        return None
    dims = coarsen["dims"]
    grid = data["grid"]
    if grid["type"] in ("pebi", "layered"):
        layers = _num_layers(data) if grid["type"] == "layered" or "horizons" in data else None
        if len(dims) != 3:
            return f"coarsen.dims: {len(dims)} values: a {grid['type']} grid's blocks are [x, y, layers]"
        cells = None if layers is None else ((None, ""), (None, ""), (layers, "grid.layers"))
    else:
        cells = grid_cells_per_axis(data, path)
    if cells is None:
        return None
    if len(dims) != len(cells):
        return f"coarsen.dims: {len(dims)} values for a grid with {len(cells)} axes"
    for a, (blocks, (n, key)) in enumerate(zip(dims, cells, strict=True)):
        if n is not None and blocks > n:
            return (
                f"coarsen.dims[{a}]: {blocks} blocks along {'ijk'[a]}, but the grid has {n} cells "
                f"there ({key}); give at most {n}"
            )
    return None


# Of the PEBI domain's extent (the larger side of its bounding box): a well's first ring this
# small merges with the well's site. The builder fails from about 2e-6 of the extent whatever
# the cell size (measured: a first ring of 1e-3 m in a 1 km domain fails, 2e-3 m builds): the
# check keeps a margin of five.
PEBI_TOLERANCE = 1e-5


def _pebi_wells_problem(data: dict[str, Any], path: Path) -> str | None:
    """A PEBI grid puts a cell centre (the well's site) at a point well, with its rings around
    it: rings must neither merge with the site nor grow beyond the domain. A point well on a
    fault is fine (a fault cell is its cell, on its ``fault_side``); only point wells have one."""
    grid = data["grid"]
    if grid["type"] != "pebi":
        return None
    domain = grid["domain"]
    area = pebi_outline(domain)
    x0, y0, x1, y1 = area.bounds
    extent = max(x1 - x0, y1 - y0)
    tolerance = PEBI_TOLERANCE * extent
    for k, well in enumerate(data.get("wells", [])):
        if "point" not in well:
            if "fault_side" in well:
                return (
                    f"wells[{k}].fault_side: well '{well['name']}' is not a point well; fault_side "
                    "chooses the fault cell of a vertical well (point) on a fault"
                )
            continue
        rings = well.get("rings") or {}
        if rings and rings["inner"] <= tolerance:
            return (
                f"wells[{k}].rings.inner: {yaml_number(rings['inner'])} m is within {tolerance:.3g} m "
                f"({PEBI_TOLERANCE:g} of the domain's extent): the first ring would merge with the "
                "well's site"
            )
        if "growth" in rings and "count" in rings:
            log_outer = _log(rings["inner"]) + (rings["count"] - 1) * _log(rings["growth"])
            if log_outer > _log(extent):
                return (
                    f"wells[{k}].rings: inner x growth^(count - 1) reaches beyond the domain's extent "
                    f"({extent:g} m); give fewer rings or a smaller growth"
                )
    return None


def rock_problem(data: dict[str, Any], path: Path) -> str | None:
    """A property taken from a deck keyword (``porosity: {deck: PORO}``) the deck gives."""
    grid = data["grid"]
    rock = data.get("petrophysics") or {}
    if grid["type"] != "deck":
        return None
    wanted = [
        (prop, spec["deck"]) for prop, spec in rock.items() if isinstance(spec, dict) and "deck" in spec
    ]
    if not wanted:
        return None
    deck = named_file(path, grid["file"])
    given = case_deck_keywords(path, grid)
    for prop, keyword in wanted:
        if keyword.upper() not in given:
            have = ", ".join(sorted(given)) or "no cell keyword"
            return f"petrophysics.{prop}.deck: {deck.name} gives no {keyword.upper()} (it gives {have})"
    return None
