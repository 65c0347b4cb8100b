"""Regenerate ``flow_reference.npz``: what OPM Flow computes for every vendored deck.

    python tests/data/decks/make_flow_reference.py     # needs `flow` (Debian libopm-simulators-bin)

For each deck, Flow's dry run (grid processing, pore volumes, transmissibilities,
NNCs, then stop) writes EGRID + INIT; we keep, per deck:

* ``<deck>_active``: linear indices (i fastest, 0-based) of Flow's active cells;
* ``<deck>_bulk``: their bulk volumes PORV / (PORO * NTG * MULTPV) in the deck's
  length unit cubed (reservoir barrels converted to ft3 for FIELD decks: 1 rb =
  9702/1728 ft3); INIT stores float32, so these carry ~6e-8 relative rounding;
* ``<deck>_nnc``: Flow's NNC pairs (0-based linear indices, smaller first, sorted).

Decks without the INIT keyword get it added in a temporary copy, and the
grid-only PINCH decks the rest of a deck (phases, tables, equilibration). The
file also records Flow's version. Nothing here is used when the tests run; they read the
npz.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import resfo

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # tests/: flow_tools
from flow_tools import PHASES, rest_of_deck

HERE = Path(__file__).parent
DECKS = {
    "SPE9_CP": "spe9/SPE9_CP.DATA",
    "SPE10_MODEL1_CP": "spe10model1/SPE10_MODEL1_CP.DATA",
    "SPE1CASE1": "spe1/SPE1CASE1.DATA",
    "SPE1CASE2_ACTNUM": "spe1/SPE1CASE2_ACTNUM.DATA",
    "2_WLIFT_MODEL5_NOINC": "model5/2_WLIFT_MODEL5_NOINC.DATA",
    "REEK_FLOWWRAP": "reek/REEK_FLOWWRAP.DATA",
    "REEK_GRDECL": "reek/REEK_GRDECL.DATA",
} | {
    name: f"pinch/{name}.DATA"
    for name in (
        "FIVE",
        "FIVE_ACTNUM",
        "FIVE_PINCH",
        "FIVE_PINCH_NOGAP",
        "FIVE_PINCH_NOGAP2",
        "FIVE_PINCH_NOGAP3",
    )
}
# OPM's PINCH/MINPV test decks have only RUNSPEC and GRID; Flow needs the rest of a deck.
RUNSPEC_EXTRA = "METRIC\n" + PHASES
REST_OF_DECK = "\nEQUALS\n 'PERMX' 100 /\n 'PERMY' 100 /\n 'PERMZ' 100 /\n/\n" + rest_of_deck(0.5, 10.0)
RB_IN_FT3 = 9702 / 1728  # 1 reservoir barrel = 5.6145833... ft3


def first_arrays(path: Path) -> dict[str, np.ndarray]:
    out: dict[str, np.ndarray] = {}
    for kw, arr in resfo.read(path):
        out.setdefault(kw.strip(), np.asarray(arr))
    return out


def run_flow(deck: Path, out: Path) -> None:
    cmd = ["flow", "--enable-dry-run=true", "--threads-per-process=1", f"--output-dir={out}", str(deck)]
    subprocess.run(cmd, check=True, capture_output=True)


def reference(name: str, relpath: str, work: Path) -> dict[str, np.ndarray]:
    src = HERE / relpath
    copy_dir = work / name
    shutil.copytree(src.parent, copy_dir)
    deck = copy_dir / src.name
    text = deck.read_text(errors="replace")
    if "\nINIT" not in text:
        text = text.replace("\nGRID\n", "\nGRID\nINIT\n", 1)
    if "\nPROPS" not in text:
        text = text.replace("RUNSPEC\n", "RUNSPEC\n" + RUNSPEC_EXTRA, 1) + REST_OF_DECK
    deck.write_text(text)
    out = work / f"{name}_out"
    run_flow(deck, out)
    egrid = first_arrays(out / f"{src.stem}.EGRID")
    init = first_arrays(out / f"{src.stem}.INIT")
    active = np.flatnonzero(egrid["ACTNUM"] > 0)
    porv = init["PORV"].astype(np.float64)[active]
    poro = init["PORO"].astype(np.float64)
    ntg = init.get("NTG", np.ones_like(poro)).astype(np.float64)
    multpv = init.get("MULTPV", np.ones_like(poro)).astype(np.float64)
    factor = RB_IN_FT3 if int(init["INTEHEAD"][2]) == 2 else 1.0
    nnc = np.zeros((0, 2), np.int32)
    if "NNC1" in egrid:
        a, b = egrid["NNC1"].astype(np.int64) - 1, egrid["NNC2"].astype(np.int64) - 1
        nnc = np.unique(np.column_stack([np.minimum(a, b), np.maximum(a, b)]), axis=0).astype(np.int32)
    return {
        f"{name}_active": active.astype(np.int32),
        f"{name}_bulk": porv / (poro * ntg * multpv) * factor,
        f"{name}_nnc": nnc,
    }


def main() -> None:
    version = subprocess.run(["flow", "--version"], capture_output=True, text=True, check=True).stdout.strip()
    arrays: dict[str, np.ndarray] = {"flow_version": np.array(version)}
    with tempfile.TemporaryDirectory() as tmp:
        for name, relpath in DECKS.items():
            arrays |= reference(name, relpath, Path(tmp))
            print(name, arrays[f"{name}_active"].size, "active", arrays[f"{name}_nnc"].shape[0], "NNCs")
    np.savez_compressed(HERE / "flow_reference.npz", **arrays)
    print(f"wrote {HERE / 'flow_reference.npz'} ({version})", file=sys.stderr)


if __name__ == "__main__":
    main()
