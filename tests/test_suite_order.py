"""The order in which make test (pytest-xdist, --dist loadfile) starts the test modules: the
longest first (tests/conftest.py), so that none of them is left to run alone at the end."""

from __future__ import annotations

from pathlib import Path

from conftest import LONGEST_FIRST

TESTS = Path(__file__).parent


def test_the_longest_modules_exist():
    """A renamed or moved module would silently lose its place at the front."""
    assert [m for m in LONGEST_FIRST if not (TESTS / m).is_file()] == []
    assert len(set(LONGEST_FIRST)) == len(LONGEST_FIRST)


def test_xdist_keeps_the_collection_order(pytestconfig):
    """pytest-xdist 3 sorts loadfile's modules by their number of tests unless told not to."""
    assert getattr(pytestconfig.option, "loadscopereorder", False) is False


def test_the_longest_modules_come_first_in_their_order(request):
    items = request.session.items
    first = [m for m in LONGEST_FIRST if any(i.path == TESTS / m for i in items)]
    seen = []
    for item in items:
        module = item.path.relative_to(TESTS).as_posix() if item.path.is_relative_to(TESTS) else None
        if module not in seen:
            seen.append(module)
    assert seen[: len(first)] == first
