"""What a job's process used (gridlib.stages.job_usage): CPU seconds, the peak resident memory
since the measurement started (also in a process that ran a bigger job before, as a warm worker
does), nested measurements, bytes written, and an ended process's figures from os.wait4."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest

from gridlib.stages.job_usage import Meter, usage_of_process

MIB = 1 << 20
LINUX = Path("/proc/self/clear_refs").exists()


def _touch(mib: int) -> np.ndarray:
    """``mib`` MiB of new memory, every page written (resident)."""
    block = np.empty(mib * MIB, dtype=np.uint8)
    block[::4096] = 1
    return block


def _burn(seconds: float) -> int:
    """Spend ``seconds`` of this process's CPU time summing integers; the sum."""
    total, end = 0, time.process_time() + seconds
    while time.process_time() < end:
        total += sum(range(1000))
    return total


def _rss_mib() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise AssertionError("no VmRSS")


def test_cpu_seconds_are_this_processs_user_and_system_time():
    with Meter() as meter:
        before = time.process_time()
        _burn(0.2)
        spent = time.process_time() - before
    assert spent >= 0.2
    assert meter.usage.cpu_seconds == pytest.approx(spent, abs=0.02)


@pytest.mark.skipif(not LINUX, reason="the peak is reset through Linux's /proc/self/clear_refs")
def test_the_peak_is_the_measurements_not_an_earlier_jobs():
    """A warm worker's second job is not charged with the first one's peak."""
    with Meter() as first:
        block = _touch(96)
        del block  # returned to the system (numpy's large blocks are mapped, then unmapped)
    with Meter() as second:
        small = _touch(8)
        del small
    baseline = _rss_mib()
    assert first.usage.max_rss_mib >= baseline + 90
    assert second.usage.max_rss_mib < baseline + 40
    assert second.usage.max_rss_mib >= baseline  # the pages already resident count


@pytest.mark.skipif(not LINUX, reason="the peak is reset through Linux's /proc/self/clear_refs")
def test_an_inner_measurement_keeps_the_outer_ones_peak():
    """A variant's measurement around its stages' own (run_logged's): the inner reset does not
    lose what the outer one saw before it."""
    with Meter() as outer:
        block = _touch(96)
        del block
        with Meter() as inner:
            small = _touch(8)
            del small
    assert outer.usage.max_rss_mib >= inner.usage.max_rss_mib + 80
    assert outer.usage.cpu_seconds >= inner.usage.cpu_seconds


@pytest.mark.skipif(not Path("/proc/self/io").exists(), reason="the system counts no bytes per process")
def test_bytes_written_count_what_the_process_wrote(tmp_path):
    data = np.random.default_rng(3).bytes(6 * MIB)
    with Meter() as meter:
        path = tmp_path / "written.bin"
        path.write_bytes(data)
        os.sync()
    assert meter.usage.written_mib >= 6
    assert meter.usage.read_mib >= 0


def test_an_ended_processs_cpu_and_peak_come_from_wait4():
    pid = os.fork()
    if pid == 0:  # the child: 64 MiB touched, 0.2 s of CPU
        try:
            block = _touch(64)
            _burn(0.2)
            del block
        finally:
            os._exit(0)
    _, status, rusage = os.wait4(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    usage = usage_of_process(rusage)
    assert usage.cpu_seconds >= 0.2
    assert usage.max_rss_mib >= 64
    assert usage.read_mib is None and usage.written_mib is None
