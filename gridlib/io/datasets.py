"""netCDF files of xarray Datasets: opened with one message naming the file on failure, and
written atomically and losslessly compressed by one routine that every gridlib writer uses.

Compression (:data:`COMPRESSION`): every numeric variable is stored in chunks of about
1 MiB (rows of its first dimension) with Zstandard at level 1; where the netCDF4 library has
no Zstandard filter, with HDF5's shuffle and deflate (zlib) at level 1 instead. Both are
lossless: every value reads back bit for bit. Measured on a 1e6-cell grid with its geometry
(464 MiB raw) on the project's 2-core VM: Zstandard writes 237 MiB in about 2 s (raw: 0.5 to
1.9 s), deflate with shuffle 175 MiB in about 6 s. (netCDF4 applies its shuffle to deflate
only; the Blosc filter, which shuffles for Zstandard, fails on chunks it cannot shrink.)
Reading needs the filter: the netCDF4 wheels from PyPI (which xarray uses) carry it, as do
conda-forge's libnetcdf and netCDF-C >= 4.9 built with its plugins; h5py users add
``hdf5plugin``.

Every file opens lazily: ``xarray.open_dataset(path, chunks={})`` gives dask arrays in the
file's chunks, and reading a slice reads and decompresses only the chunks it touches.

Damage (:func:`open_artifact`): every chunked variable also carries HDF5's Fletcher32 checksum
(:data:`CHECKSUM`), verified by HDF5 on every read of a chunk. It does not cover everything:
HDF5's own metadata is checksummed in the netCDF-4 files written here (superblock version 2,
version-2 object headers, which hold the attributes), but the values of scalar and string
variables (contiguous storage, strings in the unchecksummed global heap), the chunk index
(a version-1 B-tree) and the dimension lists are not. Each file therefore also carries
``gridlib_digest``, a SHA-256 over all attributes (global and per variable), every variable's
name, dimensions, type and shape, and the values of the variables without Fletcher32
(:func:`uncovered_digest`): the few bytes a flip there would silently change (a changed
scalar or string reads back without any HDF5 error), and it costs only the reading of those
bytes. A damaged chunk index points at wrong bytes, which then fail Fletcher32. Together: a
changed byte stops HDF5, fails a checksum or lies where no reader looks; a reader never
gets wrong values. Files of older gridlib versions (no checksum, no digest) are read
unverified. Every read of a gridlib file goes through :func:`open_artifact`, which turns any
failure into one :func:`damaged` error naming the file.

Cost, measured on the project's 2-core VM (shared, so times are rough): Fletcher32 adds 4
bytes a chunk plus its filter message, the digest one attribute. The sample cases' 63 netCDF
files: 21.08 MB become 21.11 MB (+0.17 %, 0 to 2.4 kB a file), written in 2.2 s instead of
1.8 s (then with a second opening of each file for its digest, about 5 ms a file; the digest
is now written on the handle that wrote the file, before it closes). A 1e6-cell grid with
its geometry (464 MiB raw, 38 MiB on disk): +6 kB, the write time unchanged within the noise
(7.4 s), ``read_netcdf`` 3.4 s instead of 3.1 s.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from xarray.backends.common import ArrayWriter

from ..errors import InputError
from .atomic import atomic_path
from .shared_reads import kept_open


def _compression() -> dict[str, Any]:
    import netCDF4

    if getattr(netCDF4, "__has_zstandard_support__", False):
        return {"compression": "zstd", "complevel": 1}
    return {"zlib": True, "complevel": 1, "shuffle": True}


COMPRESSION: dict[str, Any] = _compression()
CHECKSUM: dict[str, Any] = {"fletcher32": True}  # HDF5 verifies it on every chunk it reads
CHUNK_BYTES = 1 << 20  # a lazy reader (chunks={}) reads and decompresses 1 MiB pieces
DIGEST = "gridlib_digest"  # global attribute: SHA-256 of what Fletcher32 leaves out
# HDF5's cache of each variable's chunks while a file is open: a few of gridlib's chunks. netCDF-C's
# default, 64 MiB a variable, kept up to 64 MiB of every variable written or read until the file
# closed: 2 GiB more memory for writing a 4e6-cell {case}.nc, no faster.
CHUNK_CACHE_BYTES = 4 * CHUNK_BYTES
# Files up to this size stay open for the rest of a run of a case's stages once opened
# (shared_reads.kept_open): what their handles may keep (HDF5's chunk caches) stays small.
KEPT_OPEN_BYTES = 8 << 20


@contextlib.contextmanager
def small_chunk_cache() -> Iterator[None]:
    """Files opened or created in the block give each variable a chunk cache of
    :data:`CHUNK_CACHE_BYTES` (netCDF-C's setting for the files it opens next, restored after)."""
    import netCDF4

    previous = netCDF4.get_chunk_cache()
    netCDF4.set_chunk_cache(CHUNK_CACHE_BYTES)
    try:
        yield
    finally:
        netCDF4.set_chunk_cache(*previous)


def damaged(path: str | os.PathLike, reason: str) -> InputError:
    """The one error of an artifact that cannot be read as written: it names the file, what is
    wrong, and what to do."""
    return InputError(f"{path}: damaged or incomplete ({reason}); delete it and rerun the workflow")


def read_json_artifact(path: str | os.PathLike) -> Any:
    """The JSON document of an artifact gridlib wrote (summary.json, responses.json); one
    :func:`damaged` error naming the file where it is missing or not UTF-8 JSON."""
    import json

    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise damaged(path, "no such file") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise damaged(path, f"not JSON: {exc}") from None


class _Unreadable(Exception):
    """A variable whose values cannot be read (the reason names it)."""


def _reason(exc: BaseException) -> str:
    """What went wrong, in words, for :func:`damaged` (no traceback, no repr)."""
    if isinstance(exc, _Unreadable):
        return str(exc)
    text = str(exc)
    if "HDF error" in text:
        return "HDF error: the file is cut short or its bytes are changed"
    if "Unknown file format" in text or "NetCDF: Not a valid ID" in text:
        return "not a netCDF-4 file, or its header is damaged"
    if isinstance(exc, KeyError):
        return f"{text.strip(chr(34) + chr(39))} is missing"
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


_STDERR_SWAP = threading.Lock()  # file descriptor 2 is redirected by one thread at a time
_held: tuple[int, Any] | None = None  # (process id, its temporary file) of _filters_quiet


def _held_file() -> Any:
    """This process's temporary file for :func:`_filters_quiet`, empty, made once (a forked
    child makes its own: a file shared with the parent would share its offset); call it under
    ``_STDERR_SWAP``."""
    global _held
    if _held is None or _held[0] != os.getpid():
        _held = (os.getpid(), tempfile.TemporaryFile())
    return _held[1]


@contextlib.contextmanager
def _filters_quiet() -> Iterator[None]:
    """Hold back what C code writes to standard error while HDF5 decodes chunks, and pass it
    on only if the read succeeds: the Zstandard filter prints "zstd: Data corruption detected"
    on a damaged chunk, which is then told once, by :func:`damaged`. (File descriptor 2 is the
    process's: what another thread writes meanwhile comes out after the read; reads in threads
    of one process take turns, as HDF5 has them do anyway, so that no thread restores another
    thread's redirection.) The text is held in one temporary file per process, emptied after
    each read (a new file per variable read cost 30 us, 220 reads per small case)."""
    with _STDERR_SWAP:
        held = _held_file()
        sys.stderr.flush()
        saved = os.dup(2)
        os.dup2(held.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            held.seek(0)
            text = held.read()
            held.seek(0)
            held.truncate()
    if text:
        sys.stderr.write(text.decode(errors="replace"))


def _values(variable: xr.Variable | xr.DataArray, name: str) -> np.ndarray:
    try:
        with _filters_quiet():
            return np.asarray(variable.values)
    except Exception as exc:  # netCDF4 raises RuntimeError/OSError for HDF5's errors
        if "HDF error" in str(exc):
            raise _Unreadable(
                f"HDF error on variable '{name}': its checksum fails or its data is cut short"
            ) from None
        raise _Unreadable(f"variable '{name}': {_reason(exc)}") from None


def read_variable(ds: xr.Dataset, name: str, kinds: str = "biuf", ndim: int | None = None) -> np.ndarray:
    """The values of variable ``name`` of an artifact opened by :func:`open_artifact`, checked:
    present, of a dtype kind in ``kinds`` (numpy's letters: b, i, u, f, U, O) and with ``ndim``
    dimensions where given; inside :func:`open_artifact` every failure becomes its one error."""
    if name not in ds.variables:
        raise _Unreadable(f"variable '{name}' is missing")
    values = _values(ds.variables[name], name)
    if values.dtype.kind not in kinds:
        raise _Unreadable(f"variable '{name}' has type {values.dtype}, expected one of kinds {kinds!r}")
    if ndim is not None and values.ndim != ndim:
        raise _Unreadable(f"variable '{name}' has {values.ndim} dimensions, expected {ndim}")
    return values


def load_all(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` (opened by :func:`open_artifact`) with every variable in memory, each read on its
    own so that an error names the variable."""
    for name, variable in ds.variables.items():
        _values(variable, str(name))
    return ds.load()


def uncovered_digest(nc: Any) -> str:
    """The SHA-256 (hex) of what Fletcher32 does not cover in the open ``netCDF4.Dataset``
    ``nc``: every attribute but :data:`DIGEST`, every variable's name, dimensions, dtype and
    shape, and the values of every variable stored without Fletcher32 (scalars, strings), read
    raw (no masking or scaling)."""
    sha = hashlib.sha256()

    def add(*items: object) -> None:
        for item in items:
            if isinstance(item, np.ndarray) and item.dtype.kind in "biuf":
                sha.update(f"{item.dtype.str}{item.shape}".encode())
                sha.update(np.ascontiguousarray(item).tobytes())
            else:
                sha.update(repr(np.asarray(item, dtype=object).tolist()).encode())
            sha.update(b"\0")

    nc.set_auto_maskandscale(False)
    for key in sorted(nc.ncattrs()):
        if key != DIGEST:
            add(key, nc.getncattr(key))
    for name in sorted(nc.variables):
        var = nc.variables[name]
        add(name, var.dimensions, str(var.dtype), var.shape)
        for key in sorted(var.ncattrs()):
            add(key, var.getncattr(key))
        if not (var.filters() or {}).get("fletcher32") and var.size:
            add(np.asarray(var[...]))
    return sha.hexdigest()


def _verify_digest(nc: Any) -> None:
    """Raise if the open ``netCDF4.Dataset`` ``nc``'s :data:`DIGEST` disagrees with its
    contents (none: older gridlib, nothing to verify)."""
    if DIGEST in nc.ncattrs() and str(nc.getncattr(DIGEST)) != uncovered_digest(nc):
        raise _Unreadable("digest mismatch: an attribute, a scalar or a string variable changed")


def _open_verified(path: str | os.PathLike, cache: bool | None = None) -> xr.Dataset:
    """The file at ``path`` opened once: its digest verified on the netCDF4 handle, which xarray
    then reads from (a second opening of the file for the digest cost as much as the check:
    3 ms a file, 30 openings per small case); ``cache``: xarray's (keep what is read)."""
    import netCDF4

    nc = netCDF4.Dataset(path, "r")
    try:
        _verify_digest(nc)
        return xr.open_dataset(xr.backends.NetCDF4DataStore(nc), cache=cache)
    except BaseException:
        nc.close()
        raise


def _open_kept(path: str | os.PathLike) -> xr.Dataset:
    """:func:`_open_verified` for a handle that several readers share: without xarray's cache,
    so that each read gives its reader values of its own."""
    return _open_verified(path, cache=False)


@contextlib.contextmanager
def _verified_dataset(path: Path) -> Iterator[xr.Dataset]:
    """The file at ``path`` opened and verified (:func:`_open_verified`) for the block; inside
    :func:`~gridlib.io.shared_reads.shared_reads` a file of at most :data:`KEPT_OPEN_BYTES`
    is opened once and kept open for the later readers (each gets a shallow copy)."""
    kept = kept_open(path, _open_kept, xr.Dataset.close, KEPT_OPEN_BYTES)
    if kept is not None:
        yield kept.copy(deep=False)
        return
    with _open_verified(path) as ds:  # closing the Dataset closes the file
        yield ds


def not_netcdf(path: str | os.PathLike, reason: str) -> InputError:
    """The error of a user's netCDF file (a surface, not an artifact) that cannot be read."""
    return InputError(f"{path}: cannot read as netCDF ({reason})")


@contextlib.contextmanager
def open_artifact(
    path: str | os.PathLike, *, error: Callable[[Path, str], InputError] = damaged
) -> Iterator[xr.Dataset]:
    """A gridlib netCDF file opened lazily for reading, its :data:`DIGEST` verified; inside the
    ``with`` block every error but an :class:`InputError` (an HDF error, a failed checksum, a
    missing variable from :func:`read_variable`, a KeyError, a wrong shape found by the reader)
    becomes the one error of :func:`damaged` naming ``path`` (or of ``error``)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        with small_chunk_cache(), _verified_dataset(p) as ds:
            ds.attrs.pop(DIGEST, None)  # integrity, not content: a copy gets its own
            yield ds
    except InputError:
        raise
    except Exception as exc:
        raise error(p, _reason(exc)) from None


def load_artifact(path: str | os.PathLike) -> xr.Dataset:
    """A gridlib artifact wholly in memory (the file is closed again); the one error of
    :func:`damaged` if it is unreadable, damaged or incomplete."""
    with open_artifact(path) as ds:
        return load_all(ds)


def load_dataset(path: str | os.PathLike) -> xr.Dataset:
    """A user's netCDF file wholly in memory (the file is closed again); an InputError naming
    the file if it is missing or unreadable (a gridlib digest it carries is verified)."""
    with open_artifact(path, error=not_netcdf) as ds:
        return load_all(ds)


def compressed_encoding(
    ds: xr.Dataset, encoding: Mapping[str, Mapping[str, Any]] | None = None
) -> dict[str, dict[str, Any]]:
    """``encoding`` (per variable) with :data:`COMPRESSION` and :data:`CHECKSUM` added to every
    non-empty numeric variable; strings, scalars and empty variables are stored as they are
    (the file's :data:`DIGEST` covers them)."""
    given = dict(encoding or {})
    result: dict[str, dict[str, Any]] = {}
    for name, variable in ds.variables.items():
        own = dict(given.get(str(name), {}))
        if variable.dtype.kind in "biuf" and variable.ndim > 0 and variable.size > 0:
            chunks = _chunks(variable.shape, variable.dtype.itemsize)
            own = {**COMPRESSION, **CHECKSUM, "chunksizes": chunks, **own}
        if own:
            result[str(name)] = own
    return result


def _chunks(shape: tuple[int, ...], itemsize: int) -> tuple[int, ...]:
    """About :data:`CHUNK_BYTES` per chunk: rows of the first dimension, the others whole."""
    row = itemsize * int(np.prod(shape[1:], dtype=np.int64))
    return (int(min(shape[0], max(1, CHUNK_BYTES // max(row, 1)))), *shape[1:])


def save_dataset(
    path: str | os.PathLike, ds: xr.Dataset, encoding: Mapping[str, Mapping[str, Any]] | None = None
) -> Path:
    """Write ``ds`` to ``path`` as netCDF-4, compressed losslessly (:data:`COMPRESSION`), with
    checksums (:data:`CHECKSUM`, :data:`DIGEST`), atomically: on any error no file is left at
    ``path``. ``encoding`` adds per-variable settings (fill values)."""
    if DIGEST in ds.attrs:
        ds = ds.copy()
        del ds.attrs[DIGEST]  # a dataset read back carries the old file's digest
    names = list(ds.variables)
    # xarray reads every variable not in memory before it writes any: from the first such one
    # on, the variables are appended one at a time, each read as it is written and let go
    first = next((i for i, name in enumerate(names) if not ds.variables[name]._in_memory), len(names))
    head = ds.drop_vars(names[first:])
    parts = [head, *(xr.Dataset({name: ds.variables[name]}) for name in names[first:])]
    with atomic_path(path) as tmp, small_chunk_cache():
        # One handle for the whole file, the digest written before it closes: reopening a
        # file of 30 to 90 variables to add the digest cost 10 to 20 ms (netCDF-C rewrites
        # every variable's metadata as it closes a file opened for writing), its digest 1 ms.
        store = xr.backends.NetCDF4DataStore.open(tmp, mode="w", format="NETCDF4")
        try:
            unlimited = ds.encoding.get("unlimited_dims")  # as to_netcdf: a file's, read back
            for k, part in enumerate(parts):
                writer = ArrayWriter()
                part.dump_to_store(
                    store,
                    writer=writer,
                    encoding=compressed_encoding(part, encoding),
                    unlimited_dims=unlimited if k == 0 else None,
                )
                writer.sync()  # chunked (dask) arrays are written here
            store.ds.setncattr(DIGEST, uncovered_digest(store.ds))
        finally:
            store.close()
    return Path(path)
