"""A case's horizons (``horizons``): its surfaces interpolated on its lattice, ordered."""

from __future__ import annotations

from ..config import Case
from ..errors import InputError
from ..horizons.blocks import DepthFunction, FaultBlocks, footwall_top
from ..io.horizon_files import build_horizons
from ..pillars.fault_traces import FaultTrace
from .axes import axis
from .faults import fault_traces


def case_horizons(case: Case):
    """The horizons Dataset of a case (depth over (horizon, y, x), m, positive down).

    With ``per_fault_block``, an inclined fault's trace is its footwall cut-off and the picks
    go to blocks by its surface at their depth (:func:`~gridlib.horizons.build.block_surfaces`).
    """
    spec = case.data["horizons"]
    x, y = axis(spec["lattice"]["x"]), axis(spec["lattice"]["y"])
    specs = [dict(surface) for surface in spec["surfaces"]]  # files relative to the case file (base_dir)
    per_block = bool(spec["per_fault_block"])
    try:
        return build_horizons(
            specs,
            x,
            y,
            ordering=spec["ordering"],
            faults=plan_traces(case) if per_block else (),
            per_block=per_block,
            fault_surfaces=(lambda top: fault_traces(case, top=top)) if per_block else None,
            base_dir=case.path.parent,
            attrs=case.provenance(),
        )
    except InputError as exc:
        raise InputError(f"{case.path}: {exc}") from exc


def plan_traces(case: Case) -> list[FaultTrace]:
    """The case's fault traces in plan view, with their names and hanging-wall sides, no throw
    (picks per fault block hold it) and no surface."""
    return [
        FaultTrace(f["trace"], throw=0.0, name=f["name"], side=f.get("side", "right"))
        for f in case.data.get("faults", [])
    ]


def block_fault_traces(case: Case, blocks: FaultBlocks, tops, xa, ya) -> list[FaultTrace]:
    """The case's faults for horizons picked per fault block: inclined ones placed at their
    footwall tops (``tops``: (block, y, x) every block's top on the lattice ``xa``, ``ya``)."""
    top: DepthFunction = footwall_top(blocks, tops, xa, ya, plan_traces(case))
    return fault_traces(case, top=top)
