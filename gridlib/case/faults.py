"""A case's faults (``faults``) as gridlib objects: a fault's ``trace`` and ``throw`` (a number,
or ``{start, end}`` varying linearly along the trace) and ``side`` give a
:class:`~gridlib.pillars.fault_traces.FaultTrace`."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..config import Case
from ..pillars.fault_traces import FaultTrace


def fault_traces(case: Case) -> list[FaultTrace]:
    """The case's faults as FaultTraces (throw in m; 0 where none is given)."""
    traces = []
    for spec in case.data.get("faults", []):
        throw = spec["throw"]
        if isinstance(throw, dict):
            start, end = float(throw["start"]), float(throw["end"])
            value: Any = lambda s, a=start, b=end: a + (b - a) * np.asarray(s)  # noqa: E731
        else:
            value = float(throw)
        side = spec["side"]
        traces.append(FaultTrace(spec["trace"], throw=value, name=spec["name"], side=side))
    return traces
