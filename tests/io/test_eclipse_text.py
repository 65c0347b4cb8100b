"""Writing ECLIPSE text (gridlib.io.eclipse_text): exact tokens, lines and blocks; record items."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gridlib.io import eclipse_text
from gridlib.io.eclipse_text import DeckError, Source, float_item, int_item, keyword_text, text_table


def test_text_table_rows_are_the_values_text_nul_padded():
    table = text_table([0.1, -0.0, 1e-300, 3.0], False)
    assert table.dtype == np.uint8 and table.shape == (4, 6)
    assert [bytes(row).rstrip(b"\0") for row in table] == [b"0.1", b"-0.0", b"1e-300", b"3.0"]
    assert (table[0, 3:] == 0).all()
    ints = text_table([7, -12, 0], True)
    assert ints.tolist() == [[55, 0, 0], [45, 49, 50], [48, 0, 0]]  # "7", "-12", "0"
    assert text_table([], False).shape == (0, 1)


def test_format_values_exact_text():
    v = np.array([1.0, 1.0, 1.0, 0.0, -0.0, np.nan, np.nan, 0.1, 2.5, 2.5, 7.0, 8.0, 9.0])
    assert b"".join(eclipse_text.format_values(v)) == b"3*1.0 0.0 -0.0 nan nan 0.1\n2*2.5 7.0 8.0 9.0\n"
    assert b"".join(eclipse_text.format_values(np.array([3.0, 3.0, -0.0, 0.0]), integer=True)) == b"2*3 2*0\n"
    assert b"".join(eclipse_text.format_values(np.zeros(0))) == b"\n"
    assert b"".join(eclipse_text.format_values(np.array([4, 4, 5], dtype=np.int32))) == b"2*4 5\n"


def test_keyword_text_exact():
    text = b"".join(keyword_text("ACTNUM", np.array([1, 1, 0]), "1: active", integer=True))
    assert text == b"ACTNUM\n-- 1: active\n2*1 0\n/\n\n"
    assert b"".join(keyword_text("PORO", np.array([0.25]))) == b"PORO\n0.25\n/\n\n"


def test_record_items():
    src = Source(Path("deck.grdecl"), b"MULTFLT\n 'F' x /\n")
    assert int_item(src, 9, "BOX", "12", "box") == 12
    assert float_item(src, 9, "MULTFLT", "2.5d-1", "multiplier") == 0.25
    assert float_item(src, 9, "MULTFLT", None, "multiplier") is None
    with pytest.raises(DeckError, match=r"deck.grdecl:2: MULTFLT: multiplier: 'x' is not a number"):
        float_item(src, 9, "MULTFLT", "x", "multiplier")
    with pytest.raises(DeckError, match=r"deck.grdecl:2: BOX: box: '1.5' is not an integer"):
        int_item(src, 9, "BOX", "1.5", "box")


def _plain_text(values: np.ndarray, integer: bool) -> bytes:
    """What format_values writes, one token at a time: runs of bit-identical values (equal ones
    with ``integer``; NaN never repeated) as n*v, as many per line as the widest token allows."""
    v = np.asarray(values, dtype=np.float64).ravel()
    keys = (v + 0.0 if integer else v).view(np.uint64)
    tokens, i = [], 0
    while i < v.size:
        j = i + 1
        while j < v.size and keys[j] == keys[i] and (integer or not np.isnan(v[i])):
            j += 1
        text = str(int(v[i])) if integer else repr(float(v[i]))
        tokens.append(f"{j - i}*{text}" if j - i > 1 else text)
        i = j
    per_line = max(1, min(6, 132 // (max(map(len, tokens)) + 1)))
    lines = [" ".join(tokens[k : k + per_line]) for k in range(0, len(tokens), per_line)]
    return ("\n".join(lines) + "\n").encode("ascii")


@pytest.mark.parametrize("integer", [False, True])
def test_format_values_in_small_blocks_is_the_plain_text(monkeypatch, integer):
    """Small blocks (values formatted 5 at a time, 12 runs a block) give the text of one go."""
    from gridlib.io import eclipse_text

    rng = np.random.default_rng(7)
    v = np.round(rng.normal(1000.0, 5.0, 402), 1)
    v[::3] = v[1::3]  # runs
    v[50:90] = -1.2345678901234567e-100  # long tokens: fewer per line
    if integer:
        v = np.round(v)
        v[5], v[6] = 0.0, -0.0
    else:
        v[10:13] = np.nan
        v[20], v[21] = 0.0, -0.0
    expected = _plain_text(v, integer)
    assert b"".join(eclipse_text.format_values(v, integer)) == expected
    monkeypatch.setattr(eclipse_text, "_TABLE_BLOCK", 5)
    monkeypatch.setattr(eclipse_text, "_CHUNK_RUNS", 12)
    assert b"".join(eclipse_text.format_values(v, integer)) == expected


def test_numbers_parsed_in_blocks_equal_one_piece(monkeypatch):
    """Big keywords are parsed a block of text at a time (cut between tokens): the values and
    the defaulted mask are those of the text in one piece, whatever the block size."""
    import numpy as np

    from gridlib.io import eclipse_text

    rng = np.random.default_rng(3)
    for _ in range(100):
        tokens = []
        for _ in range(int(rng.integers(1, 300))):
            r = rng.random()
            if r < 0.2:
                tokens.append(f"{rng.integers(1, 5)}*{rng.normal():.6g}")
            elif r < 0.25:
                tokens.append(f"{rng.integers(1, 5)}*")
            else:
                tokens.append(repr(float(rng.normal())))
        text = "".join(t + (" ", "\n", "  ", "\t")[rng.integers(0, 4)] for t in tokens).encode()
        whole = eclipse_text._fast_block(text, None, None)
        monkeypatch.setattr(eclipse_text, "_PARSE_BLOCK", int(rng.integers(1, 50)))
        blocks = eclipse_text._fast_numbers(text, None, None)
        assert whole.values.tobytes() == blocks.values.tobytes()
        assert (whole.defaulted is None) == (blocks.defaulted is None)
        if whole.defaulted is not None:
            assert np.array_equal(whole.defaulted, blocks.defaulted)
