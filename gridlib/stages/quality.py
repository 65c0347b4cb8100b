"""Stage ``quality``: the cell-quality measures of a case's grid, and the case's ``qc:`` rules.

Per cell, every measure of :data:`gridlib.quality.MEASURES` (:func:`gridlib.quality.cell_quality`):
xtgeo's ``get_gridquality_properties`` set on the cells that are corner-point hexahedra (taken,
for corner-point and deck cases, from the case's ``grid.grdecl`` as xtgeo takes them: each
cell's own corners), and for every grid the face-orientation errors of a two-point flux, the
aspect ratio and the faces' non-planarity. The orientation errors use the cell centres of the
transmissibility stage (a PEBI grid's generating sites at the centroid depth, else the
centroids: :func:`gridlib.stages.transmissibility.cell_centres`), as the export's
``orientation_*`` figures do; ``k_orientation_error`` needs the case's permeability.

Writes ``quality.nc`` (:mod:`gridlib.io.quality_file`) and ``{case}_quality.png``: a histogram
of each measure that varies over the grid, with the case's qc limits drawn on it
(:mod:`gridlib.io.quality_histograms`).

The case's ``qc:`` rules (:func:`check_rules`), each ``{quantity, max | min, action, fraction}``:
the cells whose ``quantity`` lies above ``max`` (below ``min``) break the rule; more than
``fraction`` of the cells where the measure is defined (default 0: any cell) trigger it. A
triggered ``warn`` rule logs one warning naming the rule, its limit, how many cells and the first
of them ((i, j, k), 1-based, or cell numbers on grids without logical indices); a triggered
``fail`` rule stops the stage with that message as an InputError, before anything is written.
Every rule's result goes to ``quality.nc``'s ``qc`` attribute, and from there to
``summary.json``.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..cell_names import MAX_NAMED, cell_names, ijk
from ..config import Case
from ..errors import InputError
from ..grid import Grid
from ..io.grdecl import read_grdecl
from ..io.quality_file import measure_units, write_quality
from ..io.quality_histograms import plot_quality
from ..quality import MEASURE, cell_quality
from .common import log
from .inputs import read_grid_inputs
from .transmissibility import cell_centres


@dataclass(frozen=True)
class RuleResult:
    """One ``qc:`` rule checked: the rule (its position in ``qc`` and its keys), the cells
    that break it (0-based, in cell order), how many cells have the measure defined, and
    whether it is triggered (more than ``fraction`` of those cells break it)."""

    index: int
    rule: Mapping[str, Any]
    cells: np.ndarray
    evaluated: int

    @property
    def bound(self) -> str:
        """``max`` or ``min``: which side of the limit is bad."""
        return "max" if "max" in self.rule else "min"

    @property
    def limit(self) -> float:
        return float(self.rule[self.bound])

    @property
    def fraction(self) -> float:
        return float(self.rule.get("fraction", 0.0))

    @property
    def triggered(self) -> bool:
        return self.evaluated > 0 and self.cells.size > self.fraction * self.evaluated

    @property
    def status(self) -> str:
        """``pass``, ``warn``, ``fail`` or ``undefined`` (the measure is defined on no cell)."""
        if self.evaluated == 0:
            return "undefined"
        return str(self.rule["action"]) if self.triggered else "pass"


def check_rules(values: Mapping[str, np.ndarray], rules: Sequence[Mapping[str, Any]]) -> list[RuleResult]:
    """Every rule of a case's ``qc:`` section checked against the measures ``values`` (name ->
    one value per cell; NaN where a measure is not defined, which breaks no rule). A rule on a
    measure ``values`` lacks is defined on no cell."""
    results = []
    for k, rule in enumerate(rules):
        v = values.get(rule["quantity"])
        if v is None:
            results.append(RuleResult(k, rule, np.zeros(0, dtype=np.int64), 0))
            continue
        limit = float(rule["max"] if "max" in rule else rule["min"])
        bad = v > limit if "max" in rule else v < limit  # NaN compares False: breaks nothing
        results.append(RuleResult(k, rule, np.flatnonzero(bad), int(np.count_nonzero(~np.isnan(v)))))
    return results


def rule_message(case: Case, grid: Grid, result: RuleResult) -> str:
    """What a triggered rule says: the case file, the rule, its limit, how many cells break it
    (of how many where the measure is defined, and how many it allows) and the first of them.

    E.g. ``config/cases/x.yaml: qc[1]: maxangle_sides above max 60 degree (fail) in 12 of 400
    cells (3 %): (1, 2, 1), (2, 2, 1), (3, 2, 1), (1, 3, 1), (2, 3, 1) and 7 more``."""
    rule = result.rule
    unit = measure_units(MEASURE[rule["quantity"]])
    limit = f"{result.limit:g}" + ("" if unit in (None, "1") else f" {unit}")  # 60 degree; a ratio bare
    side = "above" if result.bound == "max" else "below"
    share = f"{_percent(result.cells.size / result.evaluated)} %"
    if result.fraction > 0:
        share += f", more than the {_percent(result.fraction)} % allowed"
    named = cell_names(result.cells, grid.cells.index_map, grid.cart_dims)
    return (
        f"{case.path}: qc[{result.index}]: {rule['quantity']} {side} {result.bound} {limit} "
        f"({rule['action']}) in {result.cells.size:,d} of {result.evaluated:,d} cells ({share}): {named}"
    )


def _percent(share: float) -> str:
    return f"{100.0 * share:.3g}"


def rule_summary(grid: Grid, result: RuleResult) -> dict[str, Any]:
    """A rule's entry of ``summary.json``'s ``qc``: the rule, its status, the number of cells
    that break it and of those with the measure defined, and the first ones ((i, j, k),
    1-based, or cell numbers)."""
    shown = result.cells[:MAX_NAMED]
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        first = ijk(grid.cells.index_map[shown], grid.cart_dims).tolist()
    else:
        first = shown.tolist()
    return {
        "rule": f"qc[{result.index}]",
        "quantity": str(result.rule["quantity"]),
        result.bound: result.limit,
        "action": str(result.rule["action"]),
        "fraction": result.fraction,
        "status": result.status,
        "cells": int(result.cells.size),
        "evaluated": result.evaluated,
        "first_cells": first,
    }


def stage_quality(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    quality: str | os.PathLike,
    quality_png: str | os.PathLike | None = None,
    petrophysics: str | os.PathLike | None = None,
    grdecl: str | os.PathLike | None = None,
) -> None:
    """The quality measures of the grid of ``grid`` and ``geometry`` (``k_orientation_error``
    with the permeability of ``petrophysics``; the hexahedral set from ``grdecl``, a
    corner-point or deck case's ``grid.grdecl``, where given), the case's qc rules checked; write
    ``quality`` (``quality.nc``) and ``quality_png`` (``{case}_quality.png``)."""
    inputs = read_grid_inputs(grid, geometry, petrophysics)
    stored, geo, rock, system = inputs.stored, inputs.geometry, inputs.rock, inputs.units
    mesh = stored.grid
    perm = None
    if rock is not None:
        perm = np.column_stack([rock["permx"], rock["permy"], rock["permz"]])[:, : mesh.dim]
    centres, _ = cell_centres(case, grid, stored, geo)
    deck = read_grdecl(grdecl) if grdecl is not None else None
    values = cell_quality(mesh, geo, perm=perm, centres=centres, deck=deck)
    rules = case.data.get("qc", [])
    results = check_rules(values, rules)
    for r in results:  # a failure stops the stage before anything is written
        if r.triggered and r.rule["action"] == "fail":
            raise InputError(rule_message(case, mesh, r))
    for r in results:
        if r.triggered:
            log.warning("%s", rule_message(case, mesh, r))
        elif r.status == "undefined":
            name = r.rule["quantity"]
            log.info("note: %s: qc[%d]: %s is defined on no cell of this grid", case.path, r.index, name)
    qc = [rule_summary(mesh, r) for r in results]
    write_quality(quality, values, {**case.provenance(), "unit_system": system.name}, qc)
    if quality_png is not None:
        plot_quality(quality_png, values, rules, f"{case.name}: {mesh.num_cells:,d} cells")
    log.info("wrote %s: %s", quality, _medians(values))


def _medians(values: Mapping[str, np.ndarray]) -> str:
    """The median of each measure (over the cells where it is defined), for the log."""
    parts = []
    for name, v in values.items():
        finite = v[np.isfinite(v)]
        if finite.size:
            unit = measure_units(MEASURE[name]) or ""
            parts.append(f"{name} median {np.median(finite):.4g} {unit}".rstrip())
    return ", ".join(parts)
