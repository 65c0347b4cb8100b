"""Benchmark: how time, memory and disk grow with the model, 1e5 to 1e7 cells.

Run:  .venv/bin/python bench/scaling.py [--sizes 63 200 400 632] [--cores 2] [--plot scaling.png]

The faulted anticline of ``bench/cases/million.yaml`` at n x n columns and 25 layers for each
``--sizes`` n (63: 1e5 cells, 200: 1e6, 400: 4e6, 632: 1e7, as ``bench/cases/ten_million.yaml``)
goes through every stage of the workflow (``bench/workflow.py``'s run: the Snakefile, one
case, ``--cores``). Printed per size: each rule's wall time and peak resident memory, per
cell (microseconds and bytes), and the artifacts' bytes per cell; then the growth from the
second size to the last (1.0 = linear). ``--plot`` draws the same per-cell figures. Every
size runs with ``outputs: {stage_files: false}`` (as ``ten_million.yaml``): the per-stage
files are dropped once ``{case}.nc`` holds them, so the artifacts are what a user keeps.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
from workflow import WorkflowRun, run_workflow

ROOT = Path(__file__).resolve().parents[1]
BASE = ROOT / "bench" / "cases" / "million.yaml"


def scaled_case(columns: int, folder: Path) -> tuple[Path, int]:
    """The base case at ``columns`` x ``columns`` columns: its file and its number of cells."""
    data = yaml.safe_load(BASE.read_text())
    data["name"] = f"scaling_{columns}"
    data["grid"]["dims"] = [columns, columns]
    data["outputs"] = {"stage_files": False}  # as ten_million.yaml: the files a user keeps
    path = folder / f"scaling_{columns}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path, columns * columns * sum(data["grid"]["layers"])


def cells_of(run: WorkflowRun, folder: Path) -> int:
    import json

    return int(json.loads((folder / "results" / run.name / "summary.json").read_text())["cells"])


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--sizes", type=int, nargs="+", default=[63, 200, 400, 632])
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--plot", type=Path, help="write the per-cell figures as a PNG")
    args = parser.parse_args()
    table = []
    for columns in args.sizes:
        with tempfile.TemporaryDirectory() as tmp:
            case, logical = scaled_case(columns, Path(tmp))
            run = run_workflow(case, Path(tmp) / "work", args.cores)
            active = cells_of(run, Path(tmp) / "work")
        table.append((columns, logical, active, run))
        print(f"{columns} x {columns} x 25: {logical:,d} cells ({active:,d} active), {run.wall:.0f} s wall")
        for rule, (seconds, rss) in run.rules.items():
            print(
                f"  {rule:16s} {seconds:8.1f} s {1e6 * seconds / active:7.2f} us/cell   "
                f"max_rss {rss:7.0f} MiB {rss * 2**20 / active:7.0f} B/cell"
            )
        disk = sum(run.sizes.values())
        print(f"  artifacts {disk / 2**30:.2f} GiB, {disk / active:.0f} B/cell", flush=True)
    if len(table) > 2:
        (_, _, a0, r0), (_, _, a1, r1) = table[1], table[-1]
        print(f"growth per cell from {a0:,d} to {a1:,d} active cells (1.00 = linear):")
        for rule in r1.rules:
            if rule in r0.rules:
                t = (r1.rules[rule][0] / a1) / (r0.rules[rule][0] / a0)
                m = (r1.rules[rule][1] / a1) / (r0.rules[rule][1] / a0)
                print(f"  {rule:16s} time {t:5.2f}   memory {m:5.2f}")
        print(
            f"  {'artifacts':16s} disk {(sum(r1.sizes.values()) / a1) / (sum(r0.sizes.values()) / a0):5.2f}"
        )
    if args.plot:
        plot(table, args.plot)


def plot(table, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(11, 4))
    rules = list(table[-1][3].rules)
    cells = [active for _, _, active, _ in table]
    for rule in rules:
        runs = [(a, r.rules[rule]) for _, _, a, r in table if rule in r.rules]
        ax_t.plot([a for a, _ in runs], [1e6 * s / a for a, (s, _) in runs], "o-", label=rule)
        ax_m.plot([a for a, _ in runs], [m * 2**20 / a for a, (_, m) in runs], "o-", label=rule)
    ax_m.plot(cells, [sum(r.sizes.values()) / a for _, _, a, r in table], "k--", label="artifacts (disk)")
    for ax, label in ((ax_t, "wall time per cell (us)"), (ax_m, "peak RSS / disk per cell (bytes)")):
        ax.set_xscale("log")
        ax.set_xlabel("active cells")
        ax.set_ylabel(label)
    ax_m.legend(fontsize=7)
    fig.suptitle("bench/scaling.py: the faulted anticline from 1e5 to 1e7 cells")
    fig.tight_layout()
    fig.savefig(path, dpi=100)


if __name__ == "__main__":
    main()
