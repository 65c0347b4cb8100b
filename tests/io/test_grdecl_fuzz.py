"""Bad decks by the hundred: seeded mutations of real and small decks.

Every mutated deck must either be read (and then processed, or refused with
an InputError) or raise the reader's DeckError naming the file (and, for
errors inside the text, the line) -- never another exception, never a hang.
"""

from __future__ import annotations

import re
import time

import numpy as np
import pytest

from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import GridError, InputError
from gridlib.io.grdecl import DeckError, read_grdecl

SMALL = b"""RUNSPEC
TITLE
 fuzz base
DIMENS
 3 2 2 /
METRIC
GRID
COORD
 0 0 0 0 0 10  1 0 0 1 0 10  2 0 0 2 0 10  3 0 0 3 0 10
 0 1 0 0 1 10  1 1 0 1 1 10  2 1 0 2 1 10  3 1 0 3 1 10
 0 2 0 0 2 10  1 2 0 1 2 10  2 2 0 2 2 10  3 2 0 3 2 10 /
ZCORN
 24*1 24*2 24*2 24*3.5 /
ACTNUM
 5*1 0 6*1 /
PORO -- fraction
 12*0.25 /
BOX
 1 2 1 1 1 2 /
PERMX
 4*100 /
ENDBOX
EQUALS
 'NTG' 0.8 /
 PERMY 50 1 3 1 2 1 1 /
/
MULTIPLY
 'PORO' 0.5 1* 1* 1* 1* 2 2 /
/
FAULTS
 'F1' 2 2 1 2 1 2 X /
/
MULTFLT
 'F1' 0.1 /
/
PINCH
 0.01 /
PROPS
"""

TOKENS = [
    b"/", b"*", b"3*", b"2*0.1", b"1e999999", b"99999999999999999*1", b"'", b"--", b"-- /", b"PORO",
    b"ZCORN", b"COORD", b"INCLUDE", b"\x00\xff\xfe", b"abc", b"1.2.3", b"-", b"+", b"1*2*3", b"BOX",
    b"ENDBOX", b"EQUALS", b"\n", b"'x' /", b"0*1", b"-3*1", b"nan", b"1D5", b"SPECGRID", b"DIMENS",
    b"'unterminated", b"\t", b"\r\n", b"GDFILE", b"COPY", b"TOPS", b"DX", b"FAULTS", b"ACTNUM", b"-1e20",
]  # fmt: skip


def mutate(base: bytes, rng: np.random.Generator) -> bytes:
    data = bytearray(base)
    for _ in range(int(rng.integers(1, 4))):
        kind = int(rng.integers(0, 8))
        n = len(data)
        at = int(rng.integers(0, max(n, 1)))
        if kind == 0:  # truncate
            del data[at:]
        elif kind == 1:  # delete a span
            del data[at : at + int(rng.integers(1, 60))]
        elif kind in (2, 3):  # insert a token, with or without spaces
            tok = TOKENS[int(rng.integers(0, len(TOKENS)))]
            data[at:at] = (b" " + tok + b" ") if kind == 2 else tok
        elif kind == 4:  # duplicate or drop a line
            lines = bytes(data).split(b"\n")
            i = int(rng.integers(0, len(lines)))
            lines.insert(i, lines[i]) if rng.random() < 0.5 else lines.pop(i)
            data = bytearray(b"\n".join(lines))
        elif kind == 5:  # swap two lines
            lines = bytes(data).split(b"\n")
            i, j = rng.integers(0, len(lines), 2)
            lines[i], lines[j] = lines[j], lines[i]
            data = bytearray(b"\n".join(lines))
        elif kind == 6:  # flip bytes
            for p in rng.integers(0, max(n, 1), int(rng.integers(1, 5))):
                if p < len(data):
                    data[p] = int(rng.integers(0, 256))
        else:  # replace a number by junk
            numbers = list(re.finditer(rb"\d+(?:\.\d+)?", bytes(data)))
            if numbers:
                m = numbers[int(rng.integers(0, len(numbers)))]
                data[m.start() : m.end()] = TOKENS[int(rng.integers(0, len(TOKENS)))]
    return bytes(data)


def check_one(path, data: bytes) -> str:
    path.write_bytes(data)
    start = time.perf_counter()
    try:
        deck = read_grdecl(path)
    except DeckError as exc:
        message = str(exc)
        assert message.startswith(str(path)), message
        return "error"
    finally:
        assert time.perf_counter() - start < 5.0, "the reader hung"
    try:
        process_grdecl(deck)
    except (InputError, GridError):
        return "refused"
    return "ok"


@pytest.mark.parametrize("base_name", ["small", "spe1", "seed"])
def test_mutated_decks_are_read_or_refused_clearly(tmp_path, decks_dir, base_name):
    base = {
        "small": SMALL,
        "spe1": (decks_dir / "spe1" / "SPE1CASE2_ACTNUM.DATA").read_bytes(),
        "seed": (decks_dir / "seed" / "simple_grdecl_4x2x3_flat_drop012.grdecl").read_bytes(),
    }[base_name]
    assert check_one(tmp_path / "base.DATA", base) == "ok"
    rng = np.random.default_rng(12345)
    outcomes = {"ok": 0, "error": 0, "refused": 0}
    for case in range(200):
        data = mutate(base, rng)
        try:
            outcomes[check_one(tmp_path / "case.DATA", data)] += 1
        except Exception as exc:  # report the deck that broke the reader
            (tmp_path / f"failing_{case}.DATA").write_bytes(data)
            raise AssertionError(f"case {case}: {type(exc).__name__}: {exc}") from exc
    # the mutations do hit both ways: decks the reader refuses, decks it reads (some of which the
    # processor then refuses clearly: e.g. two COORD lines swapped make pillars that cross)
    assert outcomes["error"] > 20 and outcomes["ok"] + outcomes["refused"] > 5


def test_binary_garbage_is_refused(tmp_path):
    rng = np.random.default_rng(3)
    for _ in range(50):
        data = rng.integers(0, 256, int(rng.integers(1, 3000)), dtype=np.uint8).tobytes()
        assert check_one(tmp_path / "junk.grdecl", data) in ("error", "ok")
