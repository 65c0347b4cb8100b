"""A corpus of broken case files: each is refused when the case is read, with one line naming the
case file and the key (in-process, through load_case), and a Snakemake run over all of them
together names every one, one line each, before any job: nothing is run, nothing is written.
A problem only a stage can find (horizons that cross) stops that case's job and leaves nothing
under results/{case}/."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import gridlib as gl
from gridlib.config import load_case

ROOT = Path(__file__).resolve().parents[2]

HORIZONS = """horizons:
  lattice: {x: {start: 0, stop: 1000, num: 11}, y: {start: 0, stop: 800, num: 9}}
  surfaces:
    - {name: top, plane: {depth: 1000}}
    - {name: base, plane: {depth: 1040}}
"""
PEBI = (
    HORIZONS
    + """grid:
  type: pebi
  domain: {rectangle: [0, 0, 1000, 800]}
  cell_size: 100
  layers: 2
"""
)
CORNERPOINT = HORIZONS + "grid: {type: cornerpoint, dims: [10, 8], layers: 2}\n"
CART = "grid: {type: cartesian, dims: [4, 4, 2], lengths: [400, 400, 20], origin: [0, 0, 1000]}\n"
ROCK = "petrophysics: {porosity: {constant: 0.2}, permeability: {constant: 100}}\n"
FIELD = "{model: exponential, len_scale: 200, mean: %s, std: 0.03, bounds: %s}"


def _rock(porosity: str = "{constant: 0.2}", permeability: str = "{constant: 100}", ntg: str = "") -> str:
    extra = f", ntg: {ntg}" if ntg else ""
    return f"petrophysics: {{porosity: {porosity}, permeability: {permeability}{extra}}}\n"


def _faults(*traces: str, names: tuple[str, ...] = ()) -> str:
    names = names or tuple(f"F{k}" for k in range(len(traces)))
    return "faults:\n" + "".join(
        f"  - {{name: {n}, trace: {t}}}\n" for n, t in zip(names, traces, strict=True)
    )


SMALL_DECK = (
    "SPECGRID\n 2 2 1 1 F /\nCOORD\n"
    + "".join(f" {x} {y} 0 {x} {y} 10\n" for y in (0, 1, 2) for x in (0, 1, 2))
    + "/\nZCORN\n 16*0 16*10 /\nPERMX\n 4*100 /\n"
)
HUGE_DECK = "RUNSPEC\nDIMENS\n 10000 10000 100 /\nGRID\nDX\n 1000000000*10 /\n"
SHORT_DECK = SMALL_DECK.replace("PERMX\n 4*100 /", "PERMX\n 3*100 /")
NAN_PILLAR_DECK = SMALL_DECK.replace("COORD\n 0 0 0", "COORD\n nan 0 0")
DECKS = {
    "small.grdecl": SMALL_DECK,
    "huge.DATA": HUGE_DECK,
    "short.grdecl": SHORT_DECK,
    "nan_pillar.grdecl": NAN_PILLAR_DECK,
}

# name -> (the case file's text after its `name:` line, what its one line says after the key)
BROKEN = {
    "misspelled_key": (
        "grid: {type: cartesian, dims: [2, 2], lenghts: [1, 1]}\n",
        "grid: Additional properties are not allowed ('lenghts' was unexpected)",
    ),
    "wrong_type": (
        "grid: {type: cartesian, dims: [2, ten]}\n",
        "grid.dims[1]: 'ten' is not of type 'integer'",
    ),
    "missing_points_file": (
        PEBI.replace("{name: base, plane: {depth: 1040}}", "{name: base, points: base_picks.xyz}"),
        "horizons.surfaces[1].points: file 'base_picks.xyz' not found",
    ),
    "fault_outside": (
        PEBI + "faults:\n  - {name: FX, trace: [[2000, 0], [2000, 800]], throw: 5}\n",
        "faults[0].trace: fault 'FX' lies entirely outside the domain",
    ),
    "well_outside": (
        PEBI + "wells:\n  - {name: P9, point: [1500, 400], rings: {inner: 1, outer: 50}}\n",
        "wells[0].point: well 'P9' at (1500, 400) lies outside the domain",
    ),
    "zero_layers": (PEBI.replace("layers: 2", "layers: 0"), "grid.layers: 0 is less than the minimum of 1"),
    "simulated_well_outside": (
        CART + ROCK + "wells:\n  - {name: W, point: [500, 100]}\n"
        "simulation: {wells: [{name: W, type: producer, bhp: 50}], report_days: [10]}\n",
        "wells[0].point: well 'W' at (500, 100) lies outside the domain",
    ),
    "simulated_well_unknown": (
        PEBI
        + "petrophysics: {porosity: {constant: 0.2}}\n"
        + "wells:\n  - {name: P1, point: [500, 400]}\n"
        + "simulation: {wells: [{name: P2, type: producer, bhp: 50}], report_days: [10]}\n",
        "simulation.wells[0].name: 'P2' is not among the case's wells (wells: P1)",
    ),
    "unknown_grid_type": (
        "grid: {type: hexahedral, dims: [2, 2]}\n",
        "grid.type: 'hexahedral' is not one of",
    ),
    "malformed_yaml": ("grid: {type: cartesian, dims: [2, 2]\n", "not valid YAML"),
    "report_days_backwards": (
        CART + ROCK + "simulation: {report_days: [10, 5]}\n",
        "simulation.report_days[1]: 5 does not come after 10 (days must increase)",
    ),
    "name_not_the_file_name": (
        "name: other\n" + CART,
        "name: 'other' must equal the file name 'name_not_the_file_name'",
    ),
    "seed_negative": ("seed: -1\n" + CART, "seed: -1 is less than the minimum of 0"),
    # YAML: a key given twice is not "the last wins"
    "grid_given_twice": (
        CART + "grid: {type: cartesian, dims: [2, 2]}\n",
        "line 3: key 'grid' given twice (first at line 2)",
    ),
    "dims_given_twice": (
        "grid: {type: cartesian, dims: [2, 2], dims: [3, 3]}\n",
        "line 2: key 'dims' given twice",
    ),
    "throw_given_twice": (
        CART + "faults:\n  - name: F\n    trace: [[100, 0], [100, 400]]\n    throw: 5\n    throw: 8\n",
        "line 7: key 'throw' given twice (first at line 6)",
    ),
    # names given twice
    "well_names_twice": (
        PEBI + "wells:\n  - {name: INJ, point: [200, 200]}\n  - {name: PROD, point: [800, 600]}\n"
        "  - {name: INJ, point: [500, 400]}\n",
        "wells[2].name: 'INJ' is also wells[0]",
    ),
    "fault_names_twice": (
        PEBI + _faults("[[300, 0], [300, 800]]", "[[700, 0], [700, 800]]", names=("F1", "F1")),
        "faults[1].name: 'F1' is also faults[0]",
    ),
    "surface_names_twice": (
        PEBI.replace("name: base", "name: top"),
        "horizons.surfaces[1].name: 'top' is also horizons.surfaces[0]",
    ),
    # fault traces and well paths
    "zero_length_trace": (
        PEBI + _faults("[[500, 100], [500, 100]]"),
        "faults[0].trace[1]: (500, 100) repeats the point",
    ),
    "repeated_trace_point": (
        PEBI + _faults("[[500, 0], [500, 400], [500, 400], [520, 800]]"),
        "faults[0].trace[2]: (500, 400) repeats the point before it",
    ),
    "self_intersecting_trace": (
        PEBI + _faults("[[100, 100], [900, 700], [900, 100], [100, 700]]"),
        "faults[0].trace: fault 'F0''s trace crosses itself",
    ),
    "self_intersecting_path": (
        PEBI + "wells:\n  - {name: H, path: [[100, 100], [900, 700], [900, 100], [100, 700]]}\n",
        "wells[0].path: well 'H''s path crosses itself",
    ),
    "fault_side_not_a_side": (
        PEBI + "wells:\n  - {name: INJ, point: [500, 400], fault_side: up}\n",
        "wells[0].fault_side: 'up' is not one of ['left', 'right']",
    ),
    "fault_side_on_a_path": (
        PEBI + "wells:\n  - {name: H, path: [[100, 100], [900, 700]], fault_side: left}\n",
        "wells[0].fault_side: well 'H' is not a point well",
    ),
    "rings_merge_with_the_well": (
        PEBI + "wells:\n  - {name: W, point: [300, 400], rings: {inner: 0.001, outer: 40}}\n",
        "wells[0].rings.inner: 0.001 m is within 0.01 m (1e-05 of the domain's extent)",
    ),
    "rings_beyond_the_domain": (
        PEBI + "wells:\n  - {name: W, point: [300, 400], rings: {inner: 2, count: 100000, growth: 2}}\n",
        "wells[0].rings: inner x growth^(count - 1) reaches beyond the domain's extent (1000 m)",
    ),
    # numbers that are no numbers
    "throw_nan": (
        PEBI + "faults:\n  - {name: F, trace: [[500, 0], [500, 800]], throw: .nan}\n",
        "faults[0].throw: .nan is not a finite number",
    ),
    "cell_size_inf": (
        PEBI.replace("cell_size: 100", "cell_size: .inf"),
        "grid.cell_size: .inf is not a finite number",
    ),
    "origin_minus_inf": (
        CART.replace("origin: [0, 0", "origin: [-.inf, 0"),
        "grid.origin[0]: -.inf is not a finite number",
    ),
    "porosity_mean_nan": (
        CART + _rock(porosity="{field: %s}" % (FIELD % (".NaN", "[0.1, 0.3]"))),
        "petrophysics.porosity.field.mean: .nan is not a finite number",
    ),
    "dims_inf": ("grid: {type: cartesian, dims: [.inf, 2]}\n", "grid.dims[0]: .inf is not a finite number"),
    "seed_beyond_numpy": (
        "seed: 9223372036854775808\n" + CART,
        "seed: 9223372036854775808 is greater than the maximum",
    ),
    "twist_folds_cells": (
        "grid: {type: cartesian, dims: [20, 20], twist: 0.5}\n",
        "grid.twist: 0.5 is greater than the maximum of 0.1",
    ),
    "origin_astronomic": (
        CART.replace("origin: [0, 0, 1000]", "origin: [0, 0, 1.0e+300]"),
        "grid.origin[2]: 1e+300 is beyond 1e+12 in magnitude",
    ),
    "float_dims": ("grid: {type: cartesian, dims: [4.0, 4]}\n", "grid.dims[0]: 4.0 is not of type 'integer'"),
    # rock values
    "porosity_above_one": (
        CART + _rock(porosity="{constant: 1.5}"),
        "petrophysics.porosity.constant: 1.5 is above 1",
    ),
    "porosity_percent": (
        CART + _rock(porosity="{constant: 20}"),
        "petrophysics.porosity.constant: 20 is above 1 (porosity is a fraction from 0 to 1; "
        "give 0.2 for 20 %)",
    ),
    "porosity_layers_percent": (
        CART + _rock(porosity="{layers: [0.2, 25]}"),
        "petrophysics.porosity.layers[1]: 25 is above 1 (porosity is a fraction from 0 to 1; "
        "give 0.25 for 25 %)",
    ),
    "porosity_bounds_reversed": (
        CART + _rock(porosity="{field: %s}" % (FIELD % ("0.2", "[0.35, 0.05]"))),
        "petrophysics.porosity.field.bounds: [0.35, 0.05] is reversed (give [low, high])",
    ),
    "porosity_bounds_percent": (
        CART + _rock(porosity="{field: %s}" % (FIELD % ("0.2", "[5, 35]"))),
        "petrophysics.porosity.field.bounds[0]: 5 is above 1 (porosity is a fraction from 0 to 1; "
        "give 0.05 for 5 %)",
    ),
    "porosity_negative": (
        CART + _rock(porosity="{constant: -0.1}"),
        "petrophysics.porosity.constant: -0.1 is negative",
    ),
    "permeability_negative": (
        CART + _rock(permeability="{constant: -5}"),
        "petrophysics.permeability.constant: -5 is negative (mD, permeability is at least 0)",
    ),
    "permeability_bounds_reversed": (
        CART + _rock(permeability="{field: %s}" % (FIELD % ("100", "[500, 10]"))),
        "petrophysics.permeability.field.bounds: [500, 10] is reversed",
    ),
    "permeability_median_zero": (
        CART + _rock(permeability="{field: %s}" % (FIELD % ("0", "[0, 10]"))),
        "petrophysics.permeability.field.mean: 0: the median permeability (mD) of the lognormal field "
        "must be positive",
    ),
    "permeability_std_overflows": (
        CART + _rock(permeability="{field: {model: gaussian, len_scale: 100, mean: 100, std: 1000}}"),
        "petrophysics.permeability.field.std: 1000: median x exp(8 std) is beyond any float",
    ),
    "porosity_zero_everywhere": (
        CART + _rock(porosity="{constant: 0}"),
        "petrophysics.porosity.constant: 0 in every cell: no pore volume or flow anywhere",
    ),
    "permeability_zero_layer_harmonic": (
        CART + _rock(permeability="{layers: [100, 0]}") + "coarsen: {method: uniform, dims: [2, 2, 1]}\n",
        "petrophysics.permeability.layers[1]: 0: coarsen.permeability harmonic-arithmetic averaging needs",
    ),
    "ntg_above_one": (CART + _rock(ntg="{constant: 1.2}"), "petrophysics.ntg.constant: 1.2 is above 1"),
    "porosity_layers_count": (
        CART + _rock(porosity="{layers: [0.2, 0.2, 0.2]}"),
        "petrophysics.porosity.layers: 3 values for 2 layers",
    ),
    # reversed ranges
    "tensor_axis_reversed": (
        "grid: {type: tensor, x: {start: 10, stop: 0, num: 3}, y: [0, 1]}\n",
        "grid.x: start 10 is not below stop 0 (node coordinates increase)",
    ),
    "tensor_axis_not_increasing": (
        "grid: {type: tensor, x: [0, 2, 1], y: [0, 1]}\n",
        "grid.x[2]: 1 does not exceed 2",
    ),
    "lattice_reversed": (
        PEBI.replace("{start: 0, stop: 800, num: 9}", "{start: 800, stop: 0, num: 9}"),
        "horizons.lattice.y: start 800 is not below stop 0",
    ),
    "rings_reversed": (
        PEBI + "wells:\n  - {name: W, point: [500, 400], rings: {inner: 50, outer: 5}}\n",
        "wells[0].rings.outer: 5 is below rings.inner 50",
    ),
    "box_reversed": (
        "grid: {type: cartesian, dims: [4, 4]}\ndomain: {box: {min: [3, 3], max: [1, 1]}}\n",
        "domain.box.min[0]: 3 is above domain.box.max[0] 1",
    ),
    "sites_given_twice": (
        "grid: {type: layered, areal: {sites: {pattern: points, xy: [[0, 0], [1, 0], [0, 0], [0, 1]]}}, "
        "layers: {num_layers: 1}}\n",
        "grid.areal.sites.xy[2]: (0, 0) is also xy[0]; give each site once",
    ),
    "sites_on_one_line": (
        "grid: {type: layered, areal: {sites: {pattern: points, xy: [[0, 0], [1, 1], [2, 2]]}}, "
        "layers: {num_layers: 1}}\n",
        "grid.areal.sites.xy: every site lies on one line",
    ),
    "domain_outside_the_grid": (
        CART + "domain: {box: {min: [1000, 0, 0], max: [2000, 400, 2000]}}\n",
        "domain.box: lies outside the grid along x (the grid spans [0, 400] m): no cell is kept",
    ),
    # coarse blocks against the grid
    "coarsen_blocks_beyond_dims": (
        CART + "coarsen: {method: uniform, dims: [8, 2, 1]}\n",
        "coarsen.dims[0]: 8 blocks along i, but the grid has 4 cells there (grid.dims[0])",
    ),
    "coarsen_blocks_beyond_layers": (
        CORNERPOINT + "coarsen: {method: uniform, dims: [2, 2, 5]}\n",
        "coarsen.dims[2]: 5 blocks along k, but the grid has 2 cells there (grid.layers)",
    ),
    "coarsen_pebi_layers": (
        PEBI + "coarsen: {method: uniform, dims: [2, 2, 3]}\n",
        "coarsen.dims[2]: 3 blocks along k, but the grid has 2 cells",
    ),
    "coarsen_tensor_axis": (
        "grid: {type: tensor, x: [0, 1, 2], y: [0, 1]}\ncoarsen: {method: uniform, dims: [3, 1]}\n",
        "coarsen.dims[0]: 3 blocks along i, but the grid has 2 cells there (grid.x)",
    ),
    "coarsen_metis_beyond_cells": (
        CART + "coarsen: {method: metis, blocks: 1000}\n",
        "coarsen.blocks: 1000 blocks for at most 32 cells",
    ),
    "matern_nu_tiny": (
        CART + _rock(porosity="{field: {model: matern, len_scale: 100, nu: 0.01}}"),
        "petrophysics.porosity.field.nu: 0.01 is less than the minimum of 0.2",
    ),
    # decks
    "deck_keyword_missing": (
        "grid: {type: deck, file: small.grdecl}\npetrophysics: {porosity: {deck: PORO}}\n",
        "petrophysics.porosity.deck: small.grdecl gives no PORO (it gives PERMX)",
    ),
    "deck_array_short": (  # the deck is read whole when the case is: its arrays against its dimensions
        "grid: {type: deck, file: short.grdecl}\npetrophysics: {porosity: {constant: 0.2}}\n",
        "short.grdecl:16: PERMX: has 3 values, expected 4",
    ),
    "deck_pillar_not_finite": (
        "grid: {type: deck, file: nan_pillar.grdecl}\npetrophysics: {porosity: {constant: 0.2}}\n",
        "nan_pillar.grdecl:3: COORD: 1 values are not finite numbers within +-1e+100 "
        "(first nan, pillar (1, 1))",
    ),
    "deck_coarsen_beyond_dims": (
        "grid: {type: deck, file: small.grdecl}\ncoarsen: {method: uniform, dims: [1, 3, 1]}\n",
        "coarsen.dims[1]: 3 blocks along j, but the grid has 2 cells there (grid.file (small.grdecl: NY))",
    ),
    # too big for the machine (or the config's max_memory_gb)
    "huge_cornerpoint": (
        HORIZONS + "grid: {type: cornerpoint, dims: [100000, 100000], layers: 1}\n",
        "grid.dims: 10,000,000,000 cells need about",
    ),
    "huge_cartesian": (
        "grid: {type: cartesian, dims: [100000, 100000, 1]}\n",
        "grid.dims: 10,000,000,000 cells need about",
    ),
    "huge_tensor": (
        "grid: {type: tensor, x: {start: 0, stop: 1, num: 100001}, y: {start: 0, stop: 1, num: 100001}, "
        "z: {start: 0, stop: 1, num: 2}}\n",
        "grid.x, grid.y, grid.z: 10,000,000,000 cells need about",
    ),
    "huge_pebi": (
        PEBI.replace("cell_size: 100", "cell_size: 0.001"),
        "grid.cell_size: 1,847,520,861,406 cells need about",
    ),
    "huge_deck": (
        "grid: {type: deck, file: huge.DATA}\n",
        "grid.file (huge.DATA: DIMENS/SPECGRID): 10,000,000,000 cells need about",
    ),
    "huge_layered": (
        "grid: {type: layered, areal: {sites: {pattern: square, counts: [100000, 100000]}}, "
        "layers: {num_layers: 10}}\n",
        "grid.areal.sites: 100,000,000,000 cells need about",
    ),
    "huge_lattice": (
        PEBI.replace("num: 11}", "num: 1000000}").replace("num: 9}", "num: 1000000}"),
        "horizons.lattice: 1,000,000,000,000 nodes x 2 surfaces need about 74,506 GiB in the horizons stage",
    ),
    "astronomic_dims": (
        "grid: {type: cartesian, dims: [1000000000000000000000000000000, 2]}\n",
        "grid.dims: 2e+30 cells need about",
    ),
}


def _case_file(folder: Path, name: str) -> Path:
    text, _ = BROKEN[name]
    path = folder / f"{name}.yaml"
    path.write_text(text if text.startswith("name:") else f"name: {name}\n{text}")
    for deck, body in DECKS.items():
        if deck in text and not (folder / deck).exists():
            (folder / deck).write_text(body)
    return path


def test_the_table_is_large():
    assert len(BROKEN) >= 40


@pytest.mark.parametrize("name", sorted(BROKEN))
def test_a_broken_case_is_refused_when_read(tmp_path, name):
    """One InputError, one line: the file, the key, what is wrong; no numpy repr."""
    path = _case_file(tmp_path, name)
    with pytest.raises(gl.InputError) as info:
        load_case(path)
    message = str(info.value)
    assert message.startswith(f"{path}: ") and "\n" not in message, message
    assert BROKEN[name][1] in message, message
    assert "np.float64(" not in message and "array(" not in message


HUGE = sorted(name for name in BROKEN if name.startswith("huge_"))


def test_oversized_cases_are_refused_before_allocating(tmp_path):
    """1e10 cells of every grid type, and a lattice of 1e12 nodes: the message gives the
    estimate, the memory it needs and the limit, and deciding allocated next to nothing (the
    check is arithmetic on the case's keys and a deck's DIMENS line). A limit given
    (``max_memory_gb``, the config's) replaces the machine's, both ways."""
    import tracemalloc

    assert len(HUGE) >= 7
    for name in HUGE:
        path = _case_file(tmp_path, name)
        tracemalloc.start()
        with pytest.raises(
            gl.InputError, match=r" need about [\d,.e+]+ GiB in the (heaviest|horizons) stage; "
        ):
            load_case(path)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert peak < 4 * 2**20, (name, peak)
    with pytest.raises(
        gl.InputError, match=r"the limit is 1\.0 GiB \(config max_memory_gb; this machine has"
    ):
        load_case(_case_file(tmp_path, "huge_deck"), max_memory_gb=1)
    small = tmp_path / "small.yaml"
    small.write_text("name: small\ngrid: {type: cartesian, dims: [100, 100, 10]}\n")
    with pytest.raises(gl.InputError, match=r"small\.yaml: grid\.dims: 100,000 cells need about 0\.1 GiB"):
        load_case(small, max_memory_gb=0.05)
    assert load_case(small, max_memory_gb=1).data["grid"]["dims"] == [100, 100, 10]


def _snakemake(tmp_path: Path, cases: list[Path]) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
         "--cores", "1", "--config", f"cases=[{','.join(str(c) for c in cases)}]", "studies=[]"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip


def test_one_run_names_every_broken_case_and_runs_nothing(tmp_path):
    """Every case file of the table and one valid case in one run: one line per broken file,
    naming it and the key, no traceback, zero jobs, nothing under results/."""
    config = tmp_path / "config"
    config.mkdir()
    files = {name: _case_file(config, name) for name in BROKEN}
    good = config / "good.yaml"
    good.write_text("name: good\ngrid: {type: cartesian, dims: [2, 2]}\n")
    result = _snakemake(tmp_path, sorted([good, *files.values()]))
    out = result.stdout + result.stderr
    assert result.returncode != 0
    lines = out.splitlines()
    for name, path in files.items():
        found = [line for line in lines if line.startswith(f"{path}: ") and BROKEN[name][1] in line]
        assert len(found) == 1, f"{name}: no line names {path} and says {BROKEN[name][1]!r}:\n{out[-3000:]}"
    assert f"{len(BROKEN)} problem(s) in the case files; nothing was run" in out
    assert "Traceback" not in out and 'File "' not in out, out[-3000:]
    assert "Building DAG" not in out and "localrule" not in out and "Finished job" not in out
    assert not (tmp_path / "results").exists() or not any((tmp_path / "results").rglob("*"))
