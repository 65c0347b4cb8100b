"""gridlib.pages: numpy's huge-page advice off inside the block, restored after it, nested or
from several threads; values never depend on it."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from gridlib.pages import _advice_setter, without_huge_pages

setter = _advice_setter()
pytestmark = pytest.mark.skipif(setter is None, reason="this numpy gives no huge-page advice")


def advice() -> bool:
    value = setter(True)
    setter(value)
    return bool(value)


@pytest.mark.parametrize("before", [True, False])
def test_off_inside_restored_after_nested_and_on_error(before):
    setter(before)
    try:
        with without_huge_pages():
            assert advice() is False
            with without_huge_pages():
                assert advice() is False
            assert advice() is False
        assert advice() is before
        with pytest.raises(ZeroDivisionError), without_huge_pages():
            1 / 0  # noqa: B018
        assert advice() is before
    finally:
        setter(True)


def test_overlapping_threads_restore_it_once_the_last_leaves():
    setter(True)
    inside, leave = threading.Barrier(3), threading.Event()
    seen = []

    def work():
        with without_huge_pages():
            inside.wait()
            leave.wait()
            seen.append(advice())

    threads = [threading.Thread(target=work) for _ in range(2)]
    for t in threads:
        t.start()
    inside.wait()  # both inside
    assert advice() is False
    leave.set()
    for t in threads:
        t.join()
    assert seen == [False, False]  # each inside while the other is (or was) too
    assert advice() is True


def test_same_values_with_and_without_the_advice():
    x = np.arange(1 << 20, dtype=np.float64)
    with without_huge_pages():
        y = np.sqrt(x) * 3.0 + 1.0
    assert np.array_equal(y, np.sqrt(x) * 3.0 + 1.0)
