"""Stage ``pictures``: the pictures of a case a geomodeller puts on a QC slide, in their own job
(beside the Flow deck's), from the stage files and the export's fault faces:

* ``{case}.png``: the grid in 3-D, coloured by porosity (else depth, else cell volume), the
  fault faces and the deviated wells' paths (:func:`gridlib.io.pictures.render_grid`);
* ``{case}_histograms.png``: cell volumes, face areas, porosity (the MRST book's Fig. 3.33)
  and log10 T (:func:`gridlib.io.pictures.plot_histograms`);
* ``{case}_plan.png``: the plan view, the top's depth contoured with the fault traces, the
  wells and the section's line (:mod:`gridlib.io.plan_view`);
* ``{case}_section.png`` (3-D grids): the cross-section along the case's ``pictures.section``,
  else through the wells (:mod:`gridlib.io.cross_section`), coloured by porosity, else zone,
  else layer, else depth;
* ``{case}_residuals.png`` (cases with horizons given by picks): each pick's residual against
  its interpolated horizon, as a map and a histogram per horizon
  (:func:`gridlib.io.pick_residuals.residuals_figure`, from ``horizons.nc``).

The wells drawn are the case's (``wells``): a vertical well at its ``point``, a PEBI grid's
refining well along its plan-view ``path`` (at the grid's top), and the trajectory and survey
wells of ``wells.nc``.

Every picture labels its axes and colour bars with the case's units (``unit_system`` of the
grid file: METRIC m, or a deck's own, e.g. FIELD ft for SPE9) and draws in the one style of
:mod:`gridlib.io.picture_style`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..completions import vertical_well_cells
from ..config import Case
from ..connectivity import ragged_arange, repeat_ids
from ..cornerpoint.map_axes import MapAxes
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid
from ..io.cross_section import default_section, section_figure, well_heads
from ..io.horizon_files import read_pick_residuals
from ..io.netcdf import read_cell_geometry, read_netcdf
from ..io.netcdf_parts import check_same_cells, read_attrs, stored_map_axes, stored_unit_system
from ..io.pick_residuals import residuals_figure
from ..io.picture_style import DPI, picture_style, quantity_label
from ..io.pictures import plot_histograms, render_grid, save_figure
from ..io.plan_view import plan_figure
from ..io.quantities import picture_quantity
from ..io.rock_file import read_rock
from ..io.section_cut import SectionCut, cut_grid
from ..io.top_surface import top_surface
from ..io.transmissibility_file import read_transmissibility
from ..io.well_tracks import WellTrack, plan_track, record_tracks, vertical_track
from ..io.wells_file import WellRecord, read_wells
from ..units import UnitSystem
from .common import log


@dataclass(frozen=True)
class Scene:
    """What the pictures of a case show: its grid and geometry, unit system, fault and well
    names, rock (None without), the cells' builder data (``zone``, ``layer``, ...), the
    transmissibilities (None without) and the deviated wells of ``wells.nc``."""

    name: str
    grid: Grid
    geo: Geometry
    units: UnitSystem
    fault_names: tuple[str, ...]
    rock: dict[str, np.ndarray] | None
    cell_data: dict[str, np.ndarray]
    trans: np.ndarray | None
    wells: tuple[WellRecord, ...]
    map_axes: MapAxes | None = None  # where the grid lies on the map (a deck's MAPAXES)

    @property
    def title(self) -> str:
        """The pictures' title: the case's name and its number of cells."""
        return f"{self.name}: {self.grid.num_cells:,d} cells"

    def colouring(self) -> tuple[str, np.ndarray]:
        """The cell value the 3-D view is coloured by: porosity, else depth (3-D), else the cell
        measure (volume, or area in 2-D): its name and values."""
        if self.rock is not None:
            return "poro", self.rock["poro"]
        if self.grid.dim == 3:
            return "depth", self.geo.cell_centroids[:, 2]
        return "volume", self.geo.cell_volumes

    def well_tracks(self, case: Case) -> tuple[WellTrack, ...]:
        """The wells to draw: the case's vertical wells (over the depths of the cells their line
        crosses, :func:`gridlib.completions.vertical_well_cells`; the grid's depth range where
        the grid has no columns) and its PEBI grid's refining wells (at its top), then the
        deviated wells of ``wells.nc``."""
        z = self.grid.nodes.coords[:, -1] if self.grid.dim == 3 else np.zeros(1)
        depths = (float(z.min()), float(z.max()))
        tracks = []
        located = self._locatable() if self.grid.dim == 3 else None
        for well in case.data.get("wells", []):
            if "point" in well:  # on the map; drawn in the grid's frame
                point = (
                    well["point"] if self.map_axes is None else self.map_axes.to_grid(np.array(well["point"]))
                )
                tracks.append(vertical_track(well["name"], point, self._crossed(located, point, depths)))
            elif "path" in well:
                tracks.append(plan_track(well["name"], np.asarray(well["path"], dtype=float), depths[0]))
        return (*tracks, *record_tracks(self.wells))

    def _locatable(self) -> Geometry:
        """The geometry with face centroids (the geometry file's are left out when read,
        :func:`gridlib.io.netcdf.read_cell_geometry`): the means of the faces' nodes, enough to
        locate a vertical well's cells."""
        npos = self.grid.faces.node_pos
        owner = repeat_ids(npos)
        xyz = self.grid.nodes.coords[self.grid.faces.nodes]
        counts = np.maximum(np.diff(npos), 1)
        centres = np.column_stack([np.bincount(owner, xyz[:, k], counts.size) / counts for k in range(3)])
        return replace(self.geo, face_centroids=centres)

    def _crossed(
        self, located: Geometry | None, point: list[float], depths: tuple[float, float]
    ) -> tuple[float, float]:
        """The depth range of the nodes of the cells a vertical line at ``point`` crosses
        (``depths`` where it crosses none, or the grid cannot say)."""
        if located is None:
            return depths
        try:
            cells = vertical_well_cells(self.grid, located, point[:2])
        except InputError:
            return depths
        if cells.size == 0:
            return depths
        pos = self.grid.cells.face_pos
        faces = self.grid.cells.faces[ragged_arange(pos[cells], pos[cells + 1] - pos[cells])]
        npos = self.grid.faces.node_pos
        nodes = self.grid.faces.nodes[ragged_arange(npos[faces], npos[faces + 1] - npos[faces])]
        z = self.grid.nodes.coords[nodes, 2]
        return float(z.min()), float(z.max())

    def quantity(self, name: str) -> tuple[str, str | None]:
        """What pictures call a cell quantity and its unit in the case's units
        (:func:`gridlib.io.quantities.picture_quantity`)."""
        return picture_quantity(name, self.units, self.grid.griddim)

    def label(self, name: str) -> str:
        """``title [unit]`` of a cell quantity (the title alone without a unit)."""
        return quantity_label(*self.quantity(name))


