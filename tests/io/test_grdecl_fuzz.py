"""Bad decks by the hundred: seeded mutations of real and small decks.

Every mutated deck must either be read and processed up to its grid and transmissibilities, or
be refused by one DeckError, InputError or GridError whose message names the deck file (and,
for errors inside the text, the line) -- never another exception, never a hang (each deck gets
a few seconds of CPU time: an alarm stops one that takes longer).
"""

from __future__ import annotations

import contextlib
import re
import signal
from pathlib import Path

import numpy as np
import pytest

from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import GridError, InputError
from gridlib.io.grdecl import DeckError, read_grdecl
from gridlib.transmissibility.deck_connections import deck_transmissibility

SECONDS_PER_DECK = 5.0  # of CPU time
WAITING_FACTOR = 20  # wall time allowed per CPU second: a loaded machine (load 20 on 2 cores)

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
PERMX
 12*50 /
BOX
 1 2 1 1 1 2 /
PERMX
 4*100 /
ENDBOX
EQUALS
 'NTG' 0.8 /
 PERMY 50 /
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
    b"10000000000*0", b"1000000000*10", b"inf", b"-inf", b"-0.5", b"INCLUDE\n 'loop.inc' /", b"MULTX",
    b"PINCH\n -1 /", b"MINPV\n -5 /", b"EQUALS\n 'FOOBAR' 1 /\n/", b"DIMENS\n 10000 10000 100 /",
]  # fmt: skip


def mutate(base: bytes, rng: np.random.Generator, kinds: tuple[int, ...] = tuple(range(9))) -> bytes:
    """1 to 3 mutations of ``base``, each of one of ``kinds`` (0-8, below)."""
    data = bytearray(base)
    for _ in range(int(rng.integers(1, 4))):
        kind = kinds[int(rng.integers(0, len(kinds)))]
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
        elif kind == 7:  # replace a number by junk
            numbers = list(re.finditer(rb"\d+(?:\.\d+)?", bytes(data)))
            if numbers:
                m = numbers[int(rng.integers(0, len(numbers)))]
                data[m.start() : m.end()] = TOKENS[int(rng.integers(0, len(TOKENS)))]
        else:  # a value made negative, NaN or huge
            numbers = list(re.finditer(rb"(?<![\w.*])\d+(?:\.\d+)?(?![\w.*])", bytes(data)))
            if numbers:
                m = numbers[int(rng.integers(0, len(numbers)))]
                new = [b"-" + m.group(), b"nan", m.group() + b"e300", b"0"][int(rng.integers(0, 4))]
                data[m.start() : m.end()] = new
    return bytes(data)


@contextlib.contextmanager
def deadline(seconds: float):
    """An AssertionError if the block computes for longer than ``seconds`` of CPU time (a hang
    that spins), or waits for longer than ``WAITING_FACTOR`` times that (a hang that blocks).
    CPU time, not wall time, so that a machine busy with other work does not look like a hang."""

    def expired(signum, frame):
        if signum == signal.SIGPROF:
            raise AssertionError(f"no answer within {seconds} s of CPU time: a hang")
        raise AssertionError(f"no answer within {seconds * WAITING_FACTOR} s: a hang (blocked)")

    timers = {signal.SIGPROF: signal.ITIMER_PROF, signal.SIGALRM: signal.ITIMER_REAL}
    previous = {signum: signal.signal(signum, expired) for signum in timers}
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, seconds * WAITING_FACTOR)
    try:
        yield
    finally:
        for signum, timer in timers.items():
            signal.setitimer(timer, 0)
            signal.signal(signum, previous[signum])


def check_one(path, data: bytes) -> str:
    """Read ``data`` as the deck ``path``, process it and compute its transmissibilities: 'ok',
    or how it was refused (always naming the deck file)."""
    path.write_bytes(data)
    with deadline(SECONDS_PER_DECK):
        try:
            deck = read_grdecl(path)
        except DeckError as exc:
            assert str(exc).startswith(str(path.parent)), str(exc)  # the deck or a file it includes
            return "error"
        try:
            cp = process_grdecl(deck)
            has_rock = "PERMX" in deck.cell_data
            if has_rock:
                deck_transmissibility(deck, cp)
        except (InputError, GridError) as exc:
            assert str(path) in str(exc), str(exc)
            return "refused"
    return "ok" if has_rock else "grid"


