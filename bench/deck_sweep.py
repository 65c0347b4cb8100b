"""Sweep: decks written by others through gridlib and OPM Flow's dry run, one line per deck.

Run:  .venv/bin/python bench/deck_sweep.py DECK_OR_FOLDER ... [--out DIR] [--skip-unknown]

Every ``*.DATA`` deck given (or found under a folder given) is run by Flow's dry run
(``flow --enable-dry-run=true``) and read by gridlib (``read_grdecl`` -> ``process_grdecl`` ->
``deck_transmissibility`` and the pore volumes, as tests/real_decks.py's ``gridlib_result``);
the two are compared as the real-deck tests compare them: the same active cells, the same
connections, every T and pore volume within 1e-6 relative. Printed per deck: the outcome
(``match``; ``differs`` and what; ``gridlib refuses`` and its one-line message; ``Flow refuses``
and Flow's last error), Flow's wall time and gridlib's (read, process, T, pore volumes), then
the counts. ``--skip-unknown`` reads with ``unknown_keywords="skip"`` (a deck with keywords
neither ECLIPSE nor Flow knows, which Flow then refuses too unless told to ignore them).

A session ran 443 decks so (OPM's opm-common and opm-tests decks, the C++ tests' inline decks,
xtgeo-testdata's GRDECL exports and probes of every keyword gridlib reads; the findings are
the tests of tests/io/test_deck_syntax.py, tests/io/test_binary_grdecl.py and
tests/transmissibility/test_real_decks.py).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import real_decks as rd  # noqa: E402  (the tests' harness: Flow's dry run and the comparisons)

CHECKS = rd.CHECKS_ALL


def decks(paths: list[str]) -> list[Path]:
    found = []
    for given in map(Path, paths):
        found += sorted(given.rglob("*.DATA")) if given.is_dir() else [given]
    return found


def sweep_one(deck: Path, out: Path, unknown: str) -> tuple[str, str, float, float]:
    """The outcome, its reason, Flow's seconds and gridlib's."""
    start = time.perf_counter()
    try:
        flow, dims = rd.flow_result(deck, out)
    except Exception as exc:  # Flow stopped: its last error line
        lines = [line for line in str(exc).splitlines() if "rror" in line] or [str(exc)]
        return "Flow refuses", lines[-1].strip()[:120], time.perf_counter() - start, float("nan")
    flow_seconds = time.perf_counter() - start
    start = time.perf_counter()
    try:
        ours = rd.gridlib_result(deck, unknown)
    except Exception as exc:
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        return "gridlib refuses", f"{type(exc).__name__}: {message}"[:160], flow_seconds, float("nan")
    gridlib_seconds = time.perf_counter() - start
    comparison = rd.Comparison(deck.stem, deck, dims, flow, ours)
    for check in CHECKS:
        try:
            check(comparison)
        except AssertionError as exc:
            return "differs", str(exc).splitlines()[0][:160], flow_seconds, gridlib_seconds
    return (
        "match",
        f"{ours.active.size} cells, {ours.pairs.shape[0]} connections",
        flow_seconds,
        gridlib_seconds,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="+", help="decks (*.DATA) or folders to search")
    parser.add_argument(
        "--out", default="deck_sweep_out", help="Flow's output folders (default: ./deck_sweep_out)"
    )
    parser.add_argument("--skip-unknown", action="store_true", help="read with unknown_keywords='skip'")
    args = parser.parse_args()
    unknown = "skip" if args.skip_unknown else "error"
    counts: Counter[str] = Counter()
    print(f"{'deck':40s} {'outcome':16s} {'Flow s':>7s} {'gridlib s':>9s}  reason")
    for deck in decks(args.paths):
        outcome, reason, flow_s, ours_s = sweep_one(deck, Path(args.out) / deck.stem, unknown)
        counts[outcome] += 1
        print(f"{deck.stem[:40]:40s} {outcome:16s} {flow_s:7.2f} {ours_s:9.2f}  {reason}", flush=True)
    print(", ".join(f"{n} {outcome}" for outcome, n in counts.most_common()))


if __name__ == "__main__":
    main()
