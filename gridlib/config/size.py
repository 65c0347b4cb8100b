"""How big a case's grid is and how much memory building it takes, known from the case alone.

The number of cells is exact for cartesian, tensor, layered and corner-point grids (a
corner-point grid's inactive cells count: they are built, then removed), read from the deck's
DIMENS or SPECGRID (:mod:`gridlib.io.grdecl.dimens`) for a deck, and estimated for a PEBI grid
(the domain's area over the lattice's cell area, plus well rings and fault and path sites, times
the layers). The peak memory of a case's heaviest stage is that number times the bytes per cell
measured for its grid type (``BYTES_PER_CELL``; the figures are in config/README.md). A case
above the limit (:func:`max_memory_bytes`) is refused when the workflow is parsed, before any
array is allocated.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ..io.grdecl.dimens import deck_dimensions
from ..memory import GIB, count_text, gib_text, machine_memory
from ..reproducible import log
from .files import fault_plan_trace, named_file, pebi_outline
from .well_paths import is_deviated, well_paths

# Peak resident memory of `gridlib build` (every stage in one process: its heaviest stage
# decides) per cell: the slope between two sizes (1e5 and 4e5 cells; PEBI 2.4e4 and 9.6e4) from
# /usr/bin/time -v, Python's start-up removed, rounded up; config/README.md gives the figures.
# Layered grids are extruded Voronoi grids as PEBI grids are: their figure is PEBI's.
BYTES_PER_CELL = {
    "cartesian": 1100,
    "tensor": 1200,
    "layered": 1700,
    "cornerpoint": 1200,
    "pebi": 1700,
    "deck": 500,
}
# The horizons stage, per lattice node and surface: measured as above with three dome surfaces
# on 1001^2 and 2001^2 nodes (0.46 and 0.70 GiB: 28 B per node and surface), rounded up.
BYTES_PER_LATTICE_NODE = 40


def max_memory_bytes(max_memory_gb: float | None = None) -> int:
    """The memory a case's stage may need: ``max_memory_gb`` GiB (the workflow's config key
    ``max_memory_gb``, e.g. for jobs that run on cluster nodes bigger than the machine that
    plans them), else this machine's physical memory."""
    if max_memory_gb is not None:
        return int(max_memory_gb * GIB)
    return physical_memory()


def physical_memory() -> int:
    """This machine's physical memory (bytes); no limit where the system does not say."""
    return machine_memory() or 2**62


def estimated_cells(data: dict[str, Any], path: Path) -> tuple[float, str] | None:
    """(number of cells, the key that sets it) of a validated case, or None where the case does
    not tell (a deck whose dimensions this scan cannot read). A float: a PEBI grid's estimate
    of a tiny ``cell_size`` can exceed any integer worth building."""
    grid = data["grid"]
    kind = grid["type"]
    if kind == "cartesian":
        return float(math.prod(grid["dims"])), "grid.dims"
    if kind == "tensor":
        counts = [_axis_cells(grid[a]) for a in ("x", "y", "z") if a in grid]
        return float(math.prod(counts)), "grid." + ", grid.".join(a for a in ("x", "y", "z") if a in grid)
    layers = _layers(data)
    if kind == "cornerpoint":
        return float(math.prod(grid["dims"])) * layers, "grid.dims"
    if kind == "layered":
        return _sites(grid["areal"]["sites"]) * layers, "grid.areal.sites"
    if kind == "pebi":
        columns, key = _pebi_columns(data, path)
        return columns * layers, key
    if kind == "deck":
        deck = named_file(path, grid["file"])
        dims = deck_dimensions(deck) if deck.is_file() else None
        return (float(math.prod(dims)), f"grid.file ({deck.name}: DIMENS/SPECGRID)") if dims else None
    return None


def _axis_cells(spec: Any) -> int:
    return int(spec["num"]) - 1 if isinstance(spec, dict) else len(spec) - 1


def _layers(data: dict[str, Any]) -> int:
    grid = data["grid"]
    if grid["type"] == "layered":
        layers = grid["layers"]
        return len(layers["thickness"]) if "thickness" in layers else int(layers["num_layers"])
    layers = grid.get("layers", 1)
    if isinstance(layers, list):
        return int(sum(layers))
    zones = len(data["horizons"]["surfaces"]) - 1 if "horizons" in data else 1
    return int(layers) * max(zones, 1)


def _sites(sites: dict[str, Any]) -> float:
    pattern = sites["pattern"]
    if pattern == "hexagonal":
        return 4.0 * sites["counts"][0] * sites["counts"][1]
    if pattern == "square":
        return float(sites["counts"][0] * sites["counts"][1])
    if pattern == "points":
        return float(len(sites["xy"]))
    radii = sites["radii"]
    if isinstance(radii, dict):
        rings = max((radii["log_stop"] - radii["log_start"]) / radii["log_step"] + 1, 1)
    else:
        rings = len(radii)
    return rings * sites["sectors"] + 1.0