BASES = {  # name: (deck, mutants); the seed and FIVE_PINCH decks are grids alone (no PERMX)
    "small": ("small", 100),
    "spe1": ("spe1/SPE1CASE2_ACTNUM.DATA", 25),
    "seed": ("seed/simple_grdecl_4x2x3_flat_drop012.grdecl", 100),
    "five_pinch": ("pinch/FIVE_PINCH.DATA", 120),
}


@pytest.mark.parametrize("base_name", list(BASES))
def test_mutated_decks_are_read_or_refused_clearly(tmp_path, decks_dir, base_name):
    relpath, count = BASES[base_name]
    base = SMALL if relpath == "small" else (decks_dir / relpath).read_bytes()
    (tmp_path / "loop.inc").write_bytes(b"INCLUDE\n 'loop.inc' /\n")  # an INCLUDE cycle
    assert check_one(tmp_path / "base.DATA", base) == ("ok" if base_name in ("small", "spe1") else "grid")
    rng = np.random.default_rng(12345)
    outcomes = {"ok": 0, "grid": 0, "error": 0, "refused": 0}
    for case in range(count):
        data = mutate(base, rng)
        try:
            outcomes[check_one(tmp_path / "case.DATA", data)] += 1
        except Exception as exc:  # report the deck that broke the reader
            (tmp_path / f"failing_{case}.DATA").write_bytes(data)
            raise AssertionError(f"case {case}: {type(exc).__name__}: {exc}") from exc
    # the mutations do hit both ways: decks the reader refuses, decks it reads (some of which the
    # processor then refuses clearly: e.g. two COORD lines swapped make pillars that cross); the
    # seed and FIVE_PINCH decks are mostly COORD and ZCORN, which nearly every mutation breaks
    assert outcomes["error"] > count // 10 and outcomes["ok"] + outcomes["grid"] + outcomes["refused"] >= 3


@pytest.mark.parametrize("base_name", ["small", "spe1", "five_pinch"])
def test_mutated_values_reach_the_grid_or_are_refused_clearly(tmp_path, decks_dir, base_name):
    """Mutants whose syntax holds, values made negative, NaN, 1e300 or 0: most are read, so
    the processing and the transmissibilities meet them."""
    relpath = BASES[base_name][0]
    base = SMALL if relpath == "small" else (decks_dir / relpath).read_bytes()
    rng = np.random.default_rng(777)
    outcomes = {"ok": 0, "grid": 0, "error": 0, "refused": 0}
    count = 20 if base_name == "spe1" else 40
    for _ in range(count):
        outcomes[check_one(tmp_path / "case.DATA", mutate(base, rng, kinds=(8,)))] += 1
    assert outcomes["ok"] + outcomes["grid"] + outcomes["refused"] >= count // 5, outcomes


def test_mutated_sample_deck_spe9(tmp_path):
    """The sample deck of config/decks (SPE9, 9000 cells): a few mutants of its DATA file, whose
    INCLUDEs stay as they are."""
    source = Path(__file__).parents[2] / "config" / "decks" / "spe9"
    for name in ("SPE9.GRDECL", "PERMVALUES.DATA"):
        (tmp_path / name).symlink_to(source / name)
    base = (source / "SPE9_CP.DATA").read_bytes()
    rng = np.random.default_rng(9)
    outcomes = [check_one(tmp_path / "SPE9_CP.DATA", mutate(base, rng)) for _ in range(8)]
    assert set(outcomes) <= {"ok", "error", "refused"} and "error" in outcomes


def test_binary_garbage_is_refused(tmp_path):
    rng = np.random.default_rng(3)
    for _ in range(50):
        data = rng.integers(0, 256, int(rng.integers(1, 3000)), dtype=np.uint8).tobytes()
        assert check_one(tmp_path / "junk.grdecl", data) in ("error", "ok")
