"""The shared text table reader: lines, header, fields, numbers and their messages."""

from functools import partial

import numpy as np
import pytest

from gridlib.errors import InputError
from gridlib.io.text_table import (
    check_widths,
    data_rows,
    first_non_number,
    read_lines,
    split_fields,
    to_numbers,
)


def test_byte_order_mark_comments_blank_lines_and_header(tmp_path):
    f = tmp_path / "t.csv"
    f.write_bytes("\ufeffX;Y # names\n\n# only a comment\n1;0,5\n2;1,5\n".encode())
    table = data_rows(read_lines(f), split=split_fields)
    assert table.header == ["X", "Y"] and table.header_line == 1
    assert table.rows == [["1", "0.5"], ["2", "1.5"]] and table.lines == [4, 5]
    np.testing.assert_array_equal(
        to_numbers(f, table.rows, table.lines, ("x", "y")), [[1.0, 0.5], [2.0, 1.5]]
    )


def test_only_a_first_line_without_numbers_is_a_header():
    table = data_rows(["1 2", "a b"], split=str.split)
    assert table.header is None and table.rows == [["1", "2"], ["a", "b"]] and table.lines == [1, 2]
    assert data_rows(["a 1", "2 3"], split=str.split).header is None


def test_separators_are_the_readers_choice():
    assert split_fields("1, 2 3") == ["1", "2 3"]
    assert split_fields("1, 2 3", mixed=True) == ["1", "2", "3"]
    assert split_fields("'1';\"2,5\"", quotes=True) == ["1", "2.5"]
    assert split_fields("1;2,5", semicolons=False) == ["1;2", "5"]


def test_messages_name_file_line_and_column(tmp_path):
    f = tmp_path / "p.txt"
    rows, lines = [["1", "2", "3"], ["4", "n/a", "6"]], [3, 7]
    with pytest.raises(InputError, match=r"^.*p\.txt:7: column 5 \(y\): 'n/a' is not a number$"):
        to_numbers(f, [[r[0], r[1]] for r in rows], lines, ("x", "y"), columns=[2, 4])
    assert first_non_number(rows, lines, [2, 1]) == (7, 1, "n/a")
    with pytest.raises(InputError, match=r"p\.txt:3: x, y and z must be finite \(hint\)$"):
        to_numbers(f, [["1", "inf", "3"]], [3], ("x", "y", "z"), finite_hint=" (hint)")
    with pytest.raises(InputError, match=r"p\.txt:7: expected 3 columns \(x, y, z\), found 2$"):
        check_widths(f, [["1", "2", "3"], ["4", "5"]], lines, 3, " (x, y, z)")
    with pytest.raises(InputError, match=r"p\.txt: no such file$"):
        read_lines(f)
    f.write_bytes(b"\xff\xfe1 2")
    with pytest.raises(InputError, match=r"p\.txt: cannot read as text"):
        read_lines(f)


def test_a_partial_splitter_keeps_its_options():
    table = data_rows(["x y z", "1, 2 3"], split=partial(split_fields, mixed=True))
    assert table.rows == [["1", "2", "3"]]
