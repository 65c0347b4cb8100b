"""Range checks on rock values (PORO, NTG, PERMX, PERMY, PERMZ) as strict as OPM Flow, no stricter.

What OPM Flow 2022.10 does with them (dry runs and simulations of small decks, and its
``FieldProps``, which checks no range): it refuses none of these values. PORO and NTG above 1
are used as given: pore volume = bulk volume x PORO x NTG, and NTG multiplies the I and J
half-transmissibilities. ECLIPSE models carry NTG above 1 (net-to-gross from a geomodel that
was never clipped), and both simulators run them; so do we, with a **note** naming the cells.

Negative, NaN or infinite values Flow also reads without a word, but nothing it computes from
them means anything: a negative porosity or NTG gives a negative pore volume (the cell stays
active), a negative permeability a negative transmissibility, NaN a NaN. gridlib does not
compute such numbers: these are **errors**, naming the keyword and the first cells.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError

FRACTIONS = ("PORO", "NTG")  # above 1: a note
ROCK_KEYWORDS = ("PORO", "NTG", "PERMX", "PERMY", "PERMZ")


def check_rock_values(
    values: Mapping[str, ArrayLike], where: str, name_cells: Callable[[np.ndarray], str]
) -> tuple[str, ...]:
    """Check rock ``values`` (keyword -> the values of the cells that count, e.g. the active ones):
    an InputError for any that is negative, NaN or infinite; a note for PORO or NTG above 1.

    ``where`` names the file (or case) in the messages, ``name_cells`` names the cells at
    positions of the arrays (e.g. :func:`gridlib.cell_names.cell_names` with their logical
    indices).

    >>> notes = check_rock_values({"NTG": [0.5, 1.25]}, "D.DATA", lambda pos: f"cells {pos.tolist()}")
    >>> print(*notes)
    D.DATA: NTG: 1 cells have NTG above 1 (up to 1.25), used as given, as OPM Flow and ECLIPSE do: cells [1]
    """
    notes = []
    for key, raw in values.items():
        v = np.asarray(raw, dtype=np.float64)
        bad = np.flatnonzero(~(v >= 0) | ~np.isfinite(v))
        if bad.size:
            raise InputError(
                f"{where}: {key}: {bad.size} cells have a negative or undefined {key} (first "
                f"{float(v[bad[0]])!r}): {name_cells(bad)}; OPM Flow would compute negative or "
                "undefined pore volumes or transmissibilities from them"
            )
        if key in FRACTIONS:
            above = np.flatnonzero(v > 1.0)
            if above.size:
                top = float(v[above].max())
                notes.append(
                    f"{where}: {key}: {above.size} cells have {key} above 1 (up to {top:.6g}), "
                    f"used as given, as OPM Flow and ECLIPSE do: {name_cells(above)}"
                )
    return tuple(notes)
