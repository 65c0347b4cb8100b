"""What every stage shares: logging to the rule's log file (notes also on the console), and
files with provenance.

Every output is written atomically (a temporary file renamed into place, so a
failed stage leaves nothing) and carries the case's provenance: gridlib
version, case name, case file and its SHA-256, seed.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from ..errors import GridError, InputError
from ..threads import ENV
from .job_usage import JobUsage, Meter

log = logging.getLogger("gridlib.stages")


def run_logged(
    log_file: str | os.PathLike,
    stage: Callable[..., None],
    *args: Any,
    threads: int | None = None,
    outputs: Iterable[str | os.PathLike] = (),
    name: str | None = None,
    label: str | None = None,
) -> None:
    """Run a stage with gridlib's log (and any traceback) going to ``log_file``, on at most
    ``threads`` threads (a rule's ``threads``; see :mod:`gridlib.threads`); at the end the log
    gets the stage's wall time, its peak memory and the size of each of ``outputs``. ``name``
    names the stage in the log (default: the function's name). The thread count in the
    environment is restored at the end.

    The console (stderr, which Snakemake shows for a job) gets each note and warning once, as it
    is logged, prefixed ``gridlib: <label>:`` (``label``, e.g. the case and the stage; default
    ``name``). A failure is one line there: an InputError or GridError its message, anything
    else (a bug) its type and message and the log file, which holds the traceback; both end the
    process with status 1 (SystemExit)."""
    name = name or stage.__name__
    previous = os.environ.get(ENV)
    if threads is not None:
        os.environ[ENV] = str(max(1, int(threads)))
    Path(log_file).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_file, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
    console = notes_on_console(label or name)
    root = logging.getLogger("gridlib")
    root.addHandler(handler)
    root.addHandler(console)
    root.setLevel(logging.INFO)
    propagate, root.propagate = root.propagate, False  # a host's own handlers (Snakemake's) print none twice
    start = time.perf_counter()
    meter = Meter()
    try:
        stage(*args)
        _log_costs(root, name, time.perf_counter() - start, meter.stop(), outputs)
    except (InputError, GridError) as exc:  # the user's input: one message, no traceback
        root.error("%s failed: %s", name, exc)
        _console_line(f"gridlib: {exc}")
        raise SystemExit(1) from None
    except Exception as exc:  # a bug: the traceback in the log, one line on the console
        root.error("%s failed: %s", name, exc, exc_info=True)
        _console_line(
            f"gridlib: {label or name} failed: {type(exc).__name__}: {exc} (an error in gridlib; "
            f"the traceback is in {log_file})"
        )
        raise SystemExit(1) from None
    finally:
        root.removeHandler(handler)
        root.removeHandler(console)
        root.propagate = propagate
        handler.close()
        if previous is None:
            os.environ.pop(ENV, None)
        else:
            os.environ[ENV] = previous


def _console_line(text: str) -> None:
    """``text`` and its line end on stderr in one write: a message of several lines printed
    with ``print`` reaches a line-buffered stderr as two writes (its lines, then the last line
    end), and a line another process writes to the same console in between would end up on
    the message's last line."""
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def notes_on_console(label: str) -> logging.Handler:
    """A handler printing each note (a message ``note: ...``) and warning once on stderr,
    prefixed ``gridlib: <label>:``; add it to the ``gridlib`` logger (:func:`run_logged`, the
    ``gridlib build`` command)."""
    console = logging.StreamHandler(sys.stderr)
    console.setFormatter(logging.Formatter(f"gridlib: {label}: %(message)s"))
    console.addFilter(_NotesOnce())
    return console


class _NotesOnce(logging.Filter):
    """Passes notes (messages starting ``note:``) and warnings, each text once: a note that two
    stages of one run both log reaches the console once (each stage's log keeps its own)."""

    def __init__(self) -> None:
        super().__init__()
        self._seen: set[str] = set()

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        is_note = record.levelno == logging.WARNING or (
            record.levelno == logging.INFO and text.startswith("note:")
        )
        if not is_note or text in self._seen:
            return False
        self._seen.add(text)
        return True


def _size(path: Path) -> int:
    """A file's bytes, or those of the files in a folder (a directory artifact)."""
    if path.is_dir():
        return sum(f.stat().st_size for f in path.rglob("*") if f.is_file())
    return path.stat().st_size


def _log_costs(
    log: logging.Logger, name: str, seconds: float, usage: JobUsage, outputs: Iterable[str | os.PathLike]
) -> None:
    """What a stage cost: wall time, CPU time, peak resident memory (of this process while the
    stage ran: :mod:`gridlib.stages.job_usage`), and the bytes it wrote."""
    sizes = [(Path(p), _size(Path(p))) for p in outputs if Path(p).exists()]
    peak = "" if usage.max_rss_mib is None else f", peak memory {usage.max_rss_mib:.0f} MiB"
    log.info("%s: %.1f s, %.1f s of CPU%s", name, seconds, usage.cpu_seconds, peak)
    for path, size in sizes:
        log.info("  %s: %.1f MiB", path.name, size / 2**20)