def read_scene(
    case: Case,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    petrophysics: str | os.PathLike | None = None,
    transmissibility: str | os.PathLike | None = None,
    wells: str | os.PathLike | None = None,
) -> Scene:
    """The :class:`Scene` of a case from its stage files (one InputError naming a file that is
    damaged or of another grid)."""
    stored = read_netcdf(grid)
    attrs = read_attrs(grid)
    geo = read_cell_geometry(geometry)
    check_same_cells(grid, stored.grid.num_cells, {geometry: geo.cell_volumes.size})
    rock = read_rock(petrophysics) if petrophysics is not None else None
    trans = None
    if transmissibility is not None:
        trans = read_transmissibility(transmissibility)[0]["trans"].values
    return Scene(
        case.name,
        stored.grid,
        geo,
        stored_unit_system(grid, attrs),
        tuple(attrs.get("fault_names", [])),
        rock,
        dict(stored.cell_data),
        trans,
        read_wells(wells) if wells is not None else (),
        stored_map_axes(grid, attrs),
    )


def stage_pictures(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    faults: str | os.PathLike,
    petrophysics: str | os.PathLike | None = None,
    transmissibility: str | os.PathLike | None = None,
    wells: str | os.PathLike | None = None,
    horizons: str | os.PathLike | None = None,
    png: str | os.PathLike,
    histograms: str | os.PathLike,
    plan: str | os.PathLike,
    section: str | os.PathLike | None = None,
    residuals: str | os.PathLike | None = None,
) -> None:
    """Draw the case's pictures from its stage files (``grid``, ``geometry``, the export's
    fault faces ``faults`` and, where the case has them, ``petrophysics``, ``transmissibility``,
    ``wells`` and ``horizons``): ``png`` ({case}.png, the 3-D view), ``histograms``, ``plan``,
    ``section`` (3-D grids) and ``residuals`` (horizons given by picks)."""
    scene = read_scene(case, grid, geometry, petrophysics, transmissibility, wells)
    tracks = scene.well_tracks(case)  # once for the figures and the 3-D view
    figures = case_figures(case, scene, with_section=section is not None, tracks=tracks)  # checks the line
    if residuals is not None and horizons is not None:
        figures["residuals"] = pick_residuals_figure(case, horizons)
    render_grid(Path(png), **view_arguments(case, scene, faults, tracks))
    poro = None if scene.rock is None else scene.rock["poro"]
    plot_histograms(
        Path(histograms), scene.geo, poro, scene.grid.griddim, scene.title, scene.units, scene.trans
    )
    drawn = {"plan": plan, "section": section, "residuals": residuals}
    for key, figure in figures.items():
        save_figure(figure, drawn[key], dpi=DPI)
    log.info("drew the pictures of %s (%d cells)", case.name, scene.grid.num_cells)


