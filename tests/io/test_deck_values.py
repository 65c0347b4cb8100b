"""Values a deck may not hold, and decks too large to read: each refused by one DeckError naming
the file, the line, the keyword and (for cell values) the cells (i, j, k); what OPM Flow 2022.10
reads (checked with its dry run, see gridlib.io.grdecl.values) is read, with a note."""

from __future__ import annotations

import tracemalloc
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

from gridlib.io.grdecl import DeckError, read_grdecl
from gridlib.memory import gib_text, machine_memory

# A 3 x 2 x 2 Cartesian box; the variants append to it (keyword lines counted from 1).
BOX = """\
DIMENS
 3 2 2 /
DX
 12*100 /
DY
 12*100 /
DZ
 12*10 /
TOPS
 6*2000 /
PORO
 12*0.25 /
PERMX
 12*100 /
"""  # the next line is line 15


def _read(tmp_path: Path, text: str):
    path = tmp_path / "v.grdecl"
    path.write_text(text)
    return read_grdecl(path)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ("DX\n -100 11*100 /\n", r"v.grdecl:15: DX: 1 values are negative \(first -100\): cells \(1, 1, 1\)"),
        ("DZ\n 11*10 -10 /\n", r"v.grdecl:15: DZ: 1 values are negative .*cells \(3, 2, 2\)"),
        (
            "DXV\n 100 -1 100 /\n",
            r"v.grdecl:15: DXV: 1 values are not finite .* or negative .*value 2 is -1.0",
        ),
        (
            "DZ\n 1e200 11*10 /\n",
            r"v.grdecl:15: DZ: 1 values are beyond \+-1e\+100 \(first 1e\+200\): cells \(1, 1, 1\)",
        ),
        ("PORO\n 5*0.25 nan 6*0.25 /\n", r"v.grdecl:15: PORO: 1 values are not finite .*cells \(3, 2, 1\)"),
        ("PERMX\n inf 11*100 /\n", r"v.grdecl:15: PERMX: 1 values are not finite numbers \(first inf\)"),
        ("ACTNUM\n 11*1 0.5 /\n", r"v.grdecl:15: ACTNUM: 1 values are not integers .*cells \(3, 2, 2\)"),
        ("MULTX\n -2 11*1 /\n", r"v.grdecl:15: MULTX: 1 values are negative .*cells \(1, 1, 1\); OPM Flow"),
        (
            "MULTPV\n 12*1 /\nMULTIPLY\n MULTPV -1 1 1 1 1 2 2 /\n/\n",
            r"v.grdecl:18: MULTIPLY: MULTPV: 1 values are negative .*\(1, 1, 2\)",
        ),
        ("EQUALS\n MULTZ -1 2 3 1 1 1 1 /\n/\n", r"v.grdecl:16: EQUALS: MULTZ: 2 values are negative"),
        ("EQUALS\n 'FOOBAR' 1 /\n/\n", r"v.grdecl:16: EQUALS: 'FOOBAR' is not a keyword with one value per"),
        ("COPY\n PORO FOOBAR /\n/\n", r"v.grdecl:16: COPY: 'FOOBAR' is not a keyword with one value"),
        ("EQUALS\n PORO nan /\n/\n", r"v.grdecl:16: EQUALS: PORO: value nan is not a finite number"),
        ("PINCH\n nan /\n", r"v.grdecl:16: PINCH: threshold thickness nan is not a finite number"),
        ("MINPV\n inf /\n", r"v.grdecl:16: MINPV: minimum pore volume inf is not a finite number"),
        ("FAULTS\n F 1 1 1 2 1 2 X /\n/\nMULTFLT\n F -0.5 /\n/\n", r"v.grdecl:19: MULTFLT: fault 'F': mult"),
        ("MAPAXES\n 0 1 0 0 nan 0 /\n", r"v.grdecl:15: MAPAXES: needs six finite numbers"),
        ("BOX\n 1 4 1 1 1 1 /\n", r"v.grdecl:16: BOX: box 1 4 1 1 1 1 is not inside the 3x2x2 grid"),
    ],
)
def test_values_flow_cannot_use_are_refused_naming_line_and_cells(tmp_path, extra, message):
    with pytest.raises(DeckError, match=r"^/.*" + message):
        _read(tmp_path, BOX + extra)


def test_cornerpoint_geometry_must_be_finite(tmp_path):
    cube = "SPECGRID\n 1 1 1 1 F /\nCOORD\n 0 0 0 0 0 1  1 0 0 1 0 1  0 1 0 0 1 1  1 1 0 1 1 1 /\nZCORN\n"
    with pytest.raises(DeckError, match=r"v.grdecl:5: ZCORN: 1 values are not finite .*cell \(1, 1, 1\)"):
        _read(tmp_path, cube + " 7*0 inf /\n")
    with pytest.raises(DeckError, match=r"v.grdecl:3: COORD: 2 values are not finite .*pillar \(2, 2\)"):
        _read(tmp_path, cube.replace("1 1 0 1 1 1", "1 1 nan 1 1 nan") + " 4*0 4*1 /\n")


