"""Report steps of a unified restart file (gridlib.io.flow_results.restart_steps), on a small
UNRST written with resfo: each step's number, time, unit system and solution arrays (float
arrays of one value per active cell only), and bad files named."""

from __future__ import annotations

import numpy as np
import pytest
import resfo

from gridlib.errors import InputError
from gridlib.io.flow_results import restart_steps


def intehead(units: int, nactive: int) -> np.ndarray:
    head = np.zeros(411, dtype=np.int32)
    head[2], head[11] = units, nactive
    return head


def write_unrst(path, steps, units=1, nactive=3):
    records = []
    for seqnum, days, pressure in steps:
        records += [
            ("SEQNUM  ", np.array([seqnum], dtype=np.int32)),
            ("INTEHEAD", intehead(units, nactive)),
            ("DOUBHEAD", np.array([days, 0.0, 365.0])),
            ("IWEL    ", np.arange(nactive, dtype=np.int32)),  # not in the solution section
            ("STARTSOL", resfo.MESS),
            ("PRESSURE", np.asarray(pressure, dtype=np.float32)),
            ("SWAT    ", np.full(nactive, 0.25, dtype=np.float32)),
            ("REGION  ", np.ones(nactive, dtype=np.int32)),  # an integer array: not a result
            ("OTHER   ", np.ones(nactive + 1, dtype=np.float32)),  # not per active cell
            ("ENDSOL  ", resfo.MESS),
        ]
    resfo.write(path, records)


def test_steps_times_units_and_solution_arrays(tmp_path):
    write_unrst(
        tmp_path / "RUN.UNRST", [(0, 0.0, [200.5, 201.0, 202.0]), (3, 90.0, [190.0, 191.25, 192.0])], units=2
    )
    steps = list(restart_steps(tmp_path / "RUN"))
    assert [(s.step, s.days, s.units) for s in steps] == [(0, 0.0, "FIELD"), (3, 90.0, "FIELD")]
    assert [list(s.cells) for s in steps] == [["PRESSURE", "SWAT"]] * 2
    assert steps[1].cells["PRESSURE"].tolist() == [190.0, 191.25, 192.0]
    assert steps[1].cells["PRESSURE"].dtype == np.float64 and steps[0].cells["SWAT"].tolist() == [0.25] * 3


def test_bad_restart_files_are_named(tmp_path):
    with pytest.raises(InputError, match=r"NONE\.UNRST: not found"):
        list(restart_steps(tmp_path / "NONE"))
    write_unrst(tmp_path / "CUT.UNRST", [(0, 0.0, [1.0, 2.0, 3.0])])
    raw = (tmp_path / "CUT.UNRST").read_bytes()
    (tmp_path / "CUT.UNRST").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(InputError, match=r"CUT\.UNRST: not readable as an ECLIPSE binary file"):
        list(restart_steps(tmp_path / "CUT"))
    odd = [("PRESSURE", np.ones(3, dtype=np.float32)), ("SEQNUM  ", np.array([1], dtype=np.int32))]
    resfo.write(tmp_path / "ODD.UNRST", odd)
    with pytest.raises(InputError, match=r"ODD\.UNRST: a report step without SEQNUM, INTEHEAD and DOUBHEAD"):
        list(restart_steps(tmp_path / "ODD"))
