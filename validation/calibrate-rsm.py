"""bushel calibrate on the study's own response surface (docs/calibration.md, "How well it
works"): the quadratic fitted to data/rsm_5sphere_large_table3_10.csv stands in for the
full-size 5-sphere cup, with the runs' scatter as noise (sd 1.2 kg/m3); the calibration seeks
826.1 kg/m3 within 2 kg/m3 over the study's four factors. For each batch size, 20 seeds: the
runs until a run confirmed a point (status "validated"), and the surface's noise-free value
at that point (it must lie within the tolerance). The runs' scatter is given to the method
(`scatter`), or fitted (at least the target's sd). The study needed 12 screening + 30 response
surface runs.

    PYTHONPATH=build/release/python /usr/bin/python3 validation/calibrate-rsm.py [BATCH...]   # default 1 2 4

Prints a Markdown table (validation/results/calibration-bayes.md records it).
"""
import os
import sys
import time

import numpy as np

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(root, "examples", "calibration"))
from rsm_simulator import FACTORS, RANGES, SCATTER, surface  # noqa: E402

from bushel.calibrate import Parameter, Settings, Target, calibrate  # noqa: E402

TARGET, TOLERANCE, SEEDS = 826.1, 2.0, range(1, 21)
truth = surface(root)
parameters = [Parameter(f, *RANGES[f]) for f in FACTORS]


def one(batch, seed, scatter):
    targets = [Target("bulk_density", TARGET, 1.2, TOLERANCE, scatter=SCATTER if scatter == "given" else None)]
    rng = np.random.default_rng(10_000 + seed)  # the runs' scatter, apart from the method's seed

    def evaluate(points, _batch):
        return [{"bulk_density": truth([p[f] for f in FACTORS]) + rng.normal(0.0, SCATTER)} for p in points]

    r = calibrate(parameters, targets, evaluate, Settings(batch=batch, budget=40, seed=seed), log=lambda s: None)
    return r.runs, max(rec.batch for rec in r.records), r.status, truth([r.best["parameters"][f] for f in FACTORS])


print("| batch | runs' scatter | seeds | runs: median (min to max) | batches after the start: median | validated | true value within 2 kg/m3 | "
      "true value: worst error [kg/m3] | seconds per calibration |")
print("|---|---|---|---|---|---|---|---|---|")
cases = [(int(a), "given") for a in sys.argv[1:]] or [(1, "given"), (2, "given"), (4, "given"), (1, "fitted"),
                                                       (2, "fitted")]
for batch, scatter in cases:
    t0 = time.time()
    out = [one(batch, s, scatter) for s in SEEDS]
    runs = [o[0] for o in out]
    err = [abs(o[3] - TARGET) for o in out]
    print(f"| {batch} | {scatter} | {len(out)} | {np.median(runs):g} ({min(runs)} to {max(runs)}) | {np.median([o[1] for o in out]):g} | "
          f"{sum(o[2] == 'validated' for o in out)} | {sum(e <= TOLERANCE for e in err)} | {max(err):.2f} | "
          f"{(time.time() - t0) / len(out):.1f} |", flush=True)
