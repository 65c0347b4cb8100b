"""What a job's own process used: CPU seconds, peak resident memory, bytes read and written.

A workflow job's benchmark file (Snakemake's ``benchmark:``) and a stage's log report these. In
a local run a job does not run in a process of its own that Snakemake could watch: a stage job
runs in a child of the run's job server, a study's variant in a warm worker process that builds
one variant after another (:mod:`gridlib.stages.job_server`, :mod:`gridlib.stages.workers`). So
the job measures itself, exactly and at no cost, from what the kernel counts for its process:

* CPU: user + system seconds of this process and of the processes it started and waited for
  (``getrusage``; e.g. OPM Flow run by a stage);
* peak memory: the process's resident set high-water mark (``VmHWM``), reset at the start of
  the measurement (Linux's ``/proc/self/clear_refs``), so that a warm worker's second variant
  is not charged with its first one's peak; it includes the pages the process shares with the
  job server or fork server it was forked from, as far as it touches them. Where the mark
  cannot be reset it is the process's peak so far;
* bytes read from and written to storage (``/proc/self/io``: ``read_bytes``, ``write_bytes``,
  the page cache's writes included), None where the system does not count them.

Measurements nest (a stage inside a variant, a variant inside a worker's job): an inner
measurement's reset does not lose the outer one's peak. The peak is the process's, so two
measurements running at once in one process's threads both see it.

>>> with Meter() as meter:
...     block = bytearray(32 << 20)  # 32 MiB, touched
>>> meter.usage.max_rss_mib >= 32, meter.usage.cpu_seconds >= 0
(True, True)
"""

from __future__ import annotations

import resource
import threading
from dataclasses import dataclass

__all__ = ["JobUsage", "Meter", "usage_of_process"]

MIB = float(1 << 20)


@dataclass(frozen=True)
class JobUsage:
    """What a job's process used (see the module's docstring for what each figure counts)."""

    cpu_seconds: float  # s, user + system
    max_rss_mib: float | None  # MiB, peak resident set; None where the system does not say
    read_mib: float | None = None  # MiB read from storage; None where not counted
    written_mib: float | None = None  # MiB written to storage; None where not counted


def _cpu_seconds() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _peak_kib() -> int | None:
    """This process's resident high-water mark (KiB), None where /proc does not say."""
    try:
        with open("/proc/self/status", "rb") as status:
            for line in status:
                if line.startswith(b"VmHWM:"):
                    return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        return None
    return None


def _reset_peak() -> bool:
    """Set the high-water mark to the present resident set (Linux 4.0+); False where it cannot."""
    try:
        with open("/proc/self/clear_refs", "w") as clear:
            clear.write("5")
    except OSError:
        return False
    return True


def _io_bytes() -> tuple[int, int] | None:
    try:
        with open("/proc/self/io", "rb") as io:
            fields = dict(line.split(b":", 1) for line in io if b":" in line)
        return int(fields[b"read_bytes"]), int(fields[b"write_bytes"])
    except (OSError, ValueError, KeyError):
        return None


_open_meters: list[Meter] = []  # the measurements under way in this process, innermost last
_lock = threading.Lock()


class Meter:
    """A measurement of this process from now on, until :meth:`stop` or the end of a ``with``
    block (also when the block raises); :attr:`usage` once it has ended."""

    def __init__(self) -> None:
        self._cpu = _cpu_seconds()
        self._io = _io_bytes()
        self._inner_peak_kib = 0  # the highest mark seen before an inner measurement's reset
        with _lock:
            for outer in _open_meters:
                outer._inner_peak_kib = max(outer._inner_peak_kib, _peak_kib() or 0)
            _open_meters.append(self)
        _reset_peak()
        self.usage: JobUsage | None = None

    def stop(self) -> JobUsage:
        """End the measurement: its :class:`JobUsage` (also kept in :attr:`usage`)."""
        peak = _peak_kib()
        io = _io_bytes()
        with _lock:
            if self in _open_meters:
                _open_meters.remove(self)
        if peak is not None:
            peak = max(peak, self._inner_peak_kib)
        read = written = None
        if io is not None and self._io is not None:
            read, written = ((now - then) / MIB for now, then in zip(io, self._io, strict=True))
        self.usage = JobUsage(
            cpu_seconds=_cpu_seconds() - self._cpu,
            max_rss_mib=None if peak is None else peak * 1024 / MIB,
            read_mib=read,
            written_mib=written,
        )
        return self.usage

    def __enter__(self) -> Meter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


def usage_of_process(rusage: resource.struct_rusage) -> JobUsage:
    """What a process that has ended used, from the ``rusage`` that :func:`os.wait4` gives for
    it (its CPU and that of the processes it waited for; its peak resident set). Its bytes
    read and written are not known once it has ended (None)."""
    return JobUsage(
        cpu_seconds=rusage.ru_utime + rusage.ru_stime,
        max_rss_mib=rusage.ru_maxrss * 1024 / MIB,  # Linux: KiB
    )