def _pebi_columns(data: dict[str, Any], path: Path) -> tuple[float, str]:
    """Areal cells of a PEBI grid (the lattice's sites in the domain, each well's rings, the
    sites along faults and well paths, two rows per cell size of trace, a deviated well's three
    rows along its whole plan view, the padding rows) and the key that gives the most of them."""
    import shapely

    grid = data["grid"]
    domain = grid["domain"]
    area = pebi_outline(domain)
    size = float(grid["cell_size"])
    cell_area = size * size * (math.sqrt(3.0) / 2.0 if grid["pattern"] == "hexagonal" else 1.0)
    parts = {"grid.cell_size": _ratio(area.area, cell_area)}
    for k, fault in enumerate(data.get("faults", [])):
        key = f"faults[{k}].trace" if "trace" in fault else f"faults[{k}].sticks"
        parts[key] = _ratio(
            2.0 * shapely.LineString(fault_plan_trace(path, fault)).intersection(area).length, size
        )
    for k, well in enumerate(data.get("wells", [])):
        if "path" in well:
            spacing = float(well.get("spacing", size))
            parts[f"wells[{k}].spacing"] = _ratio(2.0 * shapely.LineString(well["path"]).length, spacing)
        elif is_deviated(well):  # its plan view, with a row of sites on either side
            spacing = float(well.get("spacing", size))
            plan = sum(shapely.LineString(p.xyz[:, :2]).length for p in well_paths(path, well, "").paths)
            parts[f"wells[{k}].spacing"] = _ratio(6.0 * plan, spacing)
        if well.get("rings") is not None:
            parts[f"wells[{k}].rings"] = _ring_sites(well["rings"], size)
    parts["grid.padding"] = float(grid.get("padding") or 0) * _ratio(area.length, size)
    return sum(parts.values()), max(parts, key=parts.__getitem__)


def _ratio(a: float, b: float) -> float:
    """a / b, infinite where it overflows (a tiny cell size)."""
    try:
        return a / b
    except ZeroDivisionError:
        return math.inf if a > 0 else 0.0


def _ring_sites(rings: dict[str, Any], size: float) -> float:
    """Sites of a point well's rings, as :class:`gridlib.voronoi.wells.Rings` places them."""
    inner = float(rings["inner"])
    outer = rings.get("outer")
    sectors = float(rings.get("sectors") or max(6.0, _ratio(2.0 * math.pi * float(outer or inner), size)))
    if "count" in rings:
        count = float(rings["count"])
    elif outer is not None:
        log_growth = float(log(rings["growth"])) if "growth" in rings else _ratio(2.0 * math.pi, sectors)
        count = _ratio(float(log(max(_ratio(float(outer), inner), 1.0))), log_growth) + 1.0
    else:
        count = 1.0
    return count * sectors


def size_problem(data: dict[str, Any], path: Path, limit: int) -> str | None:
    """``key: N cells need about X GiB in the heaviest stage; ...`` where the estimated peak
    memory of the case's heaviest stage exceeds ``limit`` bytes (:func:`max_memory_bytes`): the
    grid's cells, or the horizons' lattice nodes (the horizons stage), whichever needs more."""
    needs = []
    estimate = estimated_cells(data, path)
    if estimate is not None:
        cells, key = estimate
        needs.append(
            (
                cells * BYTES_PER_CELL[data["grid"]["type"]],
                f"{key}: {count_text(cells)} cells",
                "the heaviest stage",
            )
        )
    horizons = data.get("horizons")
    if horizons is not None:
        nodes = float(math.prod(_axis_nodes(horizons["lattice"][a]) for a in ("x", "y")))
        surfaces = len(horizons["surfaces"])
        what = f"horizons.lattice: {count_text(nodes)} nodes x {surfaces} surfaces"
        needs.append((nodes * surfaces * BYTES_PER_LATTICE_NODE, what, "the horizons stage"))
    if not needs:
        return None
    need, what, where = max(needs, key=lambda n: n[0])
    if need <= limit:
        return None
    machine = physical_memory()
    if limit == machine:
        allowed = f"this machine has {gib_text(machine)} (the config's max_memory_gb sets another limit)"
    else:
        allowed = (
            f"the limit is {gib_text(limit)} (config max_memory_gb; this machine has {gib_text(machine)})"
        )
    return f"{what} need about {gib_text(need)} in {where}; {allowed}"


def _axis_nodes(spec: Any) -> int:
    return int(spec["num"]) if isinstance(spec, dict) else len(spec)
