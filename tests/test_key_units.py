"""The units of a case's own keys: the case schema's ``x-quantity`` annotations and the dotted
key -> quantity resolution of :mod:`gridlib.config.key_units`."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest
import yaml

from gridlib.config import load_schema
from gridlib.config.key_units import KeyQuantity, annotation_problems, key_quantity, key_unit
from gridlib.errors import InputError
from gridlib.units import FIELD, LAB, METRIC

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "config" / "cases"


def _case(name: str) -> dict:
    return yaml.safe_load((CASES / f"{name}.yaml").read_text())


def test_every_numeric_key_of_the_schema_says_what_it_measures():
    assert annotation_problems() == []


def test_a_new_numeric_key_without_a_quantity_is_found():
    schema = load_schema()
    schema["$defs"]["fault"]["properties"]["dip"] = {"type": "number"}
    schema["$defs"]["well"]["properties"]["depths"] = {"type": "array", "items": {"type": "number"}}
    schema["$defs"]["coarsen"]["properties"]["blocks"]["x-quantity"] = "lenght"
    schema["$defs"]["pebi"]["properties"]["cell_size"]["x-unit-system"] = "SI"
    assert annotation_problems(schema) == [
        "#/$defs/pebi/properties/cell_size: x-unit-system: 'SI' is none of METRIC, FIELD, LAB, PVT-M",
        "#/$defs/fault/properties/dip: a number without x-quantity (what does it measure?)",
        "#/$defs/well/properties/depths: a number without x-quantity (what does it measure?)",
        "#/$defs/coarsen/properties/blocks: x-quantity: 'lenght' is none of length, area, volume, "
        "cell_measure, face_measure, porv, pressure, permeability, transmissibility, fraction, "
        "dimensionless, angle, time, rate, count, inherit, measure",
    ]


def _study_keys() -> list[tuple[str, str]]:
    """(base case, key) of every key the sample studies and docs/studies.md vary."""
    pairs = []
    for path in sorted((ROOT / "config" / "studies").glob("*.yaml")):
        spec = yaml.safe_load(path.read_text())
        base = Path(spec["base"]).stem
        pairs += [(base, key) for key in spec["vary"]]
    return pairs


# The units the varied keys of the sample studies, docs/studies.md and the workflow tests take.
STUDY_KEYS = [
    ("waterflood_pebi", "faults.0.throw", "m", "ft"),
    ("faulted_pebi", "grid.cell_size", "m", "ft"),
    ("faulted_pebi", "petrophysics.porosity.field.mean", "1", "1"),
    ("twisted", "grid.twist", "1", "1"),
    ("twisted", "petrophysics.ntg.constant", "1", "1"),
    ("y_faults_pillars", "grid", None, None),  # whole grid sections (labelled), no unit
]


def test_the_sample_studies_keys_are_in_the_table():
    assert set(_study_keys()) <= {(case, key) for case, key, *_ in STUDY_KEYS}


@pytest.mark.parametrize(("case", "key", "metric", "field"), STUDY_KEYS)
def test_varied_keys_of_the_studies(case, key, metric, field):
    data = _case(case)
    assert key_unit(key, METRIC, data) == metric
    assert key_unit(key, FIELD, data) == field
    assert key_unit(key, METRIC) == metric  # the same without the case: no branch disagrees


# Keys of every grid type, resolved through the branch the case's grid.type selects.
GRID_KEYS = [
    ("twisted", "grid.dims", None),
    ("twisted", "grid.dims.0", None),
    ("twisted", "grid.lengths.2", "m"),
    ("twisted", "grid.origin", "m"),
    ("ellipsoid", "grid.x", "m"),
    ("ellipsoid", "grid.z.num", None),
    ("ellipsoid", "grid.z.stop", "m"),
    ("ellipsoid", "domain.ellipsoid.semi_axes.1", "m"),
    ("honeycomb", "grid.areal.sites.counts.0", None),
    ("honeycomb", "grid.areal.sites.spacing", "m"),
    ("honeycomb", "grid.layers.thickness.0", "m"),
    ("radial_well", "grid.areal.sites.radii.log_step", "1"),
    ("radial_well", "grid.areal.sites.sectors", None),
    ("anticline", "grid.dims.1", None),
    ("anticline", "grid.layers", None),
    ("anticline", "horizons.lattice.x.stop", "m"),
    ("anticline", "horizons.surfaces.0.dome.relief", "m"),
    ("peaks", "horizons.surfaces.1.peaks.amplitude", "m"),
    ("faulted_pebi", "grid.domain.rectangle.2", "m"),
    ("faulted_pebi", "faults.0.trace.1.0", "m"),
    ("composite_wells", "grid.padding", None),
    ("composite_wells", "wells.0.rings.inner", "m"),
    ("composite_wells", "wells.0.rings.growth", "1"),
    ("waterflood_pebi", "simulation.initial.pressure", "bar"),
    ("waterflood_pebi", "simulation.wells.0.rate", "sm3/day"),
    ("waterflood_pebi", "simulation.report_days.0", "day"),
    ("spe9", "grid.tolerance", "m"),
]


@pytest.mark.parametrize(("case", "key", "unit"), GRID_KEYS)
def test_keys_of_each_grid_type(case, key, unit):
    assert key_unit(key, METRIC, _case(case)) == unit


def test_a_deck_case_keys_are_in_the_deck_unit_system():
    spe9 = _case("spe9")
    assert spe9["grid"]["type"] == "deck"
    assert [key_unit("grid.tolerance", s, spe9) for s in (METRIC, FIELD, LAB)] == ["m", "ft", "cm"]
    assert key_unit("simulation.initial.pressure", FIELD, spe9) == "psia"
    assert key_unit("simulation.wells.0.bhp", LAB, spe9) == "atm"
    assert key_unit("simulation.wells.0.rate", FIELD, spe9) == "stb/day"
    assert key_unit("horizons.surfaces.0.plane.azimuth", FIELD) == "degree"


def test_keys_in_a_unit_of_their_own_whatever_the_system():
    grain = "petrophysics.permeability.carman_kozeny.grain_diameter"
    assert key_quantity(grain) == KeyQuantity("length", "METRIC")
    assert key_unit(grain, FIELD) == "m"
    assert key_unit("simulation.report_days", LAB) == "day"  # LAB's time unit is the hour
    assert key_quantity("simulation.report_days") == KeyQuantity("time", "METRIC")


def test_inherit_takes_the_quantity_of_the_property():
    for key, unit in [
        ("petrophysics.permeability.field.mean", "mD"),
        ("petrophysics.permeability.field.bounds.1", "mD"),
        ("petrophysics.permeability.layers.0", "mD"),
        ("petrophysics.porosity.field.bounds", "1"),
        ("petrophysics.ntg.field.mean", "1"),
        ("petrophysics.permeability.field.std", "1"),  # of ln k
        ("petrophysics.permeability.field.len_scale.2", "ft"),  # the grid's length unit
        ("petrophysics.porosity.field.angles.0", "degree"),
    ]:
        assert key_unit(key, FIELD) == unit, key


def test_keys_without_a_unit_and_unknown_keys():
    for key in ("seed", "name", "grid.type", "grid.file", "faults.0.name", "coarsen.blocks"):
        assert key_quantity(key) == KeyQuantity(None), key
    assert key_unit("seed", METRIC) is None
    with pytest.raises(InputError, match=r"^faults\.0\.thro: not a key of the case schema$"):
        key_quantity("faults.0.thro")
    with pytest.raises(InputError, match=r"^grid\.cell_size\.0: not a key"):
        key_quantity("grid.cell_size.0")


def test_a_key_that_measures_different_things_by_grid_needs_the_case():
    schema = copy.deepcopy(load_schema())
    schema["$defs"]["layered"]["properties"]["layers"]["x-quantity"] = "length"  # as if it were
    with pytest.raises(InputError, match=r"grid\.layers: measures length or no unit depending on the grid"):
        key_quantity("grid.layers", schema=schema)
    assert key_quantity("grid.layers", _case("anticline"), schema) == KeyQuantity(None)
    assert key_quantity("grid.layers", _case("honeycomb"), schema) == KeyQuantity("length")


def _numeric_leaves(data, path=()):
    if isinstance(data, dict):
        for k, v in data.items():
            yield from _numeric_leaves(v, (*path, str(k)))
    elif isinstance(data, list):
        for i, v in enumerate(data):
            yield from _numeric_leaves(v, (*path, str(i)))
    elif isinstance(data, int | float) and not isinstance(data, bool):
        yield ".".join(path)


@pytest.mark.parametrize("case", sorted(p.stem for p in CASES.glob("*.yaml")))
def test_every_number_of_every_sample_case_resolves(case):
    data = _case(case)
    counts = {
        "seed",
        "num",
        "dims",
        "counts",
        "sectors",
        "count",
        "padding",
        "layers",
        "num_layers",
        "blocks",
    }
    for key in _numeric_leaves(data):
        quantity = key_quantity(key, data)
        last = next(p for p in reversed(key.split(".")) if not p.isdigit())
        assert (quantity.quantity is None) == (last in counts), key


def _study_tables(tmp_path, monkeypatch, base: dict, vary: dict, summary: dict):
    """study.csv's header, study.nc's coordinates' attributes and study.png's x labels of a
    study of ``base`` (a case's data) varying ``vary``, from its manifest and made-up
    summaries (``summary`` plus each variant's name): the stage in-process, no build."""
    import matplotlib.pyplot as plt
    import xarray as xr

    from gridlib.stages import study as stage
    from gridlib.study import load_study, manifest_text

    (tmp_path / "base.yaml").write_text(yaml.safe_dump(base | {"name": "base"}))
    spec = {"name": "s", "base": "base.yaml", "vary": vary, "combine": "zip"}
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    study = load_study(tmp_path / "s.yaml", tmp_path / "results")
    (tmp_path / "variants.yaml").write_text(manifest_text(study))
    summaries = []
    for v in study.variants:
        summaries.append(tmp_path / f"{v.name}.json")
        summaries[-1].write_text(json.dumps({"case": v.name, **summary}))
    labels = []
    monkeypatch.setattr(
        stage,
        "save_figure",
        lambda fig, path, dpi=None: labels.extend(ax.get_xlabel() for ax in fig.axes) or plt.close(fig),
    )
    out = {k: str(tmp_path / f"study.{k}") for k in ("csv", "nc", "png")}
    stage.stage_study(tmp_path / "variants.yaml", summaries, out)
    with xr.open_dataset(out["nc"]) as ds:
        coords = {key: dict(ds[key].attrs) for key in vary}
    header = (tmp_path / "study.csv").read_text().splitlines()[0].split(",")
    return header, coords, sorted(set(labels) - {""})


def test_a_study_of_a_field_deck_labels_its_keys_in_feet(tmp_path, monkeypatch):
    summary = {"unit_system": "FIELD", "griddim": 3, "cells": 9000, "pore_volume": 1.5e7}
    vary = {"grid.tolerance": [0, 0.5], "petrophysics.kv_kh": [0.1, 0.2], "coarsen.dims.0": [3, 6]}
    spe9 = _case("spe9")
    spe9["grid"] |= {"file": str(CASES / spe9["grid"]["file"]), "tolerance": 0}
    header, coords, labels = _study_tables(tmp_path, monkeypatch, spe9, vary, summary)
    assert header[:6] == [
        "variant",
        "grid.tolerance [ft]",
        "petrophysics.kv_kh [1]",
        "coarsen.dims.0",
        "realisation",
        "seed",
    ]
    assert "pore_volume [ft3]" in header
    assert coords == {
        "grid.tolerance": {"units": "ft"},
        "petrophysics.kv_kh": {"units": "1"},
        "coarsen.dims.0": {},
    }
    assert labels == ["coarsen.dims.0", "grid.tolerance [ft]", "petrophysics.kv_kh [1]"]


def test_a_study_of_a_built_grid_labels_its_keys_in_metres(tmp_path, monkeypatch):
    summary = {"unit_system": "METRIC", "griddim": 3, "cells": 900, "pore_volume": 1.5e5}
    vary = {"faults.0.throw": [0, 30], "petrophysics.permeability.field.mean": [100, 300]}
    header, coords, labels = _study_tables(tmp_path, monkeypatch, _case("waterflood_pebi"), vary, summary)
    assert header[1:3] == ["faults.0.throw [m]", "petrophysics.permeability.field.mean [mD]"]
    assert coords == {
        "faults.0.throw": {"units": "m"},
        "petrophysics.permeability.field.mean": {"units": "mD"},
    }
    assert labels == ["faults.0.throw [m]", "petrophysics.permeability.field.mean [mD]"]


# config/README.md's key tables (from "## A case" to "## Studies"), in order: the case keys
# each table's rows are under; a row's `unit` cell is "<unit>" (the key's, and its unnamed
# descendants'), "`a`, `b`: <unit>" (named keys below it; "; " between parts), "(...)" (said
# elsewhere), "–" (no unit); a unit may be followed by a remark in parentheses; "<u1>, <u2>, ..."
# gives the units of a row's columns in order (a survey station's md, inclination, azimuth).
README_TABLES = [
    [""],
    ["horizons"],
    ["horizons.surfaces.0"],
    ["faults.0", "wells.0"],
    ["grid"],
    ["petrophysics"],
    ["petrophysics.porosity", "petrophysics.permeability", "petrophysics.ntg"],
    ["simulation"],
    ["coarsen"],
    ["pictures"],
    ["outputs"],
    ["domain"],
    ["qc.0"],
]
SAID_ELSEWHERE = "(said elsewhere)"
ALIASES = {"grid.x": ("grid.y", "grid.z")}  # the row `x` says "also `y`, `z`"


def _readme_units() -> list[tuple[str, str, str]]:
    """(table's prefix, row key, unit cell) of every row of the README's case key tables."""
    import re

    text = (ROOT / "config" / "README.md").read_text()
    text = text[text.index("## A case") : text.index("## Studies")]
    tables = text.split("| key | unit | meaning |")[1:]
    assert len(tables) == len(README_TABLES)
    rows = []
    for prefixes, table in zip(README_TABLES, tables, strict=True):
        for key, cell in re.findall(r"^\| `([a-z_0-9]+)` \| ([^|]*) \|", table, flags=re.M):
            rows += [(prefix, key, cell.strip()) for prefix in prefixes]
    return rows


def _cell_units(cell: str) -> tuple[str | None, dict[str, str]]:
    """A unit cell as (the row's own unit or None, {named key: unit}); "–" is None's text."""
    import re

    own, named = None, {}
    for part in cell.split("; "):
        if part.startswith("("):
            continue
        m = re.match(r"^((?:`[a-z_0-9]+`(?:, )?)+): (.*)$", part)
        text = m.group(2) if m else part
        unit = SAID_ELSEWHERE if text.startswith("(") else text.split(" (")[0]
        if m:
            named |= dict.fromkeys(re.findall(r"`([a-z_0-9]+)`", m.group(1)), unit)
        else:
            own = unit
    return own, named


def test_config_readme_gives_every_numeric_key_its_unit():
    from gridlib.config.key_units import numeric_keys

    keys = numeric_keys()
    covered: set[str] = set()
    for prefix, row, cell in _readme_units():
        own, named = _cell_units(cell)
        heads = [f"{prefix}.{row}".lstrip(".")]
        heads += list(ALIASES.get(heads[0], ()))
        for key, quantity in keys.items():
            head = next((h for h in heads if key == h or key.startswith(h + ".")), None)
            if head is None:
                continue
            rest = [p for p in key[len(head) :].split(".") if p and not p.isdigit()]
            unit = named.get(rest[-1]) if rest else None
            unit = unit or (own if not rest or rest[-1] not in named else None)
            if unit is not None and ", " in unit:  # a row's columns (a survey station's md, angles)
                unit = unit.split(", ")[int(key.rsplit(".", 1)[-1])]
            if unit is None:
                if cell.startswith("(") and not rest:
                    covered.add(key)  # said elsewhere (a property's values)
                continue
            if unit != SAID_ELSEWHERE:  # a property's values: the unit of the property they give
                assert unit == (quantity.unit(METRIC) or "–"), (key, cell)
            covered.add(key)
    assert sorted(set(keys) - covered) == []


def test_variants_in_different_unit_systems_give_each_unit_with_its_rows():
    from gridlib.stages.study import key_header, key_units

    manifest = {
        "keys": ["grid.tolerance", "grid.file", "simulation.report_days.0"],
        "key_quantities": {
            "grid.tolerance": {"quantity": "length"},
            "grid.file": {"quantity": None},
            "simulation.report_days.0": {"quantity": "time", "unit_system": "METRIC"},
        },
    }
    rows = [{"unit_system": "FIELD"}, {"unit_system": "METRIC"}, {"unit_system": "FIELD"}]
    units = key_units(manifest, rows)
    assert units == {
        "grid.tolerance": {"ft": ["FIELD"], "m": ["METRIC"]},
        "grid.file": {},
        "simulation.report_days.0": {"day": ["FIELD", "METRIC"]},
    }
    assert [key_header(k, u) for k, u in units.items()] == [
        "grid.tolerance [ft: FIELD; m: METRIC]",
        "grid.file",
        "simulation.report_days.0 [day]",
    ]
    with pytest.raises(InputError, match="the summary of variant v1 has no unit_system"):
        key_units(manifest, [{"variant": "v1"}])