def view_arguments(
    case: Case, scene: Scene, faults: str | os.PathLike, tracks: tuple[WellTrack, ...] | None = None
) -> dict[str, Any]:
    """The arguments of the 3-D view (:func:`gridlib.io.grid_view.grid_scene`, or
    :func:`~gridlib.io.pictures.render_grid` with a path): the grid coloured as
    :meth:`Scene.colouring` says, its colour bar titled ``quantity [unit]``, the case's length
    unit on the axes, the fault faces ``faults`` (``{case}_faults.vtp``) and every well
    (``tracks``: :meth:`Scene.well_tracks`, computed where not given)."""
    scalar, values = scene.colouring()
    bar_title = scene.label(scalar)
    return {
        "grid": scene.grid,
        "values": values,
        "faults": Path(faults),
        "scalar": scalar,
        "title": scene.title,
        "bar_title": bar_title,
        "length_unit": scene.units.length_label,
        "wells": scene.well_tracks(case) if tracks is None else tracks,
    }


def pick_residuals_figure(case: Case, horizons: str | os.PathLike):
    """The horizon-pick residuals' figure of the case (its ``horizons.nc``, in m) with the
    traces of its faults given by traces (:func:`gridlib.io.pick_residuals.residuals_figure`)."""
    picks, names = read_pick_residuals(horizons)
    faults = case.data.get("faults", [])
    traces = [(f["name"], np.asarray(f["trace"], dtype=np.float64)) for f in faults if "trace" in f]
    title = f"{case.name}: horizon-pick residuals"
    return residuals_figure(picks, names, title=title, length_unit="m", faults=traces)


def section_line(case: Case, scene: Scene, tracks: tuple[WellTrack, ...]) -> np.ndarray:
    """The case's ``pictures.section`` (k, 2), else the default line through its wells
    (:func:`gridlib.io.cross_section.default_section`)."""
    return section_cut(case, scene, tracks)[0]


def section_cut(case: Case, scene: Scene, tracks: tuple[WellTrack, ...]) -> tuple[np.ndarray, SectionCut]:
    """The section's line and its cut of the grid: the case's ``pictures.section`` (an
    InputError naming it where it cuts no cell), else the default line through the wells, else
    (wells all off the grid) through its centre."""
    given = case.data.get("pictures", {}).get("section")
    if given is not None:
        line = np.asarray(given, dtype=np.float64)[:, :2]
        if scene.map_axes is not None:  # given on the map, as the wells; the grid in its own frame
            line = scene.map_axes.to_grid(line)
        cut = cut_grid(scene.grid, line)
        if cut.cells.size == 0:
            raise InputError(f"{case.path}: pictures.section: the line cuts no cell of the grid")
        return line, cut
    z = scene.grid.nodes.coords[:, 2]
    xy = scene.grid.nodes.coords[:, :2]
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    line = default_section(well_heads(tracks, (float(z.min()), float(z.max()))), lo, hi)
    cut = cut_grid(scene.grid, line)
    if cut.cells.size == 0:
        line = default_section(np.zeros((0, 2)), lo, hi)
        cut = cut_grid(scene.grid, line)
    return line, cut


def section_colouring(scene: Scene) -> tuple[np.ndarray, tuple[str, str | None], bool]:
    """The cell values of the section: porosity, else zone, else layer (the first of them with
    more than one value), else depth; with their name and unit, and whether they are
    categories (zone, layer)."""
    if scene.rock is not None:
        return scene.rock["poro"], scene.quantity("poro"), False
    layers = {} if scene.grid.layering is None else {"layer": scene.grid.layering.layer}
    data = {**layers, **scene.cell_data}
    for name in ("zone", "layer"):
        if name in data and np.unique(data[name]).size > 1:  # a single zone tells nothing
            return data[name], (name, None), True
    return scene.geo.cell_centroids[:, 2], ("depth", scene.units.length_label), False


def case_figures(
    case: Case, scene: Scene, *, with_section: bool = True, tracks: tuple[WellTrack, ...] | None = None
) -> dict[str, Any]:
    """The matplotlib figures of the case's plan view (``plan``) and, ``with_section`` (3-D
    grids), its cross-section (``section``), in the pictures' style; an InputError naming
    ``pictures.section`` where the case's line cuts no cell. ``tracks``: the wells
    (:meth:`Scene.well_tracks`, computed where not given)."""
    tracks = scene.well_tracks(case) if tracks is None else tracks
    line, cut = section_cut(case, scene, tracks) if with_section else (None, None)
    figures = {}
    with picture_style():
        if line is not None:
            values, quantity, categorical = section_colouring(scene)
            figures["section"] = section_figure(
                scene.grid,
                line,
                length_unit=scene.units.length_label,
                values=values,
                quantity=quantity,
                categorical=categorical,
                fault_names=scene.fault_names,
                wells=tracks,
                cell_size=top_surface(scene.grid, scene.geo).cell_size(),
                title=case.name,
                cut=cut,
            )
        scalar, values = scene.colouring()
        figures["plan"] = plan_figure(
            scene.grid,
            scene.geo,
            length_unit=scene.units.length_label,
            fault_names=scene.fault_names,
            wells=tracks,
            values=values,
            quantity=scene.quantity(scalar),
            title=case.name,
            section=line,
        )
    return figures
