#!/usr/bin/env python3
"""validation/study_table.py, the tables of the study's experiments at full size, on made-up
summaries: every row has its header's cells; kept results are read before run folders; an
unfinished case is "not started", "running or stopped" or "parked", an interrupted one or a
failed one does not count as finished; the checks (KanMark > Garrison, the rise with drop
height, the pure fractions' order, the rise with pressure, the tapped fractions' packing ratio
and compressibility in the lab's order, a case tapped at another rate against its twin, a
reduced case with other kernels against the single spheres' compaction before the strikes) say
"holds" or "does NOT hold" from the values and wait for every case, on the means of a case's
seeds, naming the steps within the seeds' scatter, and the tapping rates and the test weight's
time steps are told apart or not against the seeds' scatter; the compaction, the overlap's
share of it, the WPACKING fit and the time-step span are the arithmetic of the values, and so
are a test weight against the lab's expectation (also written as a reference table) or, for a
pure fraction, its measurement, a sample's mixing excess over the pure fractions, a pure
fraction against the lab's three loose densities of it, and the strike's loss; the lab's mixing
excess is the special cubic of made-up mixtures that follow one exactly; a density over a
sensor the grain did not fill is marked; without cases the script takes every case it finds.

usage: study_table_check.py STUDY_TABLE_PY REFERENCES WORKDIR
"""
import json
import lzma
import os
import shutil
import subprocess
import sys

script, references, work = sys.argv[1:4]
runs, kept = os.path.join(work, "runs"), os.path.join(work, "kept")
shutil.rmtree(work, ignore_errors=True)
failures = []


def summary(results, interrupted=False, failed=None, stages=()):
    return {"engine": {"builds": ["0.1.0 (commit 0123456789ab)"]}, "interrupted": interrupted, "failed": failed,
            "results": {k: (v if isinstance(v, dict) else {"value": v, "unit": ""}) for k, v in results.items()},
            "factories": [{"count": 1000}], "dt_s": 5e-6, "critical_step_s": 4e-6, "time_step_rule": "0.5 critical", "simulated_time_s": 10.0,
            "wall_time_s": 3600.0, "particle_steps_per_s": 2.0e6, "stages": [{"name": n, "dt_s": d, "values": v[0] if v else {}} for n, d, *v in stages]}


def put(folder, case, s):
    os.makedirs(os.path.join(folder, case), exist_ok=True)
    with open(os.path.join(folder, case, "summary.json"), "w") as f:
        json.dump(s, f)


def test_weight(struck, unstruck=850.0, before=810.0):
    lb = dict(struck, value=struck["value"] / 12.8719) if isinstance(struck, dict) else struck / 12.8719
    return summary({"bulk_density": struck, "test_weight_lb_bu": lb, "bulk_density_unstruck": unstruck,
                    "bulk_density_sensor": before,
                    "fraction_large": 0.8, "fraction_medium": 0.15, "fraction_small": 0.05, "filling_time": 4.0,
                    "heap_angle": 20.0})


def compression(densities, **kw):
    r = {"bulk_density_0": densities[0]}
    for i, d in enumerate(densities[1:], 1):
        r.update({f"bulk_density_{i}": d, f"drift_{i}": -100.0 * i, f"unbalanced_{i}": 1e-5 * i})
    return summary(r, stages=[("hold_7", kw.get("dt", 1e-6))])


def table(cases):
    out = subprocess.run([sys.executable, script, runs, kept, references] + cases,
                         check=True, capture_output=True, text=True).stdout
    header = None
    for line in out.splitlines():
        if not line.startswith("|"):
            header = None
        elif header is None:
            header = line.count("|")
        elif line.count("|") != header:
            failures.append(f"{line.count('|') - 1} cells, not {header - 1}: {line}")
    return out


def expect(condition, what, out):
    if not condition:
        failures.append(what + ":\n" + out)


def row(out, case):
    return next((l for l in out.splitlines() if l.startswith(f"| {case} |")), "")


