#!/usr/bin/env python3
"""validation/tap_series.py on a made-up tapped-density run: each period of the taps takes the
sample where the cylinder stands lowest, after as many impacts as periods before it, its
density scaled by H / (H - z); the CSV holds every period and the summary the means of the
tenths and the slope against the log of the impacts from the fifth on; --phases averages the
kinetic energy and height by the time into the period over the periods after the first tenth
and names the quietest bin; --update keeps the other cases' rows; an unfinished run, a time
series short of taps and a parameter without a unit it knows are refused with a message that
names them.

usage: tap_series_check.py TAP_SERIES_PY WORKDIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

import numpy

script, work = sys.argv[1:3]
shutil.rmtree(work, ignore_errors=True)
failures = []
H, RATE, TAPS, START = 0.030, 5.0, 20, 1.0  # 30 mm, 5 Hz: a tap every 0.2 s from t = 1 s
Z = (3e-3, 3e-4, 1e-3, 2e-3)  # [m] the cylinder's height at the 4 samples of a period
KE = (4e-7, 1e-7, 2e-9, 5e-8)  # [J] the kinetic energy per particle there


def make(name, summary_extra=None, taps=TAPS, height="30 mm"):
    """A run whose tap k (from 0) has 4 samples 50 ms apart: z 3, 0.3, 1 and 2 mm, the density
    at z 0.3 mm 800 + k kg/m3 and 700 elsewhere, the kinetic energy KE[i] (+ 1 J before the
    first tenth's end, which the phases must leave out)."""
    run = os.path.join(work, name)
    os.makedirs(run)
    j = {"interrupted": False, "failed": None,
         "parameters": {"tap_frequency": f"{RATE:g}Hz", "height": height, "taps": str(TAPS)},
         "stages": [{"name": "settle", "start_s": 0.5}, {"name": "tap", "start_s": START}]}
    j.update(summary_extra or {})
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump(j, f)
    with open(os.path.join(run, "timeseries.csv"), "w") as f:
        f.write("stage,time,cylinder.bulk_density,base.position_z,kinetic_energy_per_particle\n"
                "settle,0.9,650,0,0\n")
        for k in range(taps):
            for i, z in enumerate(Z):
                ke = KE[i] + (1.0 if k < taps // 10 else 0.0)
                f.write(f"tap,{START + k / RATE + 0.05 * i + 0.001},{800 + k if i == 1 else 700},{z},{ke}\n")
        f.write("tapped,9.0,650,0,0\n")
    return run


def run(*args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


good = make("tap-good")
out_csv = os.path.join(work, "series.csv")
phases_csv = os.path.join(work, "phases.csv")
r = run("--csv", out_csv, "--phases", phases_csv, good)
if r.returncode != 0:
    failures.append("a finished run: " + r.stderr)
else:
    rows = list(csv.DictReader(open(out_csv)))
    scale = H / (H - 3e-4)
    want = [round((800 + k) * scale, 2) for k in range(TAPS)]
    got = [float(x["bulk_density"]) for x in rows]
    if [x["case"] for x in rows] != ["tap-good"] * TAPS or [int(x["impacts"]) for x in rows] != list(range(TAPS)):
        failures.append(f"the CSV's cases and impacts: {rows[:3]}")
    if got != want:
        failures.append(f"densities {got}, not {want}")
    # (tenths of 20 taps: 2 each; first 800, 801; middle 809, 810; last 818, 819; all x scale)
    # (the slope against log10 of the impacts from the fifth, 4, to 19, by numpy's least squares)
    slope, icpt = numpy.polyfit(numpy.log10(range(4, TAPS)), [w for w in want[4:]], 1)
    rms = numpy.sqrt(sum((w - icpt - slope * numpy.log10(k)) ** 2 for k, w in enumerate(want) if k >= 4) / 14)
    slope_se = rms / numpy.sqrt(sum((numpy.log10(range(4, TAPS)) - numpy.log10(range(4, TAPS)).mean()) ** 2))
    line = (f"| tap-good | 20 | {800.5 * scale:.1f} | {809.5 * scale:.1f} | {818.5 * scale:.1f} | 0.5 "
            f"| {slope:.1f} ({slope_se:.1f}) | 0.300 |")
    if line not in r.stdout:
        failures.append(f"summary line {line!r} not in:\n{r.stdout}")
    rows = list(csv.DictReader(open(phases_csv)))
    want = [["tap-good", f"{0.05 * i:.4f}", f"{KE[i]:.4e}", f"{Z[i]:.4e}", "18"] for i in range(4)]
    got = [[x["case"], x["phase_start"], x["kinetic_energy_per_particle"], x["z"], x["samples"]] for x in rows]
    if got != want:
        failures.append(f"phases {got}, not {want}")
    line = "| tap-good | 4e-07 | 2e-09 | 0.005 | 100 | 1.00 |"
    if line not in r.stdout:
        failures.append(f"phases' summary line {line!r} not in:\n{r.stdout}")

# --update: another case's rows stay where they were; the case given replaces its own in place,
# a new one comes last; without --update only the cases given are written.
if not failures:
    other = make("tap-other")
    run("--csv", out_csv, "--phases", phases_csv, other, good)
    before = [open(out_csv).read(), open(phases_csv).read()]
    for path in (out_csv, phases_csv):  # (tap-good's rows spoilt: --update must write them anew)
        text = open(path).read()
        open(path, "w").write(text.replace("tap-good,", "tap-good,9"))
    r = run("--update", "--csv", out_csv, "--phases", phases_csv, good)
    if r.returncode != 0 or [open(out_csv).read(), open(phases_csv).read()] != before:
        failures.append("--update with a case already there: its rows in place, the other's kept")
    r = run("--update", "--csv", out_csv, "--phases", phases_csv, make("tap-new"))
    cases = [x["case"] for x in csv.DictReader(open(phases_csv))]
    if r.returncode != 0 or list(dict.fromkeys(cases)) != ["tap-other", "tap-good", "tap-new"]:
        failures.append(f"--update with a new case: cases {list(dict.fromkeys(cases))}")
    r = run("--csv", out_csv, "--phases", phases_csv, good)
    if {x["case"] for x in csv.DictReader(open(out_csv))} != {"tap-good"}:
        failures.append("without --update only the cases given")
    if [f for f in os.listdir(work) if f.endswith(".tmp")]:
        failures.append("a temporary file left behind")
    open(phases_csv, "w").write("case,when\n")
    r = run("--update", "--csv", out_csv, "--phases", phases_csv, good)
    if r.returncode == 0 or "does not start with the header case,phase_start" not in r.stderr:
        failures.append(f"--update onto a file of another header: exit {r.returncode}, {r.stderr}")

# Three taps: too few for the slope (from the first on, two periods), an empty cell, not a crash.
three = make("tap-three", {"parameters": {"tap_frequency": f"{RATE:g}Hz", "height": "30 mm", "taps": "3"}}, taps=3)
r = run("--csv", os.path.join(work, "three.csv"), three)
if r.returncode != 0 or "| tap-three | 3 | " not in r.stdout or "|  | 0.300 |" not in r.stdout:
    failures.append(f"three taps: exit {r.returncode}, {r.stdout}{r.stderr}")

for name, kw, words in (("tap-interrupted", {"summary_extra": {"interrupted": True}}, "has not finished"),
                        ("tap-short", {"taps": TAPS - 3}, "17 taps in its time series, not 20"),
                        ("tap-unit", {"height": "30 furlongs"}, "cannot read the quantity '30 furlongs'")):
    r = run("--csv", os.path.join(work, name + ".csv"), make(name, **kw))
    if r.returncode == 0 or words not in r.stderr + r.stdout:
        failures.append(f"{name}: exit {r.returncode}, expected '{words}' in: {r.stderr}{r.stdout}")

for f in failures:
    print("FAIL:", f)
print(f"tap series check: {len(failures)} failed")
sys.exit(1 if failures else 0)
