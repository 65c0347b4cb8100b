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

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from deck_cases import (
    DIMS,
    SEED,
    anisotropic_rock,
    assert_close,
    assert_stage_file_equals_flow,
    build,
    write_case,
    write_deck,
)
from flow_tools import flow_connections, read_keywords, run_flow_dry

from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.io.rock_file import read_rock


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
    glob, _ = assert_stage_file_equals_flow(paths["transmissibility"], ref, ref_init["PORV"])

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