# Test weight: KanMark above Garrison at 1h, not at 8h; KanMark rises with the drop height.
tw = ["tw-kanmark-1s-1h", "tw-kanmark-1s-8h", "tw-kanmark-1s-32h", "tw-garrison-1s-1h", "tw-garrison-1s-8h"]
put(kept, "tw-kanmark-1s-1h", test_weight(800.0))
put(runs, "tw-kanmark-1s-1h", test_weight(1.0))  # (the kept summary is read first)
put(runs, "tw-kanmark-1s-8h", test_weight(805.0))
put(runs, "tw-kanmark-1s-32h", test_weight(810.0))
put(runs, "tw-garrison-1s-1h", test_weight(790.0))
put(runs, "tw-garrison-1s-8h", test_weight(806.0))
out = table(tw)
expect("KanMark > Garrison, 1s, 1h (struck, kg/m3): holds: 800.0, 790.0" in out, "KanMark > Garrison at 1h", out)
expect("KanMark > Garrison, 1s, 8h (struck, kg/m3): does NOT hold: 805.0, 806.0" in out, "not at 8h", out)
expect("KanMark > Garrison, 1s, 32h" not in out, "no comparison at a drop without a Garrison case", out)
expect("rises with the drop height, kanmark 1s (1h, 8h, 32h; struck, kg/m3): holds: 800.0, 805.0, 810.0" in out,
       "the rise with drop height", out)
expect("| 800.0 | 62.15 |" in row(out, "tw-kanmark-1s-1h"), "kg/m3 and lb/bu (800 / 12.8719)", out)
expect("80.0 / 15.0 / 5.0 (81.5 / 15.5 / 3.0)" in row(out, "tw-kanmark-1s-1h"), "the kettle's composition", out)
expect("kanmark 61.84 lb/bu, garrison 59.03 lb/bu" in out, "the ideal mixtures of the lab's fractions", out)
expect("| 61.37 | +3.8 | -2.5 |" in row(out, "tw-garrison-1s-1h"),
       "against the lab's expectation (61.37 / 59.15) and the strike (790 / 810)", out)
expect("kanmark 0.50 %, garrison 0.21 % denser" in out and "expect kanmark 62.15 lb/bu, garrison 59.15 lb/bu" in out,
       "the lab's mixing excess and the expectation", out)
# seeds: the checks on the means of a case's seeds, and the steps within the seeds' scatter
# (pooled sd: sqrt((0.5^2 * 2 + 2^2 * 2) / 2) = 2.06; 8h to 32h: 2.5 < 2 x 2.06 x sqrt(1/2 + 1/2);
# 1h to 8h: 5.5 > 2 x 2.06 x sqrt(1 + 1/2) = 5.05)
seeds = ["tw-kanmark-1s-8h-seed2", "tw-kanmark-1s-32h-seed2"]
put(runs, seeds[0], test_weight(806.0))
put(runs, seeds[1], test_weight(806.0))
out = table(tw + seeds)
expect("rises with the drop height, kanmark 1s (1h, 8h, 32h; struck, kg/m3): holds: 800.0, 805.5, 808.0 "
       "(8h to 32h: within two standard deviations of the seeds' scatter)" in out, "the rise on the seeds' means", out)
expect("- seeds, kanmark 1s 32h (struck, kg/m3): 810.0, 806.0" in out, "the seeds' values", out)
expect("a standard deviation of 2.06 kg/m3" in out, "the pooled standard deviation", out)
expect("| tw-kanmark-1s-8h-seed2 | kanmark | 1s | 8h | 850.0 | 806.0 |" in out, "a seed's row", out)
put(runs, seeds[1], dict(test_weight(806.0), interrupted=True))
out = table(tw + seeds)
expect("kanmark 1s (1h, 8h, 32h; struck, kg/m3): not every case has finished" in out, "a seed not finished", out)
for c in seeds:
    shutil.rmtree(os.path.join(runs, c))

# the pure fractions: against the lab's measurement, in the lab's order, and the samples' mixing
# excess over the ideal mixture of them (KanMark: 1 / (0.815/820 + 0.155/780 + 0.03/750) = 811.28)
pure = ["tw-large-1s-1h", "tw-medium-1s-1h", "tw-small-1s-1h"]
for case, value in zip(pure, (820.0, 780.0, 750.0)):
    put(runs, case, test_weight(value))
out = table(tw + pure)
expect("| 63.70 | +1.6 |" in row(out, "tw-large-1s-1h") and "(100.0 / 0.0 / 0.0)" in row(out, "tw-large-1s-1h"),
       "a pure fraction against the lab's measurement (820 / 12.8719 / 62.69) and its shares", out)
