"""OPM Flow as the independent reference of the tests: run it, read what it computed.

``flow --enable-dry-run=true`` processes a deck (grid, PINCH/MINPV, pore volumes,
transmissibilities, NNCs) and writes EGRID and INIT without simulating. Its
transmissibilities are spread over INIT's TRANX/TRANY/TRANZ (per active cell: the
connection to the next cell in +i, +j, and the next active cell below in the same
column) and EGRID's NNC1/NNC2 with INIT's TRANNNC (every other connection); INIT
stores float32.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import resfo
from system_tools import missing_tool


def flow_executable() -> str:
    """The ``flow`` command; without it the test fails (see system_tools.missing_tool)."""
    exe = shutil.which("flow")
    if exe is None:
        missing_tool("OPM Flow ('flow', Debian libopm-simulators-bin) is not on the PATH")
    return exe


def run_flow_dry(deck: Path, out: Path) -> Path:
    """Flow's dry run of ``deck`` into ``out``; returns the case path without suffix."""
    out.mkdir(parents=True, exist_ok=True)
    res = subprocess.run(
        [
            flow_executable(),
            "--enable-dry-run=true",
            "--threads-per-process=1",
            f"--output-dir={out}",
            str(deck),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    return out / Path(deck).stem.upper()


def read_keywords(path: Path) -> dict[str, np.ndarray]:
    return {kw.strip(): np.asarray(v) for kw, v in resfo.read(path) if v is not resfo.MESS}


def flow_connections(case: Path) -> dict[tuple[int, int], float]:
    """Flow's connections {(g1, g2): T} (0-based linear indices, g1 < g2, T in deck units),
    from ``case``.EGRID and ``case``.INIT; zero transmissibilities are left out."""
    egrid = read_keywords(Path(f"{case}.EGRID"))
    init = read_keywords(Path(f"{case}.INIT"))
    nx, ny, nz = (int(v) for v in egrid["GRIDHEAD"][1:4])
    active = np.flatnonzero(egrid["ACTNUM"] > 0) if "ACTNUM" in egrid else np.arange(nx * ny * nz)
    out: dict[tuple[int, int], float] = {}
    for key, step in (("TRANX", 1), ("TRANY", nx)):
        t = init[key].astype(np.float64)
        for g, v in zip(active[t != 0].tolist(), t[t != 0].tolist(), strict=True):
            out[(g, g + step)] = v
    # TRANZ: to the next active cell below in the same column
    t = init["TRANZ"].astype(np.float64)
    k = active // (nx * ny)
    col = active % (nx * ny)
    order = np.lexsort((k, col))
    below = np.full(active.size, -1)
    same = col[order][1:] == col[order][:-1]
    below[order[:-1][same]] = active[order[1:][same]]
    for g, b, v in zip(active.tolist(), below.tolist(), t.tolist(), strict=True):
        if v != 0:
            assert b >= 0, f"TRANZ of cell {g} without an active cell below"
            out[(g, b)] = v
    if "NNC1" in egrid and "TRANNNC" in init:
        for a, b, v in zip(
            egrid["NNC1"].tolist(),
            egrid["NNC2"].tolist(),
            init["TRANNNC"].astype(np.float64).tolist(),
            strict=True,
        ):
            pair = (min(a, b) - 1, max(a, b) - 1)
            out[pair] = out.get(pair, 0.0) + v
    return {p: v for p, v in out.items() if v != 0}


def flow_connection_arrays(case: Path) -> tuple[np.ndarray, np.ndarray]:
    """What flow_connections reads, as arrays for decks of a million cells: the (n, 2)
    0-based linear cell pairs (first < second, sorted) and their T (float64 of INIT's
    float32; an NNC on a pair that is also a neighbour adds to it); zeros left out."""
    egrid = read_keywords(Path(f"{case}.EGRID"))
    init = read_keywords(Path(f"{case}.INIT"))
    nx, ny, nz = (int(v) for v in egrid["GRIDHEAD"][1:4])
    active = np.flatnonzero(egrid["ACTNUM"] > 0) if "ACTNUM" in egrid else np.arange(nx * ny * nz)
    # TRANZ: to the next active cell below in the same column (active is ordered by k in a column)
    col = active % (nx * ny)
    order = np.argsort(col, kind="stable")
    below = np.full(active.size, -1)
    same = col[order][1:] == col[order][:-1]
    below[order[:-1][same]] = active[order[1:][same]]
    tranz = init["TRANZ"].astype(np.float64)
    if np.any((tranz != 0) & (below < 0)):
        raise AssertionError(f"{case}.INIT: TRANZ of a cell without an active cell below")
    first = [active, active, active]
    second = [active + 1, active + nx, below]
    values = [init["TRANX"].astype(np.float64), init["TRANY"].astype(np.float64), tranz]
    if "NNC1" in egrid and "TRANNNC" in init:
        n1, n2 = egrid["NNC1"].astype(np.int64) - 1, egrid["NNC2"].astype(np.int64) - 1
        first.append(np.minimum(n1, n2))
        second.append(np.maximum(n1, n2))
        values.append(init["TRANNNC"].astype(np.float64))
    a, b, t = (np.concatenate(v) for v in (first, second, values))
    keep = t != 0
    a, b, t = a[keep], b[keep], t[keep]
    key = a * (nx * ny * nz) + b
    unique, inverse = np.unique(key, return_inverse=True)
    total = np.bincount(inverse, weights=t, minlength=unique.size)
    pairs = np.column_stack(np.divmod(unique, nx * ny * nz))
    nonzero = total != 0
    return pairs[nonzero], total[nonzero]


def flow_connection_factors(deck: Path, out: Path, step_days: float = 1.0) -> dict[tuple[str, int], float]:
    """Flow's well connection factors {(well, g): CF} (g the 0-based linear cell index, CF in
    deck units, float32) of the connections that exist after the first report step.

    The dry run writes no well data, so Flow simulates one short report step of a copy of
    ``deck`` written into ``out``: the text up to the first TSTEP or DATES of its SCHEDULE
    section (which must then come in the deck file itself, not in an include), followed by
    RPTRST BASIC=1 and one TSTEP of ``step_days``; the other entries of the deck's folder are
    linked next to it, so that relative INCLUDE paths resolve. The factors are read from the
    restart file: per well, ICON holds each connection's 1-based I, J, K (items 2-4) and SCON
    its connection transmissibility factor (item 1), in windows of INTEHEAD's NICONZ and
    NSCONZ entries for NCWMAX connections; ZWEL holds the well names.
    """
    deck = Path(deck)
    out.mkdir(parents=True, exist_ok=True)
    for entry in deck.parent.iterdir():
        if entry != deck and not (out / entry.name).exists():
            (out / entry.name).symlink_to(entry.resolve())
    lines = deck.read_text(errors="replace").splitlines(keepends=True)
    keywords = [line.split("--")[0].strip().upper() for line in lines]
    schedule = keywords.index("SCHEDULE")
    stop = next(i for i in range(schedule, len(lines)) if keywords[i] in ("TSTEP", "DATES"))
    copy = out / deck.name
    copy.write_text("".join(lines[:stop]) + f"RPTRST\n 'BASIC=1' /\nTSTEP\n {step_days} /\nEND\n")
    res = subprocess.run(
        [flow_executable(), "--threads-per-process=1", f"--output-dir={out / 'flow'}", str(copy)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    case = out / "flow" / deck.stem.upper()
    restart = Path(f"{case}.UNRST") if Path(f"{case}.UNRST").exists() else Path(f"{case}.X0001")
    rst = read_keywords(restart)
    egrid = read_keywords(Path(f"{case}.EGRID"))
    nx, ny = (int(v) for v in egrid["GRIDHEAD"][1:3])
    head = rst["INTEHEAD"]
    nwells, ncwmax, niconz, nsconz = (int(head[i]) for i in (16, 17, 32, 33))
    icon = rst["ICON"].reshape(nwells, ncwmax, niconz)
    scon = rst["SCON"].reshape(nwells, ncwmax, nsconz)
    names = [bytes(v).decode().strip() if not isinstance(v, str) else v.strip() for v in rst["ZWEL"]]
    names = names[:: len(names) // nwells] if nwells else []
    factors: dict[tuple[str, int], float] = {}
    for w, name in enumerate(names):
        for c in range(ncwmax):
            if icon[w, c, 0] > 0:
                i, j, k = (int(v) - 1 for v in icon[w, c, 1:4])
                factors[(name, i + nx * (j + ny * k))] = float(scon[w, c, 0])
    return factors


# What Flow needs besides a grid to initialise (and briefly run) a model: two phases, simple
# tables, equilibrium. One place for every test that completes a grid into a deck.
PHASES = "OIL\nWATER\nTABDIMS\n 1 1 20 20 /\nEQLDIMS\n 1 /\nSTART\n 1 'JAN' 2020 /\n"
PROPS_AND_SOLUTION = """PROPS
SWOF
 0.0 0.0 1.0 0.0
 1.0 1.0 0.0 0.0 /
PVTW
 200.0 1.0 3.0e-6 0.5 0.0 /
PVDO
 100.0 1.01 1.0
 400.0 1.00 1.0 /
DENSITY
 800 1000 1 /
ROCK
 200.0 1.0e-6 /
SOLUTION
EQUIL
 {datum} 200.0 {owc} 0 {datum} 0 /
"""


def rest_of_deck(datum: float, owc: float, schedule: str = "TSTEP\n 1 /\n") -> str:
    """PROPS to END of a two-phase deck: equilibrium at ``datum`` (200 bar) with the oil-water
    contact at ``owc`` (depths in the deck's length unit), then ``schedule``."""
    return PROPS_AND_SOLUTION.format(datum=datum, owc=owc) + "SCHEDULE\n" + schedule + "END\n"


def assert_same_connections(ours: dict[tuple[int, int], float], ref: dict[tuple[int, int], float]) -> None:
    """The same cell pairs, T within 1e-6 relative (1e-11 absolute: INIT stores float32)."""
    assert set(ours) == set(ref), (sorted(set(ours) - set(ref))[:5], sorted(set(ref) - set(ours))[:5])
    pairs = list(ref)
    a, b = np.array([ours[p] for p in pairs]), np.array([ref[p] for p in pairs])
    worst = int(np.argmax(np.abs(a - b) - 1e-6 * np.abs(b))) if pairs else 0
    assert np.all(np.abs(a - b) <= 1e-6 * np.abs(b) + 1e-11), (pairs[worst], a[worst], b[worst])
