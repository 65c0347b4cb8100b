"""All of a case's stages in order, in one folder (what ``gridlib build`` runs)."""

from __future__ import annotations

import os
from pathlib import Path

from ..config import load_case
from .coarsen import stage_coarsen
from .common import artifact_paths
from .export import stage_export
from .flow_deck import stage_flow_deck
from .geometry import stage_geometry
from .grid import stage_grid
from .horizons import stage_horizons
from .petrophysics import stage_petrophysics
from .simulate import stage_simulate
from .transmissibility import stage_transmissibility


def case_outputs(name: str, folder: str | os.PathLike) -> dict[str, Path]:
    """The paths of a case's artifacts in ``folder`` (the workflow's results/{case}/ layout)."""
    d = Path(folder)
    return {
        **artifact_paths(d),
        "nc": d / f"{name}.nc",
        "vtu": d / f"{name}.vtu",
        "faults": d / f"{name}_faults.vtp",
        "png": d / f"{name}.png",
        "histograms": d / f"{name}_histograms.png",
        "summary": d / "summary.json",
        "flow_deck": d / "flow" / f"{name.upper()}.DATA",
        "flow_summary": d / "flow" / "summary.json",
        "flow_wells": d / "flow" / f"{name}_wells.png",
        "flow_vtu": d / "flow" / f"{name}_flow.vtu",
    }


def run_case(case_file: str | os.PathLike, folder: str | os.PathLike, simulate: bool = False) -> list[Path]:
    """Run every stage the case needs into ``folder``; returns the files written. With
    ``simulate``, OPM Flow also runs the deck of a case with a ``simulation`` section."""
    case = load_case(case_file)
    out = case_outputs(case.name, folder)
    Path(folder).mkdir(parents=True, exist_ok=True)
    written = []
    horizons = None
    if case.has_horizons:
        stage_horizons(case_file, out["horizons"])
        horizons = out["horizons"]
        written.append(horizons)
    grdecl = out["grdecl"] if case.writes_grdecl else None
    stage_grid(case_file, out["grid"], horizons, grdecl)
    written += [out["grid"]] + ([grdecl] if grdecl else [])
    stage_geometry(case_file, out["grid"], out["geometry"])
    written.append(out["geometry"])
    petro = None
    if case.has_petrophysics:
        petro = out["petrophysics"]
        stage_petrophysics(case_file, out["grid"], out["geometry"], petro)
        written.append(petro)
    coarse = None
    if case.has_coarsening:
        coarse = out["coarse"]
        stage_coarsen(case_file, out["grid"], out["geometry"], petro, coarse)
        written.append(coarse)
    trans = None
    if case.has_transmissibility:
        trans = out["transmissibility"]
        stage_transmissibility(case_file, out["grid"], out["geometry"], petro, trans, grdecl)
        written.append(trans)
    keys = ("nc", "vtu", "faults", "png", "histograms", "summary")
    exports = {k: str(out[k]) for k in keys if k != "vtu" or case.writes_vtu}
    stage_export(case_file, out["grid"], out["geometry"], exports, petro, coarse, trans)
    written += [Path(p) for p in exports.values()]
    if case.writes_flow_deck:
        deck = stage_flow_deck(
            case_file, out["grid"], out["geometry"], petro, trans, out["flow_deck"], grdecl
        )
        written += list(deck.files)
        if simulate and case.has_simulation:
            results = {"summary": out["flow_summary"], "wells": out["flow_wells"], "vtu": out["flow_vtu"]}
            stage_simulate(case_file, out["flow_deck"], out["grid"], trans, results)
            written += list(results.values())
    dropped = {out[k] for k in case.dropped_artifacts}  # outputs.stage_files: false
    for path in dropped:
        path.unlink(missing_ok=True)
    return [p for p in written if Path(p) not in dropped]