expect("large > medium > small, 1s, 1h (struck, kg/m3): holds: 820.0, 780.0, 750.0" in out, "the fractions' order", out)
expect("mixing excess, kanmark 1s, 1h: -1.39 % over the ideal mixture of the model's pure fractions (811.3 kg/m3); "
       "the lab's tapped mixtures +0.50 %" in out and "mixing excess, garrison 1s, 1h: +0.92 %" in out,
       "the mixing excess", out)
expect("8h: -" not in out and "mixing excess, kanmark 1s, 8h" not in out, "no excess without the pure fractions", out)
# each pure fraction against the lab's three loose densities of it: the kettle (62.69 lb/bu x
# 12.8719 = 806.9), the tapped cylinder's loose fill (0.633 x 1373 x (1 - 0.051) = 824.8), the cup
expect("the large fraction, 1s, 1h: 820.0 kg/m3 struck; the lab's loose density of it in its kettle 806.9 (+1.6 %), "
       "in the tapped cylinder's loose fill 824.8 (-0.6 %), in the calibration cup 826.1 (-0.7 %)" in out
       and "the medium fraction, 1s, 1h: 780.0 kg/m3 struck; the lab's loose density of it in its kettle 760.9 "
       "(+2.5 %), in the tapped cylinder's loose fill 773.9 (+0.8 %), in the calibration cup 798.1 (-2.3 %)" in out,
       "the pure fractions against the lab's loose densities", out)
put(runs, "tw-small-1s-1h", test_weight(790.0))
out = table(tw + pure)
expect("large > medium > small, 1s, 1h (struck, kg/m3): does NOT hold: 820.0, 780.0, 790.0" in out, "out of order", out)
for c in pure:
    shutil.rmtree(os.path.join(runs, c))

# an interrupted case is not finished; a run folder without a summary is running; a parked one
put(runs, "tw-garrison-1s-8h", dict(test_weight(806.0), interrupted=True))
os.makedirs(os.path.join(runs, "tw-garrison-1s-32h"))
open(os.path.join(runs, "tw-garrison-1s-32h", "checkpoint.bin"), "w").close()
with open(os.path.join(runs, "tw-garrison-1s-32h", "timeseries.csv"), "w") as f:
    f.write("stage,time\nfill,0.5\nflow,2.25\n")
os.makedirs(os.path.join(kept, "tw-kanmark-1s-4h"))
open(os.path.join(kept, "tw-kanmark-1s-4h", "checkpoint.bin.xz"), "wb").close()
with lzma.open(os.path.join(kept, "tw-kanmark-1s-4h", "timeseries.csv.xz"), "wt") as f:
    f.write("stage,time\nsettle,1.5\n")
out = table(tw + ["tw-garrison-1s-32h", "tw-kanmark-1s-4h", "tw-kanmark-1s-16h"])
expect("interrupted at t = 10.00 s" in row(out, "tw-garrison-1s-8h"), "an interrupted case", out)
expect("8h (struck, kg/m3): not every case has finished" in out, "an interrupted case is not finished", out)
expect("running or stopped at t = 2.25 s (flow)" in row(out, "tw-garrison-1s-32h"), "a running case", out)
expect("KanMark > Garrison, 1s, 32h (struck, kg/m3): not every case has finished" in out, "32h waits for Garrison", out)
expect("kanmark 1s (1h, 8h, 32h; struck, kg/m3): holds" in out
       and "kanmark 1s (1h, 4h, 8h, 16h, 32h; struck, kg/m3): not every case has finished" in out,
       "the rise over the study's heights, and over every height run", out)
expect("parked at t = 1.50 s (settle)" in row(out, "tw-kanmark-1s-4h"), "a parked case", out)
expect("| not started |" in row(out, "tw-kanmark-1s-16h"), "a case not started", out)
# a failed case, and a density over a sensor that was not full
put(runs, "tw-kanmark-1s-8h", dict(test_weight(805.0), failed="particles lost"))
put(runs, "tw-kanmark-1s-32h", test_weight({"value": 700.0, "unit": "kg/m3", "not_full": "the kettle was not full"},
                                           {"value": 840.0, "unit": "kg/m3", "not_full": "its lowest point lay 2.5 mm below"}))
out = table(tw)
expect("FAILED: particles lost" in row(out, "tw-kanmark-1s-8h"), "a failed case", out)
expect("kanmark 1s (1h, 8h, 32h; struck, kg/m3): not every case has finished" in out, "a failed case counts not", out)
expect("| 840.0 | 700.0 (not full) | 54.38 (not full) |" in row(out, "tw-kanmark-1s-32h"),
       "not full (the unstruck heap's sensor is never full)", out)

