"""Environments that make one machine compute as others would, for determinism tests.

BLAS and numpy choose code by the CPU and the thread count: OpenBLAS splits sums by
thread and picks its kernels by CPU (``OPENBLAS_CORETYPE`` forces another one, e.g. an
older CPU without fused multiply-add), numpy dispatches its loops to AVX2/AVX-512 code
when the CPU has it (``NPY_DISABLE_CPU_FEATURES`` switches that off, as on a CPU
without them). gridlib promises the same bits under all of them.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from concurrent.futures import ThreadPoolExecutor

THREAD_KEYS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "GRIDLIB_NUM_THREADS")
MACHINE_KEYS = (*THREAD_KEYS, "OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES")


def threads(n: int) -> dict[str, str]:
    return dict.fromkeys(THREAD_KEYS, str(n))


def simd_features() -> str:
    """numpy's dispatch targets this CPU has (empty on a baseline-only CPU)."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return " ".join(f for f in __cpu_dispatch__ if __cpu_features__.get(f))


def other_machine() -> dict[str, str]:
    """Two threads everywhere, an old CPU's BLAS kernels and numpy without its SIMD code."""
    env = {**threads(2), "OPENBLAS_CORETYPE": "Nehalem"}
    if simd_features():
        env["NPY_DISABLE_CPU_FEATURES"] = simd_features()
    return env


def machine_variants() -> list[dict[str, str]]:
    """1 or 2 threads, other OpenBLAS kernels, numpy's SIMD switched off."""
    one, two = threads(1), threads(2)
    return [
        one,
        two,
        {**one, "OPENBLAS_CORETYPE": "Haswell"},
        {**two, "OPENBLAS_CORETYPE": "Sandybridge"},
        other_machine(),
    ]


def environment(variant: dict[str, str]) -> dict[str, str]:
    """This process's environment with the machine keys replaced by ``variant``'s."""
    return {k: v for k, v in os.environ.items() if k not in MACHINE_KEYS} | variant


def run_python(code: str, variant: dict[str, str], timeout: float = 600) -> str:
    """The stdout of ``code`` run by a fresh interpreter under ``variant``; fails on an error."""
    res = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        env=environment(variant),
        capture_output=True,
        text=True,
        check=False,
        timeout=timeout,
    )
    assert res.returncode == 0, f"{variant}: {res.stderr[-3000:]}"
    return res.stdout


def outputs_everywhere(code: str) -> list[str]:
    """The stdout of ``code`` under every machine variant (in the order of machine_variants)."""
    # The interpreters run side by side (one per core): a variant's bits cannot depend on it.
    with ThreadPoolExecutor(max_workers=max(1, os.cpu_count() or 1)) as pool:
        return list(pool.map(lambda variant: run_python(code, variant), machine_variants()))


def assert_same_outputs(outs: list[str]) -> None:
    """Assert that every variant printed what the first one did, naming where they differ."""
    for env, out in zip(machine_variants(), outs, strict=True):
        diff = [a for a, b in zip(out.splitlines(), outs[0].splitlines(), strict=True) if a != b]
        assert out == outs[0], f"differs under {env}:\n  " + "\n  ".join(diff)


def same_output_everywhere(code: str) -> None:
    """Run ``code`` under every machine variant and assert identical stdout."""
    assert_same_outputs(outputs_everywhere(code))


# One interpreter per variant runs several programs (each in a namespace of its own), so
# that the variants pay for Python's start-up and gridlib's imports once, not once per program.
_SECTIONS = """
import sys, traceback
for name, code in {programs!r}.items():
    print("#### program", name, flush=True)
    try:
        exec(compile(code, name, "exec"), {{"__name__": "__main__"}})
    except BaseException:
        print("#### failed", name)
        traceback.print_exc(file=sys.stdout)
    sys.stdout.flush()
"""


def sections_everywhere(programs: dict[str, str]) -> list[dict[str, str]]:
    """What each of ``programs`` (name: code) printed under each machine variant, all of a
    variant's programs run one after the other in one fresh interpreter."""
    outs = outputs_everywhere(_SECTIONS.format(programs={k: textwrap.dedent(v) for k, v in programs.items()}))
    sections = []
    for out in outs:
        parts = out.split("#### program ")[1:]
        sections.append(dict(part.split("\n", 1) for part in parts))
        assert list(sections[-1]) == list(programs), out[-3000:]
    return sections


def assert_same_section(sections: list[dict[str, str]], name: str) -> None:
    """Assert that program ``name`` ran under every variant and printed the same everywhere."""
    for env, section in zip(machine_variants(), sections, strict=True):
        assert "#### failed" not in section[name], f"{name} under {env}:\n{section[name][-3000:]}"
    assert_same_outputs([section[name] for section in sections])