def test_what_flow_reads_is_read_with_a_note(tmp_path):
    """OPM Flow 2022.10's dry run reads these (ACTNUM 2 active, -1 inactive; PINCH -1 and
    MINPV -5 change nothing in its output for the box): so does the reader."""
    deck = _read(tmp_path, BOX + "ACTNUM\n 2 -1 10*1 /\nPINCH\n -1 /\nMINPV\n -5 /\n")
    np.testing.assert_array_equal(deck.actnum, [1, 0] + [1] * 10)
    assert deck.pinch == (-1.0, 1e20) and deck.minpv == -5.0
    notes = "\n".join(deck.notes)
    assert "v.grdecl:15: ACTNUM: 1 cells above 1: active, as OPM Flow reads them: (1, 1, 1)" in notes
    assert "ACTNUM: 1 cells below 0: inactive, as OPM Flow reads them: (2, 1, 1)" in notes
    assert "v.grdecl:18: PINCH: threshold thickness -1 is negative" in notes
    assert "v.grdecl:20: MINPV -5 is negative: no cell is removed" in notes


@contextmanager
def at_most_mebibytes(limit: float):
    """The block allocates at most ``limit`` MiB (traced by Python): a refusal came before the arrays."""
    tracemalloc.start()
    try:
        yield
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    assert peak < limit * 2**20, f"{peak / 2**20:.1f} MiB allocated"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "DIMENS\n 10000 10000 100 /\n",
            r"v.grdecl:2: DIMENS: 10000 10000 100: 10,000,000,000 cells need",
        ),
        (
            "SPECGRID\n 100000 100000 1 1 F /\n",
            r"v.grdecl:2: SPECGRID: 100000 100000 1: 10,000,000,000 cells",
        ),
    ],
)
def test_oversized_grids_are_refused_at_their_dimensions(tmp_path, text, message):
    path = tmp_path / "v.grdecl"
    path.write_text(text + "DX\n 10000000000*10 /\n")
    with at_most_mebibytes(4), pytest.raises(DeckError, match=message) as refused:
        read_grdecl(path)
    have = machine_memory()
    assert have is not None and f"to read; this machine has {gib_text(have)}" in str(refused.value)
    assert f"about {gib_text(1e10 * 160)}" in str(refused.value)  # 160 bytes a cell


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ("DX\n 1000000000*10 /\n", r"v.grdecl:15: DX: has 1000000000 values, at most 12 are allowed here"),
        ("PORO\n 99999999999999999*1 /\n", r"v.grdecl:15: PORO: has 100000000000000000 values, expected 12"),
        ("COORD\n 100000000*0 /\n", r"v.grdecl:15: COORD: has 100000000 values, expected 72"),
        ("ZCORN\n 1 2 3 /\n", r"v.grdecl:15: ZCORN: has 3 values, expected 96"),
    ],
)
def test_repeat_counts_beyond_an_array_are_refused_before_any_allocation(tmp_path, extra, message):
    with at_most_mebibytes(4), pytest.raises(DeckError, match=message):
        _read(tmp_path, BOX + extra)


def test_lengths_whose_volumes_overflow_are_refused(tmp_path):
    cube = "SPECGRID\n 1 1 1 1 F /\nCOORD\n 0 0 0 0 0 1  1 0 0 1 0 1  0 1 0 0 1 1  1 1 0 1 1 1 /\nZCORN\n"
    with pytest.raises(
        DeckError, match=r"v.grdecl:3: COORD: 2 values are not finite numbers within \+-1e\+100"
    ):
        _read(tmp_path, cube.replace("1 1 0 1 1 1", "1e200 1 0 1e200 1 1") + " 4*0 4*1 /\n")


def test_a_grid_too_large_to_process_is_refused_naming_the_deck(tmp_path, monkeypatch):
    """Read (12 cells x 160 bytes fit in 4 KiB), but not processed (12 x 1024 do not)."""
    import gridlib.memory
    from gridlib.cornerpoint.process import process_grdecl
    from gridlib.errors import InputError

    monkeypatch.setattr(gridlib.memory, "machine_memory", lambda: 4096)
    deck = _read(tmp_path, BOX)
    message = r"v.grdecl: 3 x 2 x 2 grid: 12 cells need about 1.1e-05 GiB to process .*; this machine has"
    with pytest.raises(InputError, match=message):
        process_grdecl(deck)