put(runs, "comp-large-5s", compression([{"value": 780.0, "unit": "kg/m3", "not_full": "its lowest point lay 2.5 mm below"}]
                                       + [790.0, 800.0, 810.0, 820.0, 830.0, 845.0, 858.0]))
out = table(["comp-large-5s"])
expect("| 5s | 780.0 (not full by 2.5 mm) | 790.0 |" in row(out, "comp-large-5s"), "not full by how much", out)

# Compression: rises with every level; the stiff kernels' compaction against the study's.
soft = [780.0, 790.0, 800.0, 810.0, 820.0, 830.0, 845.0, 858.0]
stiff = [770.0, 772.0, 774.0, 776.0, 778.0, 780.0, 783.0, 786.5]
put(runs, "comp-large-1s", compression(soft))
put(runs, "comp-large-1s-stiff", compression(stiff))
put(runs, "comp-large-5s", compression(soft[:3] + [799.0] + soft[4:-1] + [850.0]))
out = table(["comp-large-1s", "comp-large-1s-stiff", "comp-large-5s"])
expect("| 10.0 | -0.70 kPa at 138 kPa | 7.0e-5 at 138 kPa |" in row(out, "comp-large-1s"),
       "compaction (858 - 780) / 780, the largest drift and unbalanced force", out)
expect("| comp-large-1s | -0.10 | -0.20 | -0.30 | -0.40 | -0.50 | -0.60 | -0.70 |" in out, "the drift per level", out)
expect("rises with every level, comp-large-1s: holds" in out, "the rise with pressure", out)
expect("rises with every level, comp-large-5s: does NOT hold" in out, "a fall with pressure", out)
expect("- overlap, 1s: the kernels ten times stiffer compact 2.1 % where the study's compact 10.0 %; of the "
       "study's material's compaction at least 79 % is the kernels' overlap, about 100 % if both rearrange alike "
       "(the stiff kernels overlap 0.22 times" in out, "the overlap's share: 1 - 2.14/10, over 1 - 10^(-2/3)", out)
expect("- overlap, 5s" not in out, "no overlap line for a model without its stiff twin", out)
put(runs, "comp-large-5s-stiff", compression([780.0, 783.0, 786.0, 789.0, 792.0, 795.0, 797.0, 799.5]))
out = table(["comp-large-1s", "comp-large-1s-stiff", "comp-large-5s", "comp-large-5s-stiff"])
expect("- overlap, 5s: the kernels ten times stiffer compact 2.5 % where the study's compact 9.0 %; of the "
       "study's material's compaction at least 72 % is the kernels' overlap, about 92 % if both" in out,
       "each model against its own stiff twin (1 - 2.50/8.97)", out)
expect("- overlap, 1s: the kernels ten times stiffer compact 2.1 %" in out, "the single spheres' line kept", out)
shutil.rmtree(os.path.join(runs, "comp-large-5s-stiff"))
# the WPACKING fit, on a curve that follows D - D_o = 0.2 P + 4 sqrt(P) exactly
exact = [800.0] + [800.0 + 0.2 * p + 4 * p ** 0.5 for p in (7, 21, 34, 48, 69, 103, 138)]
put(runs, "comp-large-5s", compression(exact))
out = table(["comp-large-5s"])
expect("WPACKING form, comp-large-5s: D - D_o = a P + b sqrt(P) with a = 0.200 kg/m3 per kPa, b = 4.00 kg/m3 "
       "per sqrt(kPa) (least squares over the levels; largest residual 0.0 kg/m3)" in out, "the WPACKING fit", out)

# The time step: the span at 138 kPa, once every case has finished.
for percent, top in ((2, 858.0), (5, 858.5), (10, 859.2)):
    put(runs, f"comp-dt-{percent}", compression(soft[:-1] + [top], dt=percent * 1e-7))
dt = ["comp-dt-10", "comp-dt-2", "comp-dt-5"]
out = table(dt + ["comp-dt-20"])
expect("spans" not in out, "no span before every step has finished", out)
out = table(dt)
expect("spans 1.2 kg/m3 (0.14 %) over the steps" in out, "the span over the steps", out)
expect("| +0.14 |" in row(out, "comp-dt-10") and "| 1.000 |" in row(out, "comp-dt-10"),
       "against the smallest step; the lid's dt in us", out)
