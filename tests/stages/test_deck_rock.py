"""A deck case keeps its deck's rock and connection keywords through the stages.

An anisotropic faulted deck (PERMY != PERMX, PERMZ, NTG < 1, MULTZ, MULTX-, MULTFLT on the
fault with throw, MULTREGT on FLUXNUM and, by GRIDOPTS' default, on MULTNUM) as a case
without a petrophysics section goes grid -> geometry -> petrophysics -> transmissibility ->
flow_deck; OPM Flow's dry run of the written deck must give the connections,
transmissibilities and pore volumes of its dry run of the original deck (1e-6 relative;
Flow writes float32), and transmissibility.nc Flow's. Then each petrophysics key of a case
replaces exactly its keywords (config/README.md), and what a deck case needs is checked
with clear messages.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from flow_tools import flow_connections, read_keywords, rest_of_deck, run_flow_dry

from gridlib.config import load_case
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import write_grdecl
from gridlib.stages.flow_deck import stage_flow_deck
from gridlib.stages.geometry import stage_geometry
from gridlib.stages.grid import stage_grid
from gridlib.stages.petrophysics import read_rock, stage_petrophysics
from gridlib.stages.transmissibility import read_transmissibility, stage_transmissibility

DIMS = (6, 5, 4)  # nx even: the fault of simple_grdecl lies between columns 3 and 4
SEED = 3


def anisotropic_rock(rng: np.random.Generator, keywords: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Random rock and region keywords, one value per cell (those named in ``keywords``)."""
    nx, ny, nz = DIMS
    nc = nx * ny * nz
    j, k = np.arange(nc) // nx % ny, np.arange(nc) // (nx * ny)
    every = {
        "PORO": rng.uniform(0.1, 0.3, nc),
        "PERMX": rng.lognormal(4, 1, nc),
        "PERMY": rng.lognormal(3, 1, nc),
        "PERMZ": rng.lognormal(1, 1, nc),
        "NTG": rng.uniform(0.3, 0.9, nc),
        "FLUXNUM": 1.0 + (k >= 2),
        "MULTNUM": 3.0 + (j >= 2),
    }
    return {key: every[key] for key in keywords}


GRID_KEYWORDS = """EQUALS
 'MULTZ' 0.25 1 6 1 5 1 1 /
 'MULTX-' 0.5 2 3 1 5 2 4 /
/
FAULTS
 'F1' 3 3 1 5 1 4 X /
/
MULTFLT
 'F1' 0.3 /
/
MULTREGT
 3 4 0.45 XYZ ALL 1* /
 1 2 0.6 XYZ ALL F /
/
"""


def write_deck(folder: Path, keywords: tuple[str, ...], grid: str = GRID_KEYWORDS) -> Path:
    """ANISO.DATA in ``folder``: the faulted deck (throw 12 m) with ``keywords`` of
    :func:`anisotropic_rock` and the GRID-section text ``grid``, METRIC, oil-water."""
    folder.mkdir(parents=True, exist_ok=True)
    deck = simple_grdecl(DIMS, 12.0, phys_dims=(600.0, 500.0, 40.0))
    deck = replace(
        deck,
        coord=deck.coord + np.tile([0, 0, 1000.0], 2 * (DIMS[0] + 1) * (DIMS[1] + 1)),
        zcorn=deck.zcorn + 1000.0,
    )  # below the surface, as the Flow deck's equilibrium expects
    write_grdecl(folder / "ANISO.GRDECL", deck, anisotropic_rock(np.random.default_rng(SEED), keywords))
    nx, ny, nz = DIMS
    text = f"RUNSPEC\nDIMENS\n {nx} {ny} {nz} /\nOIL\nWATER\nMETRIC\nTABDIMS\n 1 1 20 20 /\n"
    text += "GRIDOPTS\n 'NO' 1 /\n"  # NRMULT > 0: MULTREGT's default region set is MULTNUM
    text += "EQLDIMS\n 1 /\nSTART\n 1 'JAN' 2020 /\nUNIFOUT\nGRID\nINIT\nINCLUDE\n 'ANISO.GRDECL' /\n"
    text += grid + rest_of_deck(float(deck.zcorn.min()), float(deck.zcorn.max()) + 1)
    (folder / "ANISO.DATA").write_text(text)
    return folder / "ANISO.DATA"


def write_case(folder: Path, name: str, petrophysics: dict | None = None) -> Path:
    data = {"name": name, "grid": {"type": "deck", "file": "ANISO.DATA"}}
    if petrophysics is not None:
        data["petrophysics"] = petrophysics
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def build(case: Path, out: Path, flow_deck: bool = False) -> dict[str, Path]:
    """The stages of a deck case into ``out``, as the workflow runs them."""
    out.mkdir(parents=True, exist_ok=True)
    paths = {k: out / f"{k}.nc" for k in ("grid", "geometry", "petrophysics", "transmissibility")}
    paths["grdecl"] = out / "grid.grdecl"
    stage_grid(case, paths["grid"], None, paths["grdecl"])
    stage_geometry(case, paths["grid"], paths["geometry"])
    stage_petrophysics(case, paths["grid"], paths["geometry"], paths["petrophysics"])
    if flow_deck:
        p = paths
        stage_transmissibility(
            case, p["grid"], p["geometry"], p["petrophysics"], p["transmissibility"], p["grdecl"]
        )
        paths["flow_deck"] = out / "flow" / f"{load_case(case).flow_name}.DATA"
        stage_flow_deck(
            case,
            p["grid"],
            p["geometry"],
            p["petrophysics"],
            p["transmissibility"],
            paths["flow_deck"],
            p["grdecl"],
        )
    return paths


