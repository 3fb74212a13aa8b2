"""bushel doe analyze against a second implementation: the normal equations in numpy.

usage: doe_numpy_check.py BUSHEL DATA_DIR
Fits the study's response-surface table (quadratic) and screening table (main effects)
with both and compares coefficients, standard errors, t values, R2, adjusted and predicted
R2 (PRESS) to 1e-9 relative; and the screening with two runs left out by --where (as a
campaign leaves out runs that clogged), coded against the design's levels.
"""
import csv
import json
import subprocess
import sys

import numpy as np

bushel, data = sys.argv[1], sys.argv[2]


def numpy_fit(path, factors, response, quadratic, block=None, keep=lambda r: True):
    rows = [r for r in csv.DictReader(line for line in open(path) if not line.startswith("#")) if keep(r)]
    raw = np.array([[float(r[f]) for f in factors] for r in rows])
    lo, hi = raw.min(axis=0), raw.max(axis=0)
    if len(rows) < 12:  # a filtered two-level table: its design's levels are coded -1 and +1
        lo, hi = -np.ones(len(factors)), np.ones(len(factors))
    x = (raw - (lo + hi) / 2) / ((hi - lo) / 2)
    y = np.array([float(r[response]) for r in rows])
    k = len(factors)
    names, cols = ["Constant"], [np.ones(len(y))]
    if block:  # effect coding: 1 in the block, -1 in the last
        labels = sorted({int(float(r[block])) for r in rows})
        b = np.array([int(float(r[block])) for r in rows])
        for lab in labels[:-1]:
            names.append(f"Block {lab}"); cols.append(np.where(b == lab, 1.0, np.where(b == labels[-1], -1.0, 0.0)))
    for i in range(k):
        names.append(factors[i]); cols.append(x[:, i])
    if quadratic:
        for i in range(k):
            names.append(factors[i] + "*" + factors[i]); cols.append(x[:, i] ** 2)
        for i in range(k):
            for j in range(i + 1, k):
                names.append(factors[i] + "*" + factors[j]); cols.append(x[:, i] * x[:, j])
    X = np.column_stack(cols)
    inv = np.linalg.inv(X.T @ X)
    b = inv @ X.T @ y
    e = y - X @ b
    n, p = X.shape
    mse = e @ e / (n - p)
    se = np.sqrt(mse * np.diag(inv))
    sst = ((y - y.mean()) ** 2).sum()
    h = np.einsum("ij,jk,ik->i", X, inv, X)
    press = ((e / (1 - h)) ** 2).sum()
    return dict(zip(names, zip(b, se, b / se))), 1 - e @ e / sst, 1 - mse / (sst / (n - 1)), 1 - press / sst


def check(path, factors, response, model, block=None, where=None, keep=lambda r: True):
    extra = ["--block", block] if block else []
    if where:
        extra += ["--where", where, "--levels", ",".join(f + "=-1:1" for f in factors)]
    out = subprocess.run([bushel, "doe", "analyze", path, "--factors", ",".join(factors), "--response", response,
                          "--model", model, "--json"] + extra, check=True, capture_output=True, text=True).stdout
    j = json.loads(out)
    terms, r2, r2a, r2p = numpy_fit(path, factors, response, model == "quadratic", block, keep)
    if where and j["runs"] != 10:
        sys.exit(f"--where {where}: {j['runs']} runs, expected 10")
    got = {t["term"]: t for t in j["terms"]}
    bad = []
    for name, (b, se, t) in terms.items():
        g = got[name]
        for what, mine, ref in (("coef", g["coefficient"], b), ("se", g["se"], se), ("t", g["t"], t)):
            if abs(mine - ref) > 1e-9 * max(1.0, abs(ref)):
                bad.append(f"{name} {what}: bushel {mine} numpy {ref}")
    for what, mine, ref in (("r2", j["r2"], r2), ("r2_adjusted", j["r2_adjusted"], r2a),
                            ("r2_predicted", j["r2_predicted"], r2p)):
        if abs(mine - ref) > 1e-9:
            bad.append(f"{what}: bushel {mine} numpy {ref}")
    if bad:
        print("\n".join(bad))
        sys.exit(1)
    print(f"{path}: {len(terms)} terms agree with numpy")


check(f"{data}/rsm_5sphere_large_table3_10.csv", ["fs_ww", "fr_ww", "e_ww", "fs_ws"], "bulk_density", "quadratic")
check(f"{data}/rsm_5sphere_large_table3_10.csv", ["fs_ww", "fr_ww", "e_ww", "fs_ws"], "bulk_density", "quadratic",
      "block")
check(f"{data}/pb_5sphere_large_table3_9.csv", ["fr_ww", "fr_ws", "fs_ww", "fs_ws", "e_ww", "e_ws"], "bulk_density",
      "main")
check(f"{data}/pb_5sphere_large_table3_9.csv", ["fr_ww", "fr_ws", "fs_ww", "fs_ws", "e_ww", "e_ws"], "bulk_density",
      "main", where="std_order!=4,bulk_density>775", keep=lambda r: r["std_order"] != "4" and float(r["bulk_density"]) > 775)