lines = [l for l in out.splitlines() if l.startswith("| comp-dt-")]
expect([l.split("|")[1].strip() for l in lines] == ["comp-dt-2", "comp-dt-5", "comp-dt-10"], "rows by step", out)

# without cases: every case with a folder, by name
out = subprocess.run([sys.executable, script, runs, kept, references], check=True, capture_output=True,
                     text=True).stdout
names = [l.split("|")[1].strip() for l in out.splitlines() if l.startswith("| tw-") or l.startswith("| comp-")]
names = list(dict.fromkeys(names))  # (the drift table names the compression cases again)
expect(names == ["tw-garrison-1s-1h", "tw-garrison-1s-32h", "tw-garrison-1s-8h", "tw-kanmark-1s-1h",
                 "tw-kanmark-1s-32h", "tw-kanmark-1s-4h", "tw-kanmark-1s-8h", "comp-large-1s", "comp-large-1s-stiff",
                 "comp-large-5s", "comp-dt-2", "comp-dt-5", "comp-dt-10"], "the cases found, by name", out)

# Tapped density: the lab's packing ratio and compressibility of the fraction beside the run's.
# The taps and their rate as the run took them (its parameters).
put(runs, "tap-medium-5s", dict(summary({"loose_bulk_density": 790.0, "tapped_bulk_density": 835.0,
                                         "packing_ratio": 835.0 / 1373, "compressibility": 45 / 835.0}),
                                parameters={"taps": "500", "tap_frequency": "8.66Hz"}))
out = table(["tap-medium-5s"])
# (the lab's loose fill of the medium kernels: 0.599 x 1373 x (1 - 0.059) = 773.9 kg/m3, 790 on it
# +2.1 %; the packing ratio 835 / 1373 = 0.608 on the lab's 0.599: +1.5 %)
expect("| 500 at 8.66 Hz | 790.0 | 773.9 | +2.1 | 835.0 | 0.608 | 0.599 | +1.5 | 0.0539 | 0.059 |"
       in row(out, "tap-medium-5s"), "tapped row", out)
expect("packing ratio, large" not in out, "no order check before the three fractions have cases", out)
expect("- tap-medium-5s taps at 8.66 Hz, not the lab's 4.33 Hz, and is set against the lab all the same; what that "
       "rate moves: no twin tapped at both rates" in out, "a study case at another rate", out)


def tap(loose, tapped):  # (before the strikes: 40 and 45 kg/m3 denser)
    return summary({"loose_bulk_density": loose, "tapped_bulk_density": tapped, "packing_ratio": tapped / 1373,
                    "compressibility": (tapped - loose) / tapped},
                   stages=[("rest", 1e-5, {"cylinder.bulk_density": loose + 40}),
                           ("unextended", 1e-5, {"cylinder.bulk_density": tapped + 45})])


# The fractions' order, the lab's: packing ratio falling, compressibility rising from large to small.
put(runs, "tap-large-5s", dict(summary({}), interrupted=True))
put(runs, "tap-small-5s", tap(760.0, 810.0))
out = table(["tap-large-5s", "tap-medium-5s", "tap-small-5s"])
expect("- packing ratio, large > medium > small, 5s: not every case has finished; the lab: 0.633, 0.599, 0.557"
       in out, "the order waits for every fraction", out)
put(runs, "tap-large-5s", tap(820.0, 860.0))
out = table(["tap-large-5s", "tap-medium-5s", "tap-small-5s"])
expect("- packing ratio, large > medium > small, 5s: holds: 0.626, 0.608, 0.590; the lab: 0.633, 0.599, 0.557" in out
       and "- compressibility, large < medium < small, 5s: holds: 0.047, 0.054, 0.062; the lab: 0.051, 0.059, 0.064"
       in out, "the fractions' order", out)
# (the strikes: 820 / 860 - 1 = -4.7 %, 860 / 905 - 1 = -5.0 %)
expect("| 0.0465 | 0.051 | -4.7 / -5.0 |" in row(out, "tap-large-5s"), "the strikes' cost", out)
put(runs, "tap-small-5s", tap(815.0, 850.0))
out = table(["tap-large-5s", "tap-medium-5s", "tap-small-5s"])
expect("- packing ratio, large > medium > small, 5s: does NOT hold: 0.626, 0.608, 0.619" in out
       and "- compressibility, large < medium < small, 5s: does NOT hold: 0.047, 0.054, 0.041" in out,
       "the fractions out of order", out)
