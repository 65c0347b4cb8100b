"""xarray without importing dask until dask is used: for short processes that only read and
write numpy-backed datasets (a workflow job, the ``gridlib`` command).

With dask installed (a gridlib dependency, for ``xarray.open_dataset(path, chunks={})``),
xarray asks three questions about dask that import it, though the process never makes a dask
array:

* is this data a dask array? (``array_type("dask")`` of ``xarray.namedarray.pycompat``, asked
  when xarray makes its first Variable: it imports ``dask.array``, and with it ``scipy.sparse``
  and ``scipy.fft``);
* is this array a dask collection? (``is_dask_collection`` of ``xarray.namedarray.utils``,
  asked of every variable it writes: it imports ``dask.base``);
* which dask scheduler is active? (``get_dask_scheduler`` of ``xarray.backends.locks``, also
  bound in ``xarray.backends.writers``, asked whenever it writes a netCDF file).

Together 0.2 s of CPU in every process, as much as a small stage job's own work (measured on
the project's 2-core VM: 0.21 s less per job of the sample workflow, 1.0 s -> 0.8 s).
:func:`defer_dask_import` answers them without importing dask for as long as dask is not
imported, and as before once it is. The answers are the same: no object is a dask array while
``dask.array`` is not imported; an object without ``__dask_graph__`` is no dask collection (dask's
own first test); without dask no dask scheduler is active, and xarray takes ``None`` as dask's
default, threaded one (the same lock, no closing of the file after each write). It replaces
private names of xarray, so gridlib's entry points call it (the Snakemake rules' stage script,
``gridlib.cli``), never an import; with an xarray that lacks those names it changes nothing and
dask is imported as before.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

__all__ = ["defer_dask_import"]


class _DaskArrayType:
    """Stands in for xarray's record of the ``dask`` duck-array module: its ``type`` is
    ``(dask.array.Array,)`` once ``dask.array`` is imported, ``()`` (no object is one) before;
    its other attributes import dask and answer as xarray's own record would."""

    @property
    def type(self) -> tuple[type, ...]:
        module = sys.modules.get("dask.array")
        return (module.Array,) if module is not None else ()

    def __getattr__(self, name: str) -> Any:
        from xarray.namedarray.pycompat import DuckArrayModule

        return getattr(DuckArrayModule("dask"), name)


def _scheduler_when_imported(get_scheduler: Callable[..., str | None]) -> Callable[..., str | None]:
    """xarray's ``get_dask_scheduler``, answering None (no dask scheduler) while dask is not
    imported."""

    def get_dask_scheduler(get: Any = None, collection: Any = None) -> str | None:
        if "dask" not in sys.modules:
            return None
        return get_scheduler(get, collection)

    get_dask_scheduler.__wrapped__ = get_scheduler
    return get_dask_scheduler


def _collection_when_imported(is_dask_collection: Callable[[object], bool]) -> Callable[[object], bool]:
    """xarray's ``is_dask_collection``, answering False without importing dask for an object
    without ``__dask_graph__`` (as dask's own test does first: numpy arrays, scalars)."""

    def is_collection(x: object) -> bool:
        if "dask" not in sys.modules and (isinstance(x, type) or not hasattr(x, "__dask_graph__")):
            return False
        return is_dask_collection(x)

    is_collection.__wrapped__ = is_dask_collection
    return is_collection


def defer_dask_import() -> bool:
    """Let xarray in this process import dask only when dask is used (see the module's
    docstring). True if it does so now; False if dask is imported already (nothing to save) or
    this xarray lacks the names replaced. Calling it again changes nothing more."""
    if "dask" in sys.modules:
        return False
    try:
        from xarray.backends import locks, writers
        from xarray.namedarray import pycompat, utils
    except ImportError:
        return False
    cache = getattr(pycompat, "_cached_duck_array_modules", None)
    patches = [(locks, "get_dask_scheduler", _scheduler_when_imported)]
    patches += [(writers, "get_dask_scheduler", _scheduler_when_imported)]
    patches += [(utils, "is_dask_collection", _collection_when_imported)]
    if not isinstance(cache, dict) or not all(callable(getattr(m, n, None)) for m, n, _ in patches):
        return False
    cache.setdefault("dask", _DaskArrayType())
    for module, name, wrap in patches:
        if not hasattr(getattr(module, name), "__wrapped__"):
            setattr(module, name, wrap(getattr(module, name)))
    return True