def assert_close(ours: dict, ref: dict, what: str) -> None:
    assert set(ours) == set(ref), (what, sorted(set(ours) ^ set(ref))[:5])
    keys = list(ref)
    a, b = np.array([ours[p] for p in keys]), np.array([ref[p] for p in keys])
    worst = int(np.argmax(np.abs(a - b) / np.abs(b)))
    assert np.all(np.abs(a - b) <= 1e-6 * np.abs(b)), (what, keys[worst], a[worst], b[worst])


def split_by_kind(conn: dict[tuple[int, int], float]) -> dict[str, dict[tuple[int, int], float]]:
    """Flow's connections as TRANX, TRANY, TRANZ (logical neighbours) and NNC (the rest)."""
    nx, ny, _ = DIMS
    kinds: dict[str, dict[tuple[int, int], float]] = {"TRANX": {}, "TRANY": {}, "TRANZ": {}, "NNC": {}}
    for (a, b), t in conn.items():
        step = b - a
        key = {1: "TRANX", nx: "TRANY", nx * ny: "TRANZ"}.get(step, "NNC")
        if key == "TRANX" and a % nx == nx - 1:
            key = "NNC"
        kinds[key][(a, b)] = t
    return kinds


@pytest.mark.parametrize(
    "keywords",
    [
        ("PORO", "PERMX", "PERMY", "PERMZ", "NTG", "FLUXNUM", "MULTNUM"),
        ("PORO", "PERMX", "FLUXNUM", "MULTNUM"),
    ],
    ids=["anisotropic", "permx-only"],
)
def test_deck_case_gives_flow_the_original_decks_connections(keywords, tmp_path):
    """No petrophysics section: the case has the deck's rock, and Flow computes on the deck the
    workflow writes what it computes on the original (PERMY and PERMZ default to PERMX in
    Flow; so they do in petrophysics.nc)."""
    original = write_deck(tmp_path / "deck", keywords)
    case = write_case(tmp_path / "deck", "aniso")
    assert load_case(case).has_petrophysics  # implied by the deck's PORO and PERMX
    paths = build(case, tmp_path / "out", flow_deck=True)

    ref_case = run_flow_dry(original, tmp_path / "flow_original")
    new_case = run_flow_dry(paths["flow_deck"], tmp_path / "flow_written")
    ref, new = flow_connections(ref_case), flow_connections(new_case)
    ref_kinds, new_kinds = split_by_kind(ref), split_by_kind(new)
    assert all(ref_kinds[k] for k in ref_kinds), {k: len(v) for k, v in ref_kinds.items()}  # NNCs: the throw
    for kind in ref_kinds:
        assert_close(new_kinds[kind], ref_kinds[kind], kind)
    ref_init, new_init = read_keywords(Path(f"{ref_case}.INIT")), read_keywords(Path(f"{new_case}.INIT"))
    for key in ("PORV", "PERMX", "PERMY", "PERMZ", "NTG"):  # Flow's INIT lacks what the deck does not give
        if key in ref_init:
            assert np.array_equal(new_init[key], ref_init[key]), key
    for key in ("PERMY", "PERMZ"):
        if key not in ref_init:
            assert np.array_equal(new_init[key], ref_init["PERMX"]), key

    # transmissibility.nc holds Flow's connections and pore volumes too
    variables, _ = read_transmissibility(paths["transmissibility"])
    glob = variables["cell_flow_index"].values
    pairs = np.sort(glob[variables["connection_cells"].values], axis=1)
    ours = dict(zip(map(tuple, pairs.tolist()), variables["trans"].values.tolist(), strict=True))
    assert_close(ours, ref, "transmissibility.nc")
    flow_porv = ref_init["PORV"][glob].astype(np.float64)
    assert np.all(np.abs(variables["porv"].values - flow_porv) <= 1e-6 * flow_porv)

    rock = read_rock(paths["petrophysics"])
    data = anisotropic_rock(np.random.default_rng(SEED), keywords)
    for key, name in (("PERMY", "permy"), ("PERMZ", "permz")):
        assert np.array_equal(rock[name], data.get(key, data["PERMX"])[glob]), name
    assert np.array_equal(rock["ntg"], data["NTG"][glob] if "NTG" in data else np.ones(glob.size))