# A case tapped at another rate: set against its twin at the lab's rate, outside the order check.
put(runs, "tap-large-5s-8.66hz", dict(summary({}), interrupted=True))
names = ["tap-large-5s", "tap-large-5s-8.66hz", "tap-medium-5s", "tap-small-5s"]  # (the twin first)
out = table(names)
expect("- tap-large-5s-8.66hz against tap-large-5s: not every case has finished" in out, "the rate waits", out)
put(runs, "tap-large-5s-8.66hz", tap(820.0, 880.0))
out = table(names)
expect("- tap-large-5s-8.66hz against tap-large-5s: loose 820.0 and 820.0 kg/m3, tapped 860.0 and 880.0 "
       "(+20.0 kg/m3, +2.33 %), compressibility 0.0465 and 0.0682" in out
       and "5s: does NOT hold: 0.626, 0.608, 0.619" in out, "another rate against the lab's", out)
# (its packing ratio not against the lab's, which was tapped at 4.33 Hz)
expect("| 0.641 | 0.633 |  | 0.0682 |" in row(out, "tap-large-5s-8.66hz"), "another rate's row", out)
expect("- tap-medium-5s taps at 8.66 Hz, not the lab's 4.33 Hz, and is set against the lab all the same; what that "
       "rate moves: tap-large-5s-8.66hz against tap-large-5s (above)" in out
       and "tap-large-5s taps" not in out, "a study case at another rate, with a twin at it", out)
# At rest before each fall: the quietest bin of tap-phases.csv beside KEPT against the first (the
# impact just past), for a finished case only (tap-medium-5s); tap-other-5s, not in the table, is
# left alone.
with open(os.path.join(work, "tap-phases.csv"), "w") as f:
    f.write("case,phase_start,kinetic_energy_per_particle,z,samples\n"
            "tap-medium-5s,0.0000,4.0e-7,1e-6,10\ntap-medium-5s,0.0100,3.0e-10,1e-4,10\n"
            "tap-medium-5s,0.0200,2.0e-9,2e-4,10\ntap-other-5s,0.0000,1.0e-7,1e-6,10\n"
            "tap-large-5s-8.66hz,0.0000,1.0e-7,1e-6,10\n"
            "tap-large-5s,0.0000,1.0e-7,1e-6,10\ntap-large-5s,0.0100,1.0e-9,1e-4,10\n")
put(runs, "tap-large-5s", dict(summary({}), interrupted=True))
out = table(names)
expect("- before each fall, tap-medium-5s: the quietest 10 ms of a tap's period (10 ms into it) holds "
       "0.075 % of the grain's kinetic energy just after the impact" in out, "the quietest bin, 3e-10 / 4e-7", out)
expect("before each fall, tap-large-5s" not in out, "no line for an unfinished case or a single bin", out)
os.remove(os.path.join(work, "tap-phases.csv"))

# The tapping rate: the difference of the seeds' means against their pooled scatter
# (sd: sqrt((1^2 * 2 + 1.5^2 * 2) / 2) = 1.80; the difference's: 1.80 x sqrt(1/2 + 1/2) = 1.80)
rate = {"tap-rate-4.33hz-seed1": 790.0, "tap-rate-4.33hz-seed2": 792.0, "tap-rate-8.66hz-seed1": 793.5,
        "tap-rate-8.66hz-seed2": 790.5}
# Before the strike (the end of the stage unextended): 840, 846, 843 and 849 kg/m3.
before = dict(zip(rate, (840.0, 846.0, 843.0, 849.0)))
for case, value in rate.items():
    put(runs, case, summary({"loose_bulk_density": 770.0, "tapped_bulk_density": value,
                             "compressibility": (value - 770.0) / value},
                            stages=[("unextended", 1e-5, {"cylinder.bulk_density": before[case]})]))
out = table(sorted(rate))
# (the strike: 790.5 / 849 - 1 = -6.9 %)
expect("| tap-rate-8.66hz-seed2 | 8.66 | 2 | 770.0 | 849.0 | 790.5 | -6.9 | 0.0259 |" in out, "a rate's row", out)
# (843 and 849 against 840 and 846: +3.0 kg/m3 (+0.36 %); sd sqrt((3^2 * 4) / 2) = 4.24, told apart at 8.5)
expect("- density before the strike at 8.66 Hz against 4.33 Hz: +3.0 kg/m3 (+0.36 %) on the seeds' means; one run's "
       "standard deviation 4.2 kg/m3, the difference's 4.2: the rates are not told apart" in out, "before the strike", out)
