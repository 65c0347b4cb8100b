"""Exceptions raised by gridlib.

Every user-facing failure is one of these, with a message that names the object
at fault (the file, key, keyword, line, cell or face) and what was expected.
"""

from __future__ import annotations


class GridError(ValueError):
    """A grid, or the input to a grid builder, is invalid.

    Subclasses :class:`ValueError` so that callers who only care about "bad
    input" can catch that.
    """


class InputError(ValueError):
    """A user input file (case YAML, deck, surface) is invalid.

    The message names the file and the key, keyword or line.
    """
