"""Stage helpers (gridlib.stages.common): the attributes of a stage file read back."""

from __future__ import annotations


def test_stage_attributes_decode_json_and_keep_other_text(tmp_path):
    """read_attrs decodes JSON lists and mappings; text that only starts with a bracket stays text."""
    import xarray as xr

    from gridlib.stages.common import read_attrs

    path = tmp_path / "a.nc"
    attrs = {"fault_names": '["F1", "F2"]', "note": "[not json", "map": '{"a": 1}', "n": 3}
    xr.Dataset(attrs=attrs).to_netcdf(path, engine="netcdf4")
    got = read_attrs(path)
    assert got["fault_names"] == ["F1", "F2"] and got["map"] == {"a": 1}
    assert got["note"] == "[not json" and int(got["n"]) == 3
