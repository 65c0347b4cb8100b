"""gridlib's version, as installed (``0.0.0+unknown`` in a source tree without installation)."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("gridlib")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"