expect("at 8.66 Hz against 4.33 Hz: +1.0 kg/m3 (+0.13 %) on the seeds' means; one run's standard deviation 1.8 kg/m3, "
       "the difference's 1.8: the rates are not told apart" in out, "the rates within the scatter", out)
# (8.66 Hz: 799.5 and 800.5; sd sqrt((1^2 * 2 + 0.5^2 * 2) / 2) = 1.12; +9.0 > 2 x 1.12)
put(runs, "tap-rate-8.66hz-seed1", summary({"loose_bulk_density": 770.0, "tapped_bulk_density": 799.5}))
put(runs, "tap-rate-8.66hz-seed2", summary({"loose_bulk_density": 770.0, "tapped_bulk_density": 800.5}))
out = table(sorted(rate))
expect("+9.0 kg/m3 (+1.14 %) on the seeds' means; one run's standard deviation 1.1 kg/m3, the difference's 1.1: the rates "
       "are told apart" in out, "rates told apart", out)
put(runs, "tap-rate-8.66hz-seed2", dict(summary({}), interrupted=True))
out = table(sorted(rate))
expect("8.66 Hz against" not in out, "no verdict before every rate case has finished", out)
for case in rate:
    shutil.rmtree(os.path.join(runs, case))

# The reduced taps with other kernels beside the calibrated single spheres at 8.66 Hz: the
# compaction before the strikes, (tapped + 45 - loose - 40) / (tapped + 45) of tap(): the twins
# 35 / 845 = 4.14 % and 40 / 850 = 4.71 % (mean 4.42), the 5-sphere case 55 / 875 = 6.29 %.
model = ["tap-model-5s-seed1", "tap-model-no-rolling-seed1"]
put(runs, "tap-rate-8.66hz-seed1", tap(770.0, 800.0))
put(runs, "tap-rate-8.66hz-seed2", dict(tap(770.0, 805.0), interrupted=True))  # (its stages do not count)
put(runs, "tap-model-5s-seed1", dict(tap(780.0, 830.0), parameters={"model": "5s", "fr_ww": "0.01"}))
out = table(model)
expect("- compaction before the strikes, tap-model-5s-seed1 against the calibrated single spheres: not every case "
       "has finished" in out, "the comparison waits for the twins", out)
put(runs, "tap-rate-8.66hz-seed2", tap(770.0, 805.0))
out = table(model)
expect("| tap-model-5s-seed1 | 5s | 0.01 | 780.0 | 830.0 | 0.0602 | 820.0 | 875.0 | 6.29 |" in out
       and "| tap-rate-8.66hz-seed2 |  |  | 770.0 | 805.0 | 0.0435 | 810.0 | 850.0 | 4.71 |" in out,
       "the rows: the twins first, the compaction before the strikes", out)
# (one run's standard deviation from the twins: 0.565 / sqrt(2) = 0.40 points; the difference's
# 0.40 x sqrt(1 + 1/2) = 0.49; +1.86 > 2 x 0.49: told apart)
expect("- compaction before the strikes, tap-model-5s-seed1 against the calibrated single spheres: 6.29 % against "
       "4.42 % (+1.86 points; the single spheres' seeds 4.14, 4.71 %; one run's standard deviation 0.40 points from "
       "them, the difference's 0.49: told apart)" in out, "against the twins' mean", out)
# (42 / 850 = 4.94 %: +0.52 points, under 2 x 0.49)
put(runs, "tap-model-no-rolling-seed1", tap(768.0, 805.0))
out = table(model)
expect("- compaction before the strikes, tap-model-no-rolling-seed1 against the calibrated single spheres: 4.94 % "
       "against 4.42 % (+0.52 points; the single spheres' seeds 4.14, 4.71 %; one run's standard deviation 0.40 "
       "points from them, the difference's 0.49: not told apart (under two standard deviations))" in out,
       "within the twins' scatter", out)
shutil.rmtree(os.path.join(runs, "tap-model-no-rolling-seed1"))
out = table(model)
expect("- compaction before the strikes, tap-model-no-rolling-seed1 against the calibrated single spheres: not every "
       "case has finished" in out and "Loose and tapped density (scenarios" not in out
       and "the tapping rate (reduced" not in out, "an unstarted case; not in the other tapped tables", out)
