"""Rock (gridlib.petrophysics.rock): Carman-Kozeny, porosity and permeability transforms, values per
layer and zone, make_rock and its netCDF round trip."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib import InputError
from gridlib.io import read_netcdf, write_netcdf
from gridlib.petrophysics import (
    MILLIDARCY,
    carman_kozeny,
    layer_index,
    lognormal_permeability,
    make_rock,
    normal_porosity,
    per_layer,
)


def test_carman_kozeny_of_the_mrst_book():
    k = carman_kozeny(0.2)  # d = 10 micrometres, tau = 0.81
    assert round(float(k), 1) == 21.7  # mD, to three digits
    assert float(k) * MILLIDARCY == pytest.approx(2.143e-14, rel=5e-4)  # m2
    darcy = 1e-3 * 1e-2 * 1e-2 / 101325.0  # 1 cP x 1 cm/s x 1 cm / 1 atm, exactly (m2)
    expected = 0.2**3 * (10e-6) ** 2 / (72 * 0.81 * 0.8**2) / (1e-3 * darcy)
    assert float(k) == pytest.approx(expected, rel=1e-15)
    assert carman_kozeny([0.0, 0.1, 0.3]).tolist()[0] == 0.0
    with pytest.raises(InputError, match=r"porosity must lie in \[0, 1\)"):
        carman_kozeny(1.0)


def test_porosity_permeability_transforms():
    z = np.random.default_rng(0).standard_normal(200_000)
    k = lognormal_permeability(z, median=100.0, sigma=1.0)
    assert np.median(k) == pytest.approx(100.0, rel=0.01)
    assert np.log(k).std() == pytest.approx(1.0, rel=0.01)
    phi = normal_porosity(z, mean=0.2, std=0.05, bounds=(0.05, 0.35))
    assert phi.min() == 0.05 and phi.max() == 0.35 and np.median(phi) == pytest.approx(0.2, abs=1e-3)


def test_per_layer_and_zone_values():
    g = gl.cart_grid([2, 2, 4])
    layer = layer_index(g)
    assert per_layer(layer, 0.25).tolist() == [0.25] * 16
    assert per_layer(layer, [0.1, 0.2, 0.3, 0.4])[::4].tolist() == [0.1, 0.2, 0.3, 0.4]
    assert per_layer(layer, [0.1, 0.3], zones=[1, 3])[::4].tolist() == [0.1, 0.3, 0.3, 0.3]
    with pytest.raises(InputError, match=r"layer 3 has no value \(2 values\)"):
        per_layer(layer, [0.1, 0.2])
    with pytest.raises(InputError, match="zones must be one positive layer count per value"):
        per_layer(layer, [0.1, 0.3], zones=[4])


def test_rock_and_netcdf(tmp_path):
    g = gl.cart_grid([3, 2, 2])
    layer = layer_index(g)
    poro = per_layer(layer, [0.2, 0.3])
    rock = make_rock(poro, carman_kozeny(poro), kv_kh=0.1, ntg=per_layer(layer, [1.0, 0.8]))
    assert rock.num_cells == 12 and rock.permz.tolist() == pytest.approx((0.1 * rock.permx).tolist())
    assert not rock.poro.flags.writeable
    write_netcdf(tmp_path / "rock.nc", g, cell_data=rock.cell_data())
    back = read_netcdf(tmp_path / "rock.nc").cell_data
    assert np.array_equal(back["permx"], rock.permx) and np.array_equal(back["ntg"], rock.ntg)
    with pytest.raises(InputError, match=r"rock\.poro: values must be >= 0"):
        make_rock(-0.1, 100.0)
    assert make_rock(1.2, 100.0, ntg=1.5).ntg.tolist() == [1.5]  # as OPM Flow: a note, not an error
    with pytest.raises(InputError, match=r"make_rock: the properties have different lengths \[2, 3\]"):
        make_rock([0.2, 0.2], [1.0, 2.0, 3.0])
