"""What a case builds: every stage, the files it reads and writes, and when a case has them.

This table is the one place that says it. :func:`gridlib.stages.run_case`, the Snakemake rules
(``workflow/rules/stages.smk`` generates one rule per stage from it), the studies and
:func:`case_paths` all derive from :data:`STAGES`. Adding a stage is one :class:`Stage` entry
(here, or :func:`register_stage` from a module of one's own) and its stage function.

A stage function has the signature ``function(case, **paths)``: the loaded
:class:`~gridlib.config.Case` and, as keyword arguments named after the artifacts' keys, the
paths of its inputs (an input the case does not have is left out: its parameter defaults to
None) and of its outputs (those the case has). It writes each output atomically
(:mod:`gridlib.io.atomic`).

Paths are relative to the case's folder (``results/<case>/`` in the workflow); ``{case}`` is
the case's name and ``{NAME}`` its OPM Flow deck's name (the name in upper case).

>>> [stage.name for stage in STAGES][:4]
['horizons', 'grid', 'geometry', 'petrophysics']
>>> case_paths("anticline", "results/anticline")["flow_deck"].as_posix()
'results/anticline/flow/ANTICLINE.DATA'
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from string import Formatter
from typing import Any

from .config import Case

CasePredicate = Callable[[Case], bool]


def always(case: Case) -> bool:
    """Every case."""
    return True


def never(case: Case) -> bool:
    """No case."""
    return False


def drops_stage_files(case: Case) -> bool:
    """``outputs.stage_files: false``: a stage file goes once ``{case}.nc`` holds it."""
    return not case.keeps_stage_files


def drops_grdecl(case: Case) -> bool:
    """``grid.grdecl`` goes with the stage files where the OPM Flow deck's GRID include holds the
    same grid; a case without a Flow deck keeps it (it is the only GRDECL the case writes)."""
    return not case.keeps_stage_files and case.writes_flow_deck


def has_pick_horizons(case: Case) -> bool:
    """A case with a horizon given by picks (``horizons.surfaces[k].points``)."""
    return case.has_horizons and any("points" in s for s in case.data["horizons"]["surfaces"])


@dataclass(frozen=True)
class Report:
    """Where a picture goes in the Snakemake report: its caption (a file of
    ``workflow/report/``) and category (the case is its subcategory)."""

    caption: str
    category: str


@dataclass(frozen=True)
class Artifact:
    """A file a stage writes: its key (the stage functions' keyword), its path in the case's
    folder, which cases have it (beside its stage's own condition), and which cases remove it
    once their run ends (``temporary``: Snakemake's ``temp()``). A ``directory`` artifact is a
    folder whose files the case decides (``exchange/``: one surface per horizon): Snakemake's
    ``directory()``, written whole by :func:`gridlib.io.atomic.atomic_directory`."""

    key: str
    path: str
    when: CasePredicate = always
    temporary: CasePredicate = never
    report: Report | None = None
    directory: bool = False

    def path_in(self, folder: str | os.PathLike, name: str) -> Path:
        """The artifact's path in ``folder`` for the case called ``name``."""
        return Path(folder) / self.path.format(case=name, NAME=name.upper())

    @property
    def wildcards(self) -> tuple[str, ...]:
        """The fields of :attr:`path` (``case``, ``NAME``)."""
        return tuple(field for _, field, _, _ in Formatter().parse(self.path) if field)


@dataclass(frozen=True)
class Stage:
    """One stage: its name (its log file's, and its Snakemake rule's unless ``rule`` gives
    another), its function (or the
    ``"module:function"`` that names it, imported by :func:`gridlib.stages.run_stage` when the
    stage runs, so that the workflow's parse and each job import only what they use), the keys
    of the artifacts it reads, the artifacts it writes, which cases run it, and what a job of it
    asks for."""

    name: str
    function: Callable[..., Any] | str
    inputs: tuple[str, ...]
    outputs: tuple[Artifact, ...]
    when: CasePredicate = always
    on_request: bool = False  # run only when asked (``simulate``), not by default
    threads: int = 1
    mem_mb: int = 4000
    doc: str = ""
    rule: str = ""  # the Snakemake rule's name where it is not the stage's

    @property
    def rule_name(self) -> str:
        """The name of the stage's Snakemake rule (variants add a suffix)."""
        return self.rule or self.name

    def outputs_of(self, case: Case) -> tuple[Artifact, ...]:
        """The outputs ``case`` has (all of them where it runs the stage)."""
        return tuple(a for a in self.outputs if a.when(case)) if self.when(case) else ()


# The Snakemake report's categories. Its menu sorts them by name (Snakemake's html reporter):
# numbered, so that the cases' pictures come first, then the summary table, the simulations and
# the studies (workflow/report/workflow.rst, the landing page, links to them; the rule graph is
# the menu's "Workflow" entry).
PICTURES = "1. Cases"
SUMMARY = "2. Summary"
SIMULATIONS = "3. Simulations"
STUDIES = "4. Studies"

STAGES: tuple[Stage, ...] = (
    Stage(
        "horizons",
        "gridlib.stages.horizons:stage_horizons",
        (),
        (Artifact("horizons", "horizons.nc", temporary=drops_stage_files),),
        when=lambda case: case.has_horizons,
        mem_mb=2000,
        doc="The case's horizons on their lattice, ordered (erode/onlap/error).",
    ),
    Stage(
        "grid",
        "gridlib.stages.grid:stage_grid",
        ("horizons",),
        (
            Artifact("grid", "grid.nc", temporary=drops_stage_files),
            Artifact("grdecl", "grid.grdecl", when=lambda case: case.writes_grdecl, temporary=drops_grdecl),
        ),
        doc="The case's grid, checked (and its GRDECL for simulators: corner-point and deck grids).",
    ),
    Stage(
        "geometry",
        "gridlib.stages.geometry:stage_geometry",
        ("grid",),
        (Artifact("geometry", "geometry.nc", temporary=drops_stage_files),),
        doc="Cell volumes and centroids, face areas, normals and centroids.",
    ),
    Stage(
        "petrophysics",
        "gridlib.stages.petrophysics:stage_petrophysics",
        ("grid", "geometry"),
        (Artifact("petrophysics", "petrophysics.nc", temporary=drops_stage_files),),
        when=lambda case: case.has_petrophysics,
        doc="Porosity, permeability and NTG per cell (random fields in depositional coordinates).",
    ),
    Stage(
        "coarsen",
        "gridlib.stages.coarsen:stage_coarsen",
        ("grid", "geometry", "petrophysics"),
        (Artifact("coarse", "coarse.nc", temporary=drops_stage_files),),
        when=lambda case: case.has_coarsening,
        doc="Partition, coarse grid and upscaled rock.",
    ),
    Stage(
        "transmissibility",
        "gridlib.stages.transmissibility:stage_transmissibility",
        ("grid", "grdecl", "geometry", "petrophysics"),
        (Artifact("transmissibility", "transmissibility.nc", temporary=drops_stage_files),),
        when=lambda case: case.has_transmissibility,
        doc="Connections (cell pairs, T, kind, face), pore volumes and the simulator's cell index.",
    ),
    Stage(
        "quality",
        "gridlib.stages.quality:stage_quality",
        ("grid", "grdecl", "geometry", "petrophysics"),
        (
            Artifact("quality", "quality.nc", temporary=drops_stage_files),
            Artifact(
                "quality_png",
                "{case}_quality.png",
                when=lambda case: case.writes_pictures,
                report=Report("quality.rst", PICTURES),
            ),
        ),
        doc="Cell-quality measures (xtgeo's set on hexahedra, orientation errors, aspect ratio, face "
        "non-planarity), their histograms, and the case's qc rules checked.",
    ),
    Stage(
        "wells",
        "gridlib.stages.wells:stage_wells",
        ("grid", "grdecl", "geometry", "petrophysics"),
        (Artifact("wells", "wells.nc"),),
        when=lambda case: case.has_deviated_wells,
        doc="The trajectory and survey wells: their paths, the cells they cross and their connection "
        "factors.",
    ),
    Stage(
        "export",
        "gridlib.stages.export:stage_export",
        ("grid", "geometry", "petrophysics", "coarse", "transmissibility", "wells", "horizons", "quality"),
        (
            Artifact("nc", "{case}.nc"),
            Artifact("vtu", "{case}.vtu", when=lambda case: case.writes_vtu),
            Artifact("faults", "{case}_faults.vtp"),
            Artifact("well_paths", "{case}_wells.vtp", when=lambda case: case.has_deviated_wells),
            Artifact("summary", "summary.json"),
        ),
        doc="One self-describing netCDF, VTU, fault faces and the case's summary.",
    ),
    Stage(
        "pictures",
        "gridlib.stages.pictures:stage_pictures",
        ("grid", "geometry", "petrophysics", "transmissibility", "wells", "faults", "horizons"),
        (
            Artifact("png", "{case}.png", report=Report("grid.rst", PICTURES)),
            Artifact("histograms", "{case}_histograms.png", report=Report("histograms.rst", PICTURES)),
            Artifact("plan", "{case}_plan.png", report=Report("plan.rst", PICTURES)),
            Artifact(
                "section",
                "{case}_section.png",
                when=lambda case: case.is_3d,
                report=Report("section.rst", PICTURES),
            ),
            Artifact(
                "residuals",
                "{case}_residuals.png",
                when=has_pick_horizons,
                report=Report("residuals.rst", PICTURES),
            ),
        ),
        when=lambda case: case.writes_pictures,
        mem_mb=2000,
        doc="The pictures of a QC slide: the grid in 3-D, its histograms, plan view and cross-section, "
        "and the horizon-pick residuals (unless ``outputs.pictures: false``).",
    ),
    Stage(
        "exchange",
        "gridlib.stages.exchange:stage_exchange",
        ("grid", "grdecl", "petrophysics", "horizons"),
        (
            Artifact("roff", "{case}.roff", when=lambda case: case.writes_grdecl),
            Artifact("exchange", "exchange", when=lambda case: case.has_horizons, directory=True),
        ),
        when=lambda case: case.writes_grdecl or case.has_horizons,
        doc="The grid, rock and zones as ROFF; the horizons as IRAP binary surfaces and the faults as "
        "RMS/xtgeo polygons in exchange/ (RMS, xtgeo, ResInsight).",
    ),
    Stage(
        "flow_deck",
        "gridlib.stages.flow_deck:stage_flow_deck",
        ("grid", "grdecl", "geometry", "petrophysics", "transmissibility", "wells"),
        (Artifact("flow_deck", "flow/{NAME}.DATA"),),
        when=lambda case: case.writes_flow_deck,
        doc="The case's OPM Flow deck flow/<NAME>.DATA and its includes.",
    ),
    Stage(
        "simulate",
        "gridlib.stages.simulate:stage_simulate",
        ("flow_deck", "grid", "transmissibility"),
        (
            Artifact("flow_summary", "flow/summary.json"),
            Artifact("flow_wells", "flow/{case}_wells.png", report=Report("wells.rst", SIMULATIONS)),
            Artifact("flow_pvd", "flow/{case}_flow.pvd"),
        ),
        when=lambda case: case.writes_flow_deck and case.has_simulation,
        on_request=True,
        rule="simulate_case",  # `snakemake simulate` is the target of every case's simulation
        doc="OPM Flow runs the case's deck: the wells' rates and pressures, the field figures, and the "
        "results on the case's own grid.",
    ),
)


def register_stage(stage: Stage, *, after: str | None = None) -> None:
    """Add ``stage`` to :data:`STAGES` (after the stage named ``after``, else at the end; a stage
    of the same name is replaced in place): it then runs in :func:`gridlib.stages.run_case` and
    gets its rule in the workflow (which imports the modules its configuration's ``plugins``
    list names, where such calls go). Its inputs must be earlier stages' artifacts."""
    global STAGES
    known = {a.key for s in STAGES if s.name != stage.name for a in s.outputs}
    for a in stage.outputs:
        if a.key in known:
            raise ValueError(f"stage {stage.name!r}: artifact {a.key!r} is another stage's output")
    names = [s.name for s in STAGES]
    if stage.name in names:
        at = names.index(stage.name)
        table = STAGES[:at] + (stage,) + STAGES[at + 1 :]
    else:
        if after is not None and after not in names:
            raise ValueError(f"stage {stage.name!r}: no stage {after!r} to follow")
        at = names.index(after) + 1 if after is not None else len(names)
        table = STAGES[:at] + (stage,) + STAGES[at:]
    earlier = {a.key for s in table[:at] for a in s.outputs}
    unknown = [key for key in stage.inputs if key not in earlier]
    if unknown:
        raise ValueError(
            f"stage {stage.name!r}: its inputs {', '.join(map(repr, unknown))} are no earlier stage's outputs"
        )
    STAGES = table


def artifacts() -> dict[str, Artifact]:
    """Every artifact of :data:`STAGES` by key."""
    return {a.key: a for stage in STAGES for a in stage.outputs}


def producers() -> dict[str, Stage]:
    """The stage that writes each artifact, by artifact key."""
    return {a.key: stage for stage in STAGES for a in stage.outputs}


def case_paths(name: str, folder: str | os.PathLike) -> dict[str, Path]:
    """The path of every artifact a case called ``name`` may have, in ``folder`` (its
    results/<case>/ folder), by key."""
    return {key: artifact.path_in(folder, name) for key, artifact in artifacts().items()}


def case_artifacts(case: Case, *, on_request: bool = False) -> tuple[Artifact, ...]:
    """The artifacts ``case`` writes, in stage order (with ``on_request``, those of the stages
    run only when asked too, e.g. its simulation)."""
    return tuple(a for stage in STAGES if on_request or not stage.on_request for a in stage.outputs_of(case))


def dropped(case: Case) -> tuple[str, ...]:
    """The keys of the artifacts ``case`` removes once its run ends (``outputs.stage_files:
    false``)."""
    return tuple(a.key for a in case_artifacts(case, on_request=True) if a.temporary(case))


def stage_inputs(stage: Stage, case: Case) -> tuple[str, ...]:
    """The keys of ``stage``'s inputs that ``case`` has (an input no stage of the case writes is
    left out, and its parameter of the stage function keeps its default)."""
    has = {a.key for a in case_artifacts(case, on_request=True)}
    return tuple(key for key in stage.inputs if key in has)
