"""Stage ``petrophysics``: rock properties per cell as ``petrophysics.nc``.

Porosity (fraction), permeability (mD: ``permx``, ``permy``, ``permz``) and NTG
(fraction), each a constant, one value per layer, a Gaussian random field at
depositional coordinates (so that fault throw does not decorrelate it), or,
for deck grids, the deck's own keyword. A deck grid's rock is its deck's PORO,
PERMX, PERMY, PERMZ and NTG, each replaced only by the case key that sets it
(:mod:`gridlib.case.rock`); each variable's ``source`` attribute says where it
came from. Fields are seeded with the case's seed (porosity), seed + 1
(permeability) and seed + 2 (NTG): the same case and seed give identical arrays.
Porosity or NTG above 1 (a deck's, or a case's
constant) is used as given, as OPM Flow and ECLIPSE use it, with a note naming the cells
(in the log and the ``notes`` attribute); negative or undefined values are errors
(:mod:`gridlib.petrophysics.ranges`).
"""

from __future__ import annotations

import os
from functools import partial

from ..case.rock import case_rock_with_sources
from ..cell_names import cell_names
from ..config import Case
from ..grid import Grid
from ..io.netcdf import read_geometry_netcdf, read_netcdf
from ..io.rock_file import write_rock
from ..petrophysics import Rock
from ..petrophysics.ranges import check_rock_values
from .common import log


def rock_notes(case: Case, grid: Grid, rock: Rock) -> tuple[str, ...]:
    """Notes on porosity or NTG above 1 (:mod:`gridlib.petrophysics.ranges`: OPM Flow and ECLIPSE
    use them as given), naming the cells ((i, j, k) where the grid has logical indices)."""
    values = {"PORO": rock.poro, "NTG": rock.ntg}
    names = partial(cell_names, index_map=grid.cells.index_map, cart_dims=grid.cart_dims)
    return check_rock_values(values, str(case.path), names)


def stage_petrophysics(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    petrophysics: str | os.PathLike,
) -> None:
    """Sample the case's rock properties on the grid of the files ``grid`` and ``geometry``;
    write ``petrophysics`` (``petrophysics.nc``)."""
    mesh = read_netcdf(grid).grid
    rock, sources = case_rock_with_sources(case, mesh, read_geometry_netcdf(geometry))
    notes = rock_notes(case, mesh, rock)
    write_rock(petrophysics, rock, {**case.provenance(), "notes": "; ".join(notes)}, sources)
    for note in notes:
        log.info("note: %s", note)
    log.info(
        "wrote %s: porosity %.4g-%.4g (mean %.4g), permx %.4g-%.4g mD",
        petrophysics,
        rock.poro.min(),
        rock.poro.max(),
        rock.poro.mean(),
        rock.permx.min(),
        rock.permx.max(),
    )
    for name, source in sources.items():
        log.info("%s: %s", name, source)
