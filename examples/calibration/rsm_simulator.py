"""A stand-in for a full-size 5-sphere cup run, for trying `bushel calibrate` in seconds: the
study's response surface (data/rsm_5sphere_large_table3_10.csv: 30 runs of the full-size cup,
large kernels) fitted with a full quadratic, plus the runs' seed-to-seed scatter (normal, sd
1.2 kg/m3, seeded by the run's seed). Prints {"bulk_density": ...} as a campaign command must.

usage: rsm_simulator.py FS_WW FR_WW E_WW FS_WS SEED
"""
import csv
import json
import os
import sys

import numpy as np

FACTORS = ("fs_ww", "fr_ww", "e_ww", "fs_ws")
RANGES = {"fs_ww": (0.17, 0.40), "fr_ww": (0.01, 0.10), "e_ww": (0.20, 0.50), "fs_ws": (0.17, 0.40)}
SCATTER = 1.2  # kg/m3


def _features(coded):
    c = np.atleast_2d(coded)
    k = c.shape[1]
    cols = [np.ones(len(c))] + [c[:, i] for i in range(k)] + [c[:, i] ** 2 for i in range(k)]
    cols += [c[:, i] * c[:, j] for i in range(k) for j in range(i + 1, k)]
    return np.column_stack(cols)


def _coded(x):
    low = np.array([RANGES[f][0] for f in FACTORS])
    high = np.array([RANGES[f][1] for f in FACTORS])
    return (np.asarray(x, float) - (low + high) / 2) / ((high - low) / 2)


def surface(root=None):
    """The fitted quadratic: a function of (fs_ww, fr_ww, e_ww, fs_ws) -> bulk density [kg/m3]."""
    root = root or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    with open(os.path.join(root, "data", "rsm_5sphere_large_table3_10.csv")) as f:
        rows = list(csv.DictReader(f))
    x = np.array([[float(r[n]) for n in FACTORS] for r in rows])
    y = np.array([float(r["bulk_density"]) for r in rows])
    beta = np.linalg.lstsq(_features(_coded(x)), y, rcond=None)[0]
    return lambda point: float((_features(_coded(point)) @ beta)[0])


if __name__ == "__main__":
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    *point, seed = sys.argv[1:]
    noise = np.random.default_rng(int(seed)).normal(0.0, SCATTER)
    print(json.dumps({"bulk_density": surface()([float(v) for v in point]) + noise}))
