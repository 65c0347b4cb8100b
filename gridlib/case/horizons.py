"""A case's horizons (``horizons``): its surfaces interpolated on its lattice, ordered."""

from __future__ import annotations

from ..config import Case
from ..errors import InputError
from ..io.horizon_files import build_horizons
from .axes import axis


def case_horizons(case: Case):
    """The horizons Dataset of a case (depth over (horizon, y, x), m, positive down)."""
    spec = case.data["horizons"]
    x, y = axis(spec["lattice"]["x"]), axis(spec["lattice"]["y"])
    specs = [dict(surface) for surface in spec["surfaces"]]  # files relative to the case file (base_dir)
    try:
        return build_horizons(
            specs,
            x,
            y,
            ordering=spec["ordering"],
            faults=[f["trace"] for f in case.data.get("faults", [])] if spec["per_fault_block"] else (),
            per_block=bool(spec["per_fault_block"]),
            base_dir=case.path.parent,
            attrs=case.provenance(),
        )
    except InputError as exc:
        raise InputError(f"{case.path}: {exc}") from exc