# What each case key replaces (config/README.md): the case's petrophysics, and the arrays of
# petrophysics.nc it sets, each a function of the deck's arrays; the others stay the deck's.
KX, KV, PHI, NTG = 50.0, 0.2, 0.25, 0.8
OVERRIDES = {
    "porosity": ({"porosity": {"constant": PHI}}, {"poro": lambda d: PHI}),
    "permeability": ({"permeability": {"constant": KX}}, {"permx": lambda d: KX, "permy": lambda d: KX}),
    "kv_kh": ({"kv_kh": KV}, {"permz": lambda d: KV * d["PERMX"]}),
    "permeability_kv_kh": (
        {"permeability": {"constant": KX}, "kv_kh": KV},
        {"permx": lambda d: KX, "permy": lambda d: KX, "permz": lambda d: KV * KX},
    ),
    "ntg": ({"ntg": {"constant": NTG}}, {"ntg": lambda d: NTG}),
    "permeability_deck": (
        {"permeability": {"deck": "PERMY"}},
        {"permx": lambda d: d["PERMY"], "permy": lambda d: d["PERMY"]},
    ),
}
ROCK = {"PORO": "poro", "PERMX": "permx", "PERMY": "permy", "PERMZ": "permz", "NTG": "ntg"}


@pytest.fixture(scope="module")
def deck_folder(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("aniso")
    write_deck(folder, (*ROCK, "FLUXNUM", "MULTNUM"))
    return folder


@pytest.mark.parametrize("which", list(OVERRIDES))
def test_a_case_key_replaces_exactly_its_keywords(which, deck_folder, tmp_path):
    spec, replaced = OVERRIDES[which]
    paths = build(write_case(deck_folder, which, spec), tmp_path / "out")
    rock = read_rock(paths["petrophysics"])
    deck = anisotropic_rock(np.random.default_rng(SEED), tuple(ROCK))  # every cell active: grid order
    assert rock["poro"].size == deck["PORO"].size
    for keyword, name in ROCK.items():
        expected = replaced[name](deck) if name in replaced else deck[keyword]
        assert np.array_equal(rock[name], np.broadcast_to(expected, rock[name].shape)), (which, name)
    with xr.open_dataset(paths["petrophysics"]) as ds:
        for keyword, name in ROCK.items():
            source = ds[name].attrs["source"]
            if name in replaced:
                assert source.startswith("petrophysics."), (name, source)
            else:
                assert source == f"the deck's {keyword}", (name, source)


def test_what_a_deck_case_needs(tmp_path):
    """A deck without PORO and PERMX gives no rock by itself; a case on it needs porosity (and gets
    the defaults of other grids: Carman-Kozeny, kv_kh 0.1); bad deck values name the keyword and cell;
    every other grid still needs porosity."""
    geometry_only = tmp_path / "geometry_only"
    write_deck(geometry_only, ("FLUXNUM", "MULTNUM"))
    assert not load_case(write_case(geometry_only, "bare")).has_petrophysics
    case = write_case(geometry_only, "needs_poro", {"kv_kh": 0.5})
    with pytest.raises(InputError, match=r"needs_poro.yaml: petrophysics.porosity: the deck gives no PORO"):
        build(case, tmp_path / "out1")
    case = write_case(geometry_only, "own_rock", {"porosity": {"constant": 0.2}})
    rock = read_rock(build(case, tmp_path / "out2")["petrophysics"])
    assert np.allclose(rock["permx"], 21.72, atol=0.01) and np.array_equal(rock["permz"], 0.1 * rock["permx"])

    bad = tmp_path / "bad"
    write_deck(bad, ("PORO", "PERMX", "NTG"), grid="EQUALS\n 'PERMX' -5 2 2 3 3 4 4 /\n/\n")
    with pytest.raises(
        InputError, match=r"ANISO.DATA: PERMX: 1 cells have a negative or undefined PERMX .*\(2, 3, 4\)"
    ):
        build(write_case(bad, "bad"), tmp_path / "out3")

    other = tmp_path / "cart.yaml"
    other.write_text(
        yaml.safe_dump(
            {"name": "cart", "grid": {"type": "cartesian", "dims": [2, 2]}, "petrophysics": {"kv_kh": 0.5}}
        )
    )
    with pytest.raises(InputError, match=r"cart.yaml: petrophysics.porosity: required"):
        load_case(other)

    poro_only = tmp_path / "poro_only"
    write_deck(poro_only, ("PORO", "FLUXNUM", "MULTNUM"))
    assert not load_case(write_case(poro_only, "poro_only")).has_petrophysics


def test_the_edit_section_is_said_to_be_left_out(tmp_path, caplog):
    """grid.grdecl (a GRID include) holds no EDIT section: the grid stage says so."""
    folder = tmp_path / "d"
    write_deck(folder, ("PORO", "PERMX", "FLUXNUM", "MULTNUM"))
    text = (
        (folder / "ANISO.DATA")
        .read_text()
        .replace("PROPS\n", "EDIT\nMULTIPLY\n 'TRANX' 0.5 /\n/\nPROPS\n", 1)
    )
    (folder / "ANISO.DATA").write_text(text)
    with caplog.at_level("INFO", logger="gridlib.stages"):
        stage_grid(write_case(folder, "edited"), tmp_path / "grid.nc", None, tmp_path / "grid.grdecl")
    assert "the deck's EDIT section (TRANX/TRANY/TRANZ) is not in" in caplog.text