for case in model + ["tap-rate-8.66hz-seed1", "tap-rate-8.66hz-seed2"]:
    shutil.rmtree(os.path.join(runs, case), ignore_errors=True)

# The single-sphere test weight's time step: each coarser step's seeds against the finest's
# (sd: sqrt(2) from pairs 2 apart; the difference's: 1.41; 20 %: -4.0 > 2 x 1.41, 10 %: -2.0 not)
steps = {"tw-dt-20-seed1": 800.0, "tw-dt-20-seed2": 802.0, "tw-dt-10-seed1": 802.0, "tw-dt-10-seed2": 804.0,
         "tw-dt-5-seed1": 804.0, "tw-dt-5-seed2": 806.0}
heaped = {"value": 850.0, "unit": "kg/m3", "not_full": "its lowest point lay 48.8 mm below"}  # (never full)
for case, value in steps.items():
    put(runs, case, dict(test_weight(value, heaped), dt_s=int(case.split("-")[2]) * 0.25e-6))
out = table(sorted(steps))
lines = [l.split("|")[1].strip() for l in out.splitlines() if l.startswith("| tw-dt-")]
expect(lines == list(steps), "rows from the coarsest step, by seed", out)
expect("| tw-dt-20-seed2 | 20 | 1.25 | 2 | 850.0 | 802.0 | -1.0 | 4.00 |" in out,
       "a step's row: its share of the critical step (5 / 4 us), the unstruck density unmarked and the strike "
       "(802 / 810)", out)
expect("- struck density at 20 % against 5 % of the Rayleigh step: -4.0 kg/m3 (-0.50 %) on the seeds' means; one "
       "run's standard deviation 1.4 kg/m3, the difference's 1.4: the steps are told apart" in out, "20 % told apart", out)
expect("- struck density at 10 % against 5 % of the Rayleigh step: -2.0 kg/m3 (-0.25 %) on the seeds' means; one "
       "run's standard deviation 1.4 kg/m3, the difference's 1.4: the steps are not told apart" in out,
       "10 % not told apart", out)
expect("Test weight per bushel" not in out and "KanMark" not in out, "not a test-weight sample", out)
put(runs, "tw-dt-5-seed2", dict(summary({}), interrupted=True))
out = table(sorted(steps))
expect("Rayleigh step:" not in out, "no verdict before the finest step has finished", out)
for case in steps:
    shutil.rmtree(os.path.join(runs, case))

# The expected test weights as a reference table for bushel report (docs/report.md).
out = subprocess.run([sys.executable, script, "--expected", references], check=True, capture_output=True,
                     text=True).stdout
expect(out.startswith("scenario,result,share_large,share_medium,share_small,drop,value,unit,sd,source\n")
       and "\ntest-weight,bulk_density,81.5%,15.5%,3%,5.1 cm,62.15,lb/bu,," in out
       and "\ntest-weight,bulk_density,21.8%,60.6%,17.6%,5.1 cm,59.15,lb/bu,," in out, "the expected test weights", out)

# The mixing excess, on made-up mixtures that follow a known special cubic exactly: the fit
# returns it, so the excess is the polynomial over the ideal mixture of its pure values.
sys.path.insert(0, os.path.dirname(script))
import study_table  # noqa: E402

def packing(l, m, s):
    return 0.63 * l + 0.60 * m + 0.56 * s + 0.04 * l * m + 0.03 * l * s + 0.02 * m * s + 0.1 * l * m * s

made_up = os.path.join(work, "ternary.csv")
with open(made_up, "w") as f:
    f.write("# made up\nm7_pct,m8_pct,m10_pct,packing_ratio_kanmark\n")
    for l in range(0, 101, 20):
        for m in range(0, 101 - l, 20):
            f.write(f"{l},{m},{100 - l - m},{packing(l / 100, m / 100, (100 - l - m) / 100)}\n")
shares = (0.5, 0.3, 0.2)
exact = packing(*shares) * sum(s / p for s, p in zip(shares, (0.63, 0.60, 0.56))) - 1
got = study_table.mixing_excess(made_up, shares)
expect(abs(got - exact) < 1e-12, f"mixing excess {got}, not {exact}", "")
expect(study_table.mixing_excess(made_up, (0.0, 1.0, 0.0)) == 0.0, "no excess of a pure fraction", "")

for f in failures:
    print("FAIL:", f)
print(f"study table check: {len(failures)} failed")
sys.exit(1 if failures else 0)
