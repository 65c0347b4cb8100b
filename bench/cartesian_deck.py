"""Benchmark: a Cartesian DX/DY/DZ/TOPS deck against the faulted corner-point deck, per cell.

Run:  .venv/bin/python bench/cartesian_deck.py [--runs 3] [--compare-with /path/to/other/checkout]
                                               [--spe-dims 60 220 85] [--model3-dims 200 200 25]

Two GRDECL files are written (not timed):

* ``spe``: an SPE10-like box grid (60 x 220 x 85 = 1,122,000 cells, 20 x 10 x 2 ft cells)
  given as the SPE benchmark gives it: DIMENS, ``DX``/``DY``/``DZ`` as ``1122000*20``,
  ``TOPS`` for the top layer only (``13200*12000``), PORO, PERMX, PERMY, PERMZ per cell
  (lognormal, a few PORO 0 cells inactive as in the benchmark);
* ``model3``: bench/cornerpoint.py's ``make_model3`` (an anticline cut by two faults, with
  inactive cells; COORD/ZCORN/ACTNUM) with PORO, NTG and PERMX/Y/Z.

Each deck is then read (``read_grdecl``), processed (``process_grdecl``), its geometry
computed (``compute_geometry``) and its transmissibilities (``deck_transmissibility``), in a
fresh child process per run; each stage's time and the peak RSS up to the end of that stage
(``ru_maxrss``, which includes the interpreter and numpy, about 60 MiB) are printed per cell
(microseconds and bytes per deck cell, then per active cell: model3 has 19 % inactive cells,
the spe deck 2 %, so per deck cell the spe deck has more faces and connections), the
median of ``--runs`` children. Each deck's faces per cell are printed, and the geometry time
per face too: compute_geometry works face by face, so per face the decks compare without
their different shares of inactive cells. The CPU seconds of every stage (all threads) are
printed as well, with the load average: on a busy machine they vary far less than wall times.

``--compare-with PATH`` runs the same children with ``PYTHONPATH=PATH`` too (another
checkout of gridlib, e.g. the previous commit), alternating with this one, and prints both
side by side: this machine's speed varies by 2x between days, so only figures of one run
compare. The issue's target: every spe figure per cell no worse than model3's.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

STAGES = ("read", "process", "geometry", "transmissibility")

CHILD = """
import json, resource, sys, time
from gridlib import compute_geometry
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl
from gridlib.transmissibility import deck_transmissibility
out = {}
def stage(name, t0):
    out[name] = {"seconds": time.perf_counter() - t0[0], "cpu": time.process_time() - t0[1],
                 "max_rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}
now = lambda: (time.perf_counter(), time.process_time())
t = now(); deck = read_grdecl(sys.argv[1]); stage("read", t)
t = now(); cp = process_grdecl(deck); stage("process", t)
t = now(); geo = compute_geometry(cp.grid); stage("geometry", t)
t = now(); conn = deck_transmissibility(deck, cp); stage("transmissibility", t)
out["cells"] = deck.num_cells
out["active"] = cp.grid.num_cells
out["connections"] = int(conn.num)
out["faces"] = cp.grid.num_faces
print(json.dumps(out))
"""


def write_spe_deck(path: Path, dims: tuple[int, int, int]) -> None:
    """The SPE10-like deck: constant DX/DY/DZ and top-layer TOPS as repeat counts, rock per cell."""
    nx, ny, nz = dims
    n = nx * ny * nz
    rng = np.random.default_rng(10)
    poro = np.round(0.05 + 0.3 * rng.random(n), 4)
    poro[rng.random(n) < 0.02] = 0.0  # SPE10 has cells of zero porosity: inactive
    permx = np.round(10.0 ** rng.normal(1.0, 1.0, n), 3)
    with open(path, "w") as f:
        f.write(f"DIMENS\n {nx} {ny} {nz} /\nFIELD\n")
        for key, value in (("DX", 20), ("DY", 10), ("DZ", 2)):
            f.write(f"{key}\n {n}*{value} /\n")
        f.write(f"TOPS\n {nx * ny}*12000 /\n")
        for key, values in (("PORO", poro), ("PERMX", permx), ("PERMY", permx), ("PERMZ", permx / 10)):
            f.write(f"{key}\n")
            np.savetxt(f, values.reshape(-1, 8) if n % 8 == 0 else values, fmt="%.6g")
            f.write("/\n")


def write_model3_deck(path: Path, dims: tuple[int, int, int]) -> None:
    """bench/cornerpoint.py's faulted deck with PORO, NTG and PERMX/Y/Z."""
    from gridlib.cornerpoint.generators import make_model3
    from gridlib.io.grdecl import write_grdecl

    deck = make_model3(list(dims))
    n = deck.num_cells
    rng = np.random.default_rng(0)
    permx = np.round(10.0 ** rng.normal(2.0, 0.5, n), 3)
    props = {
        "PORO": np.round(0.1 + 0.2 * rng.random(n), 4),
        "NTG": np.full(n, 0.9),
        "PERMX": permx,
        "PERMY": permx,
        "PERMZ": permx / 10.0,
    }
    write_grdecl(path, deck, props)


def child(path: Path, checkout: str | None) -> dict:
    env = dict(os.environ)
    if checkout is not None:
        env["PYTHONPATH"] = checkout
    done = subprocess.run(
        [sys.executable, "-c", CHILD, str(path)],
        env=env,
        cwd=path.parent,  # not a checkout: ``python -c`` puts the working directory first on sys.path
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode:
        raise SystemExit(f"child ({checkout or 'this checkout'}) on {path.name} failed:\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def per_cell(runs: list[dict], count: str) -> dict[str, tuple[float, float]]:
    """Median us/cell and bytes/cell (peak RSS up to the stage) of every stage, per deck
    cell (``count`` "cells") or per active cell ("active")."""
    n = runs[0][count]
    return {
        s: (
            statistics.median(r[s]["seconds"] for r in runs) * 1e6 / n,
            statistics.median(r[s]["max_rss"] for r in runs) / n,
        )
        for s in STAGES
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--runs", type=int, default=3, help="fresh children per deck and checkout")
    parser.add_argument("--compare-with", help="another gridlib checkout, run with PYTHONPATH side by side")
    parser.add_argument("--spe-dims", type=int, nargs=3, default=[60, 220, 85])
    parser.add_argument("--model3-dims", type=int, nargs=3, default=[200, 200, 25])
    args = parser.parse_args()

    import gridlib

    here = str(Path(gridlib.__file__).resolve().parent.parent)
    checkouts = {"this": here}
    if args.compare_with:
        checkouts["other"] = str(Path(args.compare_with).resolve())
    with tempfile.TemporaryDirectory() as tmp:
        decks = {"spe": Path(tmp) / "spe.grdecl", "model3": Path(tmp) / "model3.grdecl"}
        write_spe_deck(decks["spe"], tuple(args.spe_dims))
        write_model3_deck(decks["model3"], tuple(args.model3_dims))
        results: dict[tuple[str, str], list[dict]] = {(c, d): [] for c in checkouts for d in decks}
        load = os.getloadavg()
        for _ in range(args.runs):  # alternating: checkouts and decks see the same machine load
            for d, path in decks.items():
                for c, where in checkouts.items():
                    results[c, d].append(child(path, where))
        for d, path in decks.items():
            r = results["this", d][0]
            print(
                f"{d}: {r['cells']:,d} cells ({r['active']:,d} active), {r['faces']:,d} faces "
                f"({r['faces'] / r['cells']:.2f} per cell, {r['faces'] / r['active']:.2f} per active cell), "
                f"{r['connections']:,d} connections, "
                f"GRDECL {path.stat().st_size / 2**20:.0f} MiB"
            )
    for c, where in checkouts.items():
        print(f"{c}: {where}")
    print(f"load average (1 min) before and after the runs: {load[0]:.2f}, {os.getloadavg()[0]:.2f}")
    header = f"{'stage':<17s}" + "".join(f"{c + ' ' + d:>22s}" for c in checkouts for d in decks)
    # CPU seconds of all threads: on a busy machine they vary far less than wall times.
    print(f"\nCPU per deck cell, median of {args.runs} fresh children: us (all threads)")
    print(header)
    for s in STAGES:
        cpu = [
            statistics.median(r[s]["cpu"] for r in results[c, d]) / results[c, d][0]["cells"]
            for c in checkouts
            for d in decks
        ]
        print(f"{s:<17s}" + "".join(f"{us * 1e6:>22.3f}" for us in cpu))
    # Geometry works face by face: per face, the decks compare without their share of inactive cells.
    print("geometry per face, median wall | CPU ns:", end="")
    for (c, d), runs in results.items():
        ns_wall, ns_cpu = (
            statistics.median(r["geometry"][k] for r in runs) * 1e9 / runs[0]["faces"]
            for k in ("seconds", "cpu")
        )
        print(f" {c} {d} {ns_wall:.0f} | {ns_cpu:.0f};", end="")
    print()
    for count, label in (("cells", "deck cell"), ("active", "active cell")):
        print(f"\nper {label}, median of {args.runs} fresh children: us | peak RSS bytes (up to the stage)")
        print(header)
        table = {(c, d): per_cell(results[c, d], count) for c in checkouts for d in decks}
        for s in STAGES:
            row = f"{s:<17s}"
            for c in checkouts:
                for d in decks:
                    us, b = table[c, d][s]
                    row += f"{us:>11.3f} | {b:>7.0f}"
            print(row)
        for c in checkouts:
            worse = [
                s for s in STAGES if any(table[c, "spe"][s][m] > table[c, "model3"][s][m] for m in (0, 1))
            ]
            print(
                f"{c}: spe per {label} no worse than model3 in every stage: "
                f"{'yes' if not worse else 'no (' + ', '.join(worse) + ')'}"
            )


if __name__ == "__main__":
    main()
