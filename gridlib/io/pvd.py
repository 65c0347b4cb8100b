"""Time series of one grid for ParaView: a ``.pvd`` collection of ``.vtu`` files, one per time.

A PVD file (VTK's ``Collection``, read by ParaView, VTK's ``vtkPVDReader`` and pyvista's
``PVDReader``) lists data sets with their ``timestep``; ParaView plays them as one object
over time (its time toolbar shows the ``timestep`` values). :func:`write_vtu_series` writes

* ``<folder>/<folder>_<index:04d>.vtu`` for every step, ``<folder>`` being the PVD path
  without its suffix (``flow/x_flow.pvd`` -> ``flow/x_flow/x_flow_0003.vtu``): the grid
  (:func:`gridlib.io.vtu.write_vtu`, z as elevation) with that step's cell arrays;
* the PVD listing them, relative to its own folder, with their times.

Every file holds the same grid, laid out once (:func:`gridlib.io.vtu.vtu_geometry`) and only
the cell arrays are compressed per step. The step folder is written beside its target and
renamed into place whole (a folder of an earlier run with other steps goes), then the PVD is
written atomically: the PVD never lists a missing file.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterable, Sequence
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

import numpy as np

from ..errors import GridError
from ..grid import Grid
from .atomic import atomic_path
from .vtu import vtu_geometry, write_vtu

__all__ = ["write_pvd", "write_vtu_series"]


def write_pvd(path: str | os.PathLike, datasets: Sequence[tuple[float, str]], *, note: str = "") -> Path:
    """Write a PVD collection (atomically): ``datasets`` are ``(time, file)``, ``file`` relative
    to the PVD's folder (POSIX separators), times strictly increasing; ``note`` goes in an XML
    comment (e.g. the arrays' units).

    >>> import tempfile, os
    >>> steps = [(0.0, "s/s_0000.vtu"), (90.0, "s/s_0001.vtu")]
    >>> p = write_pvd(os.path.join(tempfile.mkdtemp(), "s.pvd"), steps)
    >>> print(open(p).read().strip())  # doctest: +ELLIPSIS
    <?xml version="1.0"?>
    <VTKFile type="Collection" version="0.1" byte_order="LittleEndian">
    <Collection>
    <DataSet timestep="0.0" group="" part="0" file="s/s_0000.vtu"/>
    <DataSet timestep="90.0" group="" part="0" file="s/s_0001.vtu"/>
    </Collection>
    </VTKFile>
    """
    times = np.array([float(t) for t, _ in datasets])
    _check_times(path, times)
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">']
    if note:
        lines.append(f"<!-- {escape(note).replace('--', '- -')} -->")
    lines.append("<Collection>")
    lines += [
        f'<DataSet timestep="{t!r}" group="" part="0" file={quoteattr(str(f))}/>'
        for t, f in zip(times.tolist(), (f for _, f in datasets), strict=True)
    ]
    lines += ["</Collection>", "</VTKFile>"]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return Path(path)


def write_vtu_series(
    path: str | os.PathLike,
    grid: Grid,
    steps: Iterable[tuple[int, float, dict[str, np.ndarray]]],
    *,
    note: str = "",
    compress: bool = True,
) -> Path:
    """Write the PVD ``path`` and one VTU of ``grid`` per step (see the module docstring).

    ``steps``: ``(index, time, cell_data)``, consumed one at a time (a generator holds one
    step's arrays in memory), times increasing; ``index`` numbers the file. Returns ``path``.
    """
    pvd = Path(path)
    folder = pvd.with_suffix("")
    folder.parent.mkdir(parents=True, exist_ok=True)
    geometry = vtu_geometry(grid, compress=compress)
    work = Path(tempfile.mkdtemp(prefix=f".{folder.name}.", suffix=".partial", dir=folder.parent))
    try:
        datasets = []
        for index, time, data in steps:
            _check_times(path, [*(t for t, _ in datasets[-1:]), float(time)])
            name = f"{folder.name}_{int(index):04d}.vtu"
            write_vtu(work / name, grid, data, compress=compress, geometry=geometry)
            datasets.append((float(time), f"{folder.name}/{name}"))
        _replace_folder(work, folder)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    return write_pvd(pvd, datasets, note=note)


def _check_times(path: str | os.PathLike, times) -> None:
    times = np.asarray(times, dtype=np.float64)
    if not np.isfinite(times).all() or (np.diff(times) <= 0).any():
        raise GridError(f"{path}: write_pvd: the times must be finite and increasing, got {times.tolist()}")


def _replace_folder(new: Path, target: Path) -> None:
    """Rename the folder ``new`` to ``target``, an existing ``target`` moved aside and removed."""
    os.chmod(new, 0o777 & ~_umask())  # mkdtemp makes it 0700: give the usual mode
    if target.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old", dir=target.parent))
        os.replace(target, old / target.name)
        os.replace(new, target)
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.replace(new, target)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
