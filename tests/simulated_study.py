"""The base case of the simulated studies' tests: a 48-cell corner-point waterflood for OPM Flow
(6 x 4 columns of 50 m, 2 layers between planes 30 m apart dipping 3 degrees east, a fault with
15 m throw, a water injector and a producer; 400 days in 3 report steps). Flow simulates it in
about 0.4 s; water reaches the producer within the 400 days."""

from __future__ import annotations

BASE = {
    "name": "tiny_flood",
    "seed": 5,
    "horizons": {
        "lattice": {"x": {"start": 0, "stop": 300, "num": 7}, "y": {"start": 0, "stop": 200, "num": 5}},
        "surfaces": [
            {"name": "top", "plane": {"depth": 2000, "dip": 3.0, "azimuth": 90}},
            {"name": "base", "plane": {"depth": 2030, "dip": 3.0, "azimuth": 90}},
        ],
    },
    "faults": [{"name": "F1", "trace": [[170, -50], [190, 250]], "throw": 15}],
    "wells": [{"name": "INJ", "point": [270, 60]}, {"name": "PROD", "point": [30, 140]}],
    "grid": {"type": "cornerpoint", "dims": [6, 4], "layers": 2},
    "petrophysics": {
        "porosity": {
            "field": {
                "model": "exponential",
                "len_scale": [150, 100, 10],
                "mean": 0.22,
                "std": 0.03,
                "bounds": [0.1, 0.32],
            }
        },
        "permeability": {
            "field": {"model": "exponential", "len_scale": [150, 100, 10], "mean": 200, "std": 0.8}
        },
        "ntg": {"constant": 0.9},
    },
    "simulation": {
        "fluid": "oil-water",
        "initial": {"pressure": 210, "datum": 2000, "owc": 2070},
        "wells": [
            {"name": "INJ", "type": "injector", "rate": 300, "bhp": 400},
            {"name": "PROD", "type": "producer", "bhp": 150},
        ],
        "report_days": [100, 200, 400],
    },
}
