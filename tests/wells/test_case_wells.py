"""Trajectory and survey wells in a case (issue 26): the schema's ``wells`` keys, the checks that
name the case file and the key of every mistake (each message exact), and the paths
:func:`gridlib.case.wells.case_well_paths` reads (branches continue their parent's MD)."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from gridlib.case.wells import case_well_paths, pebi_wells
from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.wells.survey import minimum_curvature

# A 1000 x 800 x 40 m box at 2000 m depth; P2 a horizontal producer from a file (x y z md),
# I1 an injector built from vertical to 45 degrees east by a survey.
P2 = np.array(
    [
        [100.0, 400.0, 1950.0, 1950.0],
        [160.0, 400.0, 2030.0, 2050.0],
        [900.0, 400.0, 2030.0, 2790.0],
    ]
)
CASE = {
    "name": "c",
    "grid": {
        "type": "cartesian",
        "dims": [10, 8, 4],
        "lengths": [1000.0, 800.0, 40.0],
        "origin": [0, 0, 2000],
    },
    "wells": [
        {"name": "P2", "trajectory": "data/p2.xyz", "perforations": [[2100, 2700]], "radius": 0.108},
        {
            "name": "I1",
            "survey": {
                "head": [500.0, 200.0, 1800.0],
                "stations": [[1800, 0, 90], [2000, 45, 90], [2100, 45, 90]],
            },
        },
    ],
}


def _table(rows: np.ndarray) -> str:
    return "\n".join(" ".join(f"{v:g}" for v in row) for row in rows) + "\n"


def _case(tmp_path: Path, data: dict, files: dict[str, str] | None = None) -> Path:
    (tmp_path / "data").mkdir(exist_ok=True)
    (tmp_path / "data" / "p2.xyz").write_text(_table(P2))
    for name, text in (files or {}).items():
        (tmp_path / "data" / name).write_text(text)
    path = tmp_path / "c.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def _with(change) -> dict:
    data = copy.deepcopy(CASE)
    change(data)
    return data


def test_a_case_with_a_trajectory_and_a_survey_well_reads_their_paths(tmp_path):
    case = load_case(_case(tmp_path, CASE))
    assert case.has_deviated_wells
    p2, i1 = case_well_paths(case)
    assert (p2.name, p2.key, p2.radius, p2.skin, p2.branches) == ("P2", "wells[0]", 0.108, 0.0, ())
    np.testing.assert_array_equal(p2.path.xyz, P2[:, :3])
    np.testing.assert_array_equal(p2.path.md, P2[:, 3])
    np.testing.assert_array_equal(p2.perforations[0], [[2100.0, 2700.0]])
    expected = minimum_curvature([500.0, 200.0, 1800.0], CASE["wells"][1]["survey"]["stations"], step=10.0)
    np.testing.assert_array_equal(i1.path.xyz, expected.xyz)
    np.testing.assert_array_equal(i1.path.md, expected.md)
    assert (i1.radius, i1.perforations[0].tolist()) == (None, [[1800.0, 2100.0]])  # default: whole path
    assert pebi_wells(case) == []  # deviated wells are not point or map-path wells


def test_a_branch_without_md_continues_its_parents(tmp_path):
    branch = np.array([[300.0, 400.0, 2030.0], [300.0, 700.0, 2035.0]])  # off P2 at MD 2190
    files = {"b1.xyz": _table(branch)}
    data = _with(lambda d: d["wells"][0].update(branches=[{"trajectory": "data/b1.xyz"}]))
    (p2, _) = case_well_paths(load_case(_case(tmp_path, data, files)))
    (b1,) = p2.branches
    assert (b1.name, p2.parents) == ("P2:1", (0,))
    np.testing.assert_array_equal(b1.md, [2190.0, 2190.0 + np.hypot(300.0, 5.0)])
    np.testing.assert_array_equal(p2.perforations[1], [b1.md[[0, -1]]])


def _raises(tmp_path: Path, data: dict, message: str, files: dict[str, str] | None = None) -> None:
    path = _case(tmp_path, data, files)
    with pytest.raises(InputError) as info:
        load_case(path)
    assert str(info.value) == f"{path}: {message}"


def _set(key: str, value):
    def change(data):
        *head, last = key.split(".")
        node = data
        for part in head:
            node = node[int(part)] if part.isdigit() else node[part]
        node[int(last) if last.isdigit() else last] = value

    return change


MISTAKES = [
    (
        _set("wells.0.point", [1, 2]),
        "wells[0]: give exactly one of point, path, trajectory, survey (got point, trajectory)",
    ),
    (
        _set("wells.0.perforations", [[2400, 2150]]),
        "wells[0].perforations[0]: MD interval [2400, 2150]: 2400 is not below 2150; give [from, to] with "
        "from < to",
    ),
    (
        _set("wells.0.perforations", [[2100, 2800]]),
        "wells[0].perforations[0]: MD interval [2100, 2800] reaches beyond the path of 'P2' (MD 1950 to "
        "2790)",
    ),
    (
        _set("wells.0.perforations", [[2500, 2700], [2100, 2550]]),
        "wells[0].perforations[1]: MD interval [2100, 2550] overlaps perforations[0] [2500, 2700]; give "
        "each MD once",
    ),
    (
        _set("wells.0.trajectory", "data/p3.xyz"),
        "wells[0].trajectory: file 'data/p3.xyz' not found (looked for {tmp}/data/p3.xyz)",
    ),
    (
        _set("wells.0.trajectory", {"file": "data/p3.xyz", "format": "rms"}),
        "wells[0].trajectory.file: file 'data/p3.xyz' not found (looked for {tmp}/data/p3.xyz)",
    ),
    (
        _set("wells.1.survey.stations", [[1800, 0, 90], [1790, 45, 90]]),
        "wells[1].survey.stations[1][0]: md 1790 does not exceed the station before it (1800); MD increases "
        "along the hole",
    ),
    (
        _set("wells.1.survey.stations", [[1800, 0, 90], [2000, 190, 90]]),
        "wells[1].survey.stations[1][1]: inclination 190 is outside [0, 180] degrees (0 is straight down, "
        "90 horizontal)",
    ),
    (
        _set("wells.1.survey", {"head": [500, 200, 1800], "file": "data/i1.dev"}),
        "wells[1].survey.file: file 'data/i1.dev' not found (looked for {tmp}/data/i1.dev)",
    ),
    (
        _set("wells.1.rings", {"inner": 1.0, "outer": 10.0}),
        "wells[1].rings: rings go with a vertical well at a point; well 'I1' is a survey well",
    ),
    (
        _set("wells.1", {"name": "V1", "point": [500, 300], "skin": 2}),
        "wells[1].skin: well 'V1' is a vertical well at a point; perforations, radius, skin, branches go "
        "with a trajectory or survey well",
    ),
    (
        _set("grid", {"type": "cartesian", "dims": [10, 8], "lengths": [1000.0, 800.0]}),
        "wells[0].trajectory: well 'P2': a 2-D grid has no depth (give the grid a third axis)",
    ),
    (
        _set("wells.1.survey.head", [5000, 200, 1800]),
        "wells[1].survey: well 'I1' lies entirely outside the domain (in plan view)",
    ),
    (
        _set("wells.0.branches", [{"trajectory": "data/b1.xyz"}]),
        "wells[0].branches[0].trajectory: branch 'P2:1' starts at (300, 410, 2030), 10 from the nearest path "
        "of well 'P2' (its main path or an earlier branch); a branch starts on its parent's path (within 1 "
        "in the case's length unit)",
    ),
    (
        _set("wells.0.branches", [{"trajectory": "data/b2.xyz"}]),
        "wells[0].branches[0].trajectory: branch 'P2:1' starts at MD 2180, but its parent's path is at MD "
        "2190 there; give MD that continues the parent's (within 1), or none",
    ),
    (
        _set("wells.0.branches", [{"trajectory": "data/b3.xyz", "perforations": [[2190, 2600]]}]),
        "wells[0].branches[0].perforations[0]: MD interval [2190, 2600] reaches beyond the path of 'P2:1' "
        "(MD 2190 to 2490.041664)",
    ),
    (  # a lateral's file that repeats P2's hole from its head: P2's cells would be completed twice
        _set("wells.0.branches", [{"trajectory": "data/b4.xyz"}]),
        "wells[0].branches[0].trajectory: branch 'P2:1' runs along the path of its parent from its start at "
        "(100, 400, 1950) for 30 or more: give the branch's own hole only, from where it leaves its parent "
        "(its cells would be completed twice)",
    ),
]
MISTAKES.append(
    (
        _set("wells.0.trajectory", "data/broken.xyz"),
        "wells[0].trajectory: {tmp}/data/broken.xyz: line 2: expected 4 fields, found 3",
    )
)
BRANCHES = {
    "broken.xyz": "100 400 1950 1950\n160 400 2030\n",
    "b1.xyz": "300 410 2030\n300 700 2035\n",  # 10 m off P2
    "b2.xyz": "300 400 2030 2180\n300 700 2035 2481\n",  # MD 10 m short of P2's there
    "b3.xyz": "300 400 2030\n300 700 2035\n",
    "b4.xyz": "100 400 1950\n160 400 2030\n300 400 2030\n300 700 2035\n",  # P2's hole to MD 2190, then off
}


@pytest.mark.parametrize(("change", "message"), MISTAKES)
def test_every_mistake_is_one_message_naming_the_case_file_and_the_key(tmp_path, change, message):
    _raises(tmp_path, _with(change), message.format(tmp=tmp_path), BRANCHES)


PEBI = {
    "name": "c",
    "horizons": {
        "lattice": {"x": {"start": 0, "stop": 1000, "num": 11}, "y": {"start": 0, "stop": 800, "num": 9}},
        "surfaces": [
            {"name": "top", "plane": {"depth": 2000, "dip": 0.0, "azimuth": 90}},
            {"name": "base", "plane": {"depth": 2040, "dip": 0.0, "azimuth": 90}},
        ],
    },
    "grid": {"type": "pebi", "domain": {"rectangle": [0, 0, 1000, 800]}, "cell_size": 50, "layers": 2},
    "wells": [
        {"name": "P1", "point": [150, 150]},
        {
            "name": "D1",  # straight from (100, 400, 1900) to (600, 400, 2150): x 300 to 380 at 2000 to 2040
            "survey": {
                "head": [100, 400, 1900],
                "stations": [[0, 63.434948822922, 90], [559.0169943749474, 63.434948822922, 90]],
            },
            "branches": [
                {"survey": {"head": [600, 400, 2150], "stations": [[559.0169943749474, 0, 0], [600, 0, 0]]}}
            ],
        },
    ],
}


def test_a_pebi_grid_refines_along_the_plan_view_of_a_deviated_well_in_the_reservoir(tmp_path):
    case = load_case(_case(tmp_path, PEBI))
    point, deviated = pebi_wells(
        case, lambda x, y: np.full(np.shape(x), 2000.0), lambda x, y: np.full(np.shape(x), 2040.0)
    )
    assert (point.name, deviated.name) == ("P1", "D1")
    (lateral,) = deviated.path  # the vertical branch stays below the base: no part
    np.testing.assert_allclose(lateral, [[300.0, 400.0], [380.0, 400.0]], rtol=0, atol=1e-6)
    shallower = pebi_wells(
        case, lambda x, y: np.full(np.shape(x), 1900.0), lambda x, y: np.full(np.shape(x), 2200.0)
    )
    lateral, vertical = shallower[1].path  # the whole lateral; the branch a point
    np.testing.assert_allclose(lateral, [[100.0, 400.0], [600.0, 400.0]], rtol=0, atol=1e-6)
    np.testing.assert_allclose(vertical, [[600.0, 400.0]], rtol=0, atol=1e-6)
    assert [w.name for w in pebi_wells(case)] == ["P1"]  # without the reservoir's depths: none
