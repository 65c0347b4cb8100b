"""Benchmark: a faulted corner-point deck of about 1e6 cells, text to grid to geometry.

Run:  .venv/bin/python bench/cornerpoint.py [--dims 200 200 25] [--repeat 3] [--peer-python PY]

Writes ``make_model3(dims)`` (an anticline cut by two faults, with inactive
cells; PORO and NTG added) to a GRDECL file, then times separately, each the
median of ``--repeat`` runs in this process:

* ``write_grdecl`` (the text writer),
* ``read_grdecl`` (the text parser),
* ``process_grdecl`` (the pillar engine: faces, fault subdivision, NNCs),
* ``compute_geometry`` of the processed grid,

and the peak memory of one fresh process doing all three (max RSS, which
includes the interpreter and numpy, about 60 MiB). Targets (issue 3) for
200x200x25: read <= 2 s, process <= 3 s, geometry <= 1.5 s, peak <= 2 GiB.

If resdata or xtgeo can be imported (here, or by ``--peer-python``, e.g. a
separate virtualenv with ``pip install resdata xtgeo six``), their read of the
same file plus cell volumes is timed too, with the ratios to gridlib's read +
process + geometry (which gives faces, fault topology and NNCs as well).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import gridlib as gl
from gridlib.cornerpoint.generators import make_model3
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl, write_grdecl

ONE_RUN = """
import json, resource, sys, time
from gridlib import compute_geometry
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl
t0 = time.perf_counter()
deck = read_grdecl(sys.argv[1])
t1 = time.perf_counter()
r = process_grdecl(deck)
t2 = time.perf_counter()
geo = compute_geometry(r.grid)
t3 = time.perf_counter()
print(json.dumps({"read": t1 - t0, "process": t2 - t1, "geometry": t3 - t2,
                  "max_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""

PEERS = """
import json, sys, time
out = {}
path = sys.argv[1]
try:
    from resdata.grid import Grid
    t = time.perf_counter()
    g = Grid.load_from_grdecl(path)
    v = g.export_volume(g.export_index(active_only=True))
    out["resdata"] = {"seconds": time.perf_counter() - t, "active": int(g.get_num_active()),
                      "volume": float(sum(v))}
except ImportError:
    pass
try:
    import xtgeo
    t = time.perf_counter()
    g = xtgeo.grid_from_file(path, fformat="grdecl")
    v = g.get_bulk_volume()
    out["xtgeo"] = {"seconds": time.perf_counter() - t, "active": int(g.nactive),
                    "volume": float(v.values.sum())}
except ImportError:
    pass
print(json.dumps(out))
"""


def timed(fn, *args):
    t0 = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - t0


def summary(times: list[float]) -> str:
    return f"median {statistics.median(times):6.3f} s (min {min(times):.3f}, max {max(times):.3f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--peer-python", default=sys.executable, help="interpreter with resdata/xtgeo")
    args = parser.parse_args()

    deck = make_model3(args.dims)
    rng = np.random.default_rng(0)
    props = {"PORO": np.round(0.1 + 0.2 * rng.random(deck.num_cells), 4), "NTG": np.full(deck.num_cells, 0.9)}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model3.grdecl"
        writes = [timed(write_grdecl, path, deck, props)[1] for _ in range(args.repeat)]
        size = path.stat().st_size / 2**20
        print(
            f"make_model3({args.dims}): {deck.num_cells:,d} cells, {int(deck.active.sum()):,d} active; "
            f"GRDECL {size:.0f} MiB"
        )
        print(f"  write_grdecl      {summary(writes)}")

        reads, procs, geoms = [], [], []
        for _ in range(args.repeat):
            d, t = timed(read_grdecl, path)
            reads.append(t)
            r, t = timed(process_grdecl, d)
            procs.append(t)
            _, t = timed(gl.compute_geometry, r.grid)
            geoms.append(t)
        g = r.grid
        print(
            f"  grid: {g.num_cells:,d} cells, {g.num_faces:,d} faces ({int((g.faces.tag > 0).sum()):,d} "
            f"on faults), {g.num_nodes:,d} nodes, {r.nnc.num:,d} NNCs"
        )
        print(f"  read_grdecl       {summary(reads)}")
        print(f"  process_grdecl    {summary(procs)}")
        print(f"  compute_geometry  {summary(geoms)}")
        total = statistics.median(reads) + statistics.median(procs) + statistics.median(geoms)
        print(f"  total             {total:6.3f} s (sum of medians)")

        fresh = json.loads(
            subprocess.run(
                [sys.executable, "-c", ONE_RUN, str(path)], check=True, capture_output=True, text=True
            ).stdout
        )
        print(
            f"  one fresh process: read {fresh['read']:.3f} s, process {fresh['process']:.3f} s, "
            f"geometry {fresh['geometry']:.3f} s, peak memory (max RSS) {fresh['max_rss_mib']:.0f} MiB"
        )

        done = subprocess.run([args.peer_python, "-c", PEERS, str(path)], capture_output=True, text=True)
        peers = json.loads(done.stdout) if done.returncode == 0 and done.stdout.strip() else {}
        if not peers:
            print("  (resdata/xtgeo not importable: no peer timings; see --peer-python)")
        ours_volume = float(r.bulk_volumes.sum())
        for name, p in peers.items():
            print(
                f"  {name:<8s} read + cell volumes {p['seconds']:6.3f} s, {p['active']:,d} active cells, "
                f"volume {p['volume']:.6e} (ours {ours_volume:.6e})"
            )
            print(f"           gridlib read + process + geometry takes {total / p['seconds']:.2f}x its time")


if __name__ == "__main__":
    main()
