"""Stage files read together: their attributes read back (gridlib.io.netcdf_parts), and files of
different grids refused."""

from __future__ import annotations


def test_stage_attributes_decode_json_and_keep_other_text(tmp_path):
    """read_attrs decodes JSON lists and mappings; text that only starts with a bracket stays text."""
    import xarray as xr

    from gridlib.io.netcdf_parts import read_attrs

    path = tmp_path / "a.nc"
    attrs = {"fault_names": '["F1", "F2"]', "note": "[not json", "map": '{"a": 1}', "n": 3}
    xr.Dataset(attrs=attrs).to_netcdf(path, engine="netcdf4")
    got = read_attrs(path)
    assert got["fault_names"] == ["F1", "F2"] and got["map"] == {"a": 1}
    assert got["note"] == "[not json" and int(got["n"]) == 3


def test_stage_files_of_different_grids_fail_naming_both_files(tmp_path):
    """The transmissibility, Flow deck and export stages read several stage files of one case; a
    geometry, rock or transmissibility file of another grid ends in an InputError that names
    the file and the grid file, and writes nothing."""
    import re

    import pytest
    import yaml
    from artifacts import run_case_without_pictures

    from gridlib.config import load_case
    from gridlib.errors import InputError
    from gridlib.stages import case_outputs, stage_export, stage_flow_deck, stage_transmissibility

    def build(name, counts):
        data = {
            "name": name,
            "grid": {
                "type": "layered",
                "areal": {"sites": {"pattern": "hexagonal", "counts": counts, "spacing": 10.0}},
                "layers": {"top": 1000.0, "thickness": [5.0, 5.0]},
            },
            "petrophysics": {"porosity": {"constant": 0.2}, "permeability": {"constant": 100}},
        }
        case = tmp_path / f"{name}.yaml"
        case.write_text(yaml.safe_dump(data, sort_keys=False))
        run_case_without_pictures(case, tmp_path / name)
        return load_case(case), case_outputs(name, tmp_path / name)

    case, a = build("small", [4, 3])
    _, b = build("large", [5, 4])
    out = tmp_path / "new"
    out.mkdir()

    def fails(file, call):
        message = rf"^{re.escape(str(file))}: 80 cells, but {re.escape(str(a['grid']))} has 48 \(stage files"
        with pytest.raises(InputError, match=message):
            call()
        assert list(out.iterdir()) == []

    t = out / "transmissibility.nc"
    stage_files = {key: a[key] for key in ("grid", "geometry", "petrophysics")}

    def transmissibility(**other):
        return stage_transmissibility(case, **(stage_files | other), transmissibility=t)

    fails(b["geometry"], lambda: transmissibility(geometry=b["geometry"]))
    fails(b["petrophysics"], lambda: transmissibility(petrophysics=b["petrophysics"]))
    deck = out / "SMALL.DATA"
    fails(
        f"{b['transmissibility']}: porv",
        lambda: stage_flow_deck(case, **stage_files, transmissibility=b["transmissibility"], flow_deck=deck),
    )
    exports = {key: out / f"small.{key}" for key in ("nc", "faults")}
    fails(
        f"{b['transmissibility']}: porv",
        lambda: stage_export(
            case,
            **stage_files,
            transmissibility=b["transmissibility"],
            **exports,
            summary=out / "summary.json",
        ),
    )
