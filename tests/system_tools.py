"""What a test does when a system program it runs against (OPM Flow, SLURM) is missing.

``make test`` installs them (tests/system_tools.sh), so a missing program is a failure that
names it; ``GRIDLIB_SKIP_MISSING_TOOLS=1`` is the explicit way to run the rest without them,
and then the tests that need them skip, saying why.
"""

from __future__ import annotations

import os

import pytest

OPT_OUT = "GRIDLIB_SKIP_MISSING_TOOLS"


def missing_tool(reason: str) -> None:
    """Fail the test with ``reason`` (and how to install), or skip it if the user opted out."""
    if os.environ.get(OPT_OUT) == "1":
        pytest.skip(f"{reason} ({OPT_OUT}=1)")
    pytest.fail(
        f"{reason}: `make test` installs it (tests/system_tools.sh); {OPT_OUT}=1 skips the tests "
        "that need it",
        pytrace=False,
    )
