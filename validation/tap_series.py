#!/usr/bin/env python3
"""The bulk density in the tapped cylinder tap by tap, from finished tapped-density runs
(scenarios/tapped-density.yaml): whether grain tapped at another rate packs denser before the
strike, where the struck (tapped) density also depends on how the strike leaves the surface.

usage: tap_series.py [--update] --csv OUT.csv [--phases PHASES.csv] RUN...
  RUN: a finished run's folder (summary.json, timeseries.csv)

A tap's period is the lift, then the free fall onto the stop: the impact ends it. So in period
k (from 0) the time series' sample where the cylinder stands lowest comes just after k impacts
(k = 0: the settled fill before the first; the state after the last is the stage
tapped_rest's), the extension's grain above the rim, so the cylinder is full. Its cylinder
sensor's bulk density (kernels centred in it) is read there. The sensor is fixed in space and
the cylinder has risen by z at that sample (up to 0.02 mm at 4.33 Hz, 0.09 mm at 8.66 Hz: 10 ms
into the lift), so the bottom z of the sensor is empty: the value is scaled by H / (H - z), H
the cylinder's height (at 8.66 Hz in a 30 mm cylinder up to 0.3 %). Writes every period to
OUT.csv (case, impacts, bulk_density [kg/m3], z [m]) and prints, per run, the means over the
first, the middle and the last tenth of the periods, with a rough standard error of the last
(the scatter about its mean over the square root of the count), and how fast it still grows:
the least-squares slope of the density against the log of the count of impacts from the fifth
of the taps on (from the 100th of 500), in kg/m3 per tenfold taps, as a tapped bed's density
grows about as the log of the count. The values are not independent: the bed carries over from
tap to tap, and where the period is not a whole number of samples the sample's delay after the
impact alternates from tap to tap (at 8.66 Hz, 11.5 samples of 10 ms), which shows as
neighbouring values moving opposite ways.

--phases: whether the bed is at rest when the next fall begins, the condition under which only
the lift between the taps, not their impact, differs between rates. Over the periods after the
first tenth, the time series' kinetic energy per particle and the cylinder's height are averaged
in bins of one sample interval by the time into the period (0: the impact just past, the lift
beginning). The quietest bin lies near the top of the lift, where the cylinder slows to a stop: its
kinetic energy bounds the grain's own agitation when the fall begins (it still holds some of the
cylinder's motion), and the summary sets it against that just after the impact. Writes
PHASES.csv (case, phase_start [s], kinetic_energy_per_particle [J], z [m], samples).

--update: OUT.csv and PHASES.csv keep the rows of the cases not given (runs whose folders are
gone), in their order; a case given replaces its rows where they were, a new one comes last.
Each file is written whole under another name and then renamed, so that two scripts refreshing
it at once leave one of their versions, never a mix.
"""
import argparse
import csv
import json
import math
import os
import re
import sys
from statistics import mean, median, stdev

UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "Hz": 1.0, "kg/m3": 1.0}


def quantity(text, what):
    """A parameter's or option's text ('30mm', '8.66 Hz', '1373 kg/m3') in SI; WHAT names it in
    the refusal."""
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*([A-Za-z/0-9]+)\s*", str(text))
    if not m or m.group(2) not in UNITS:
        raise SystemExit(f"{os.path.basename(sys.argv[0])}: {what}: cannot read the quantity '{text}' (expected a "
                         "number and one of " + ", ".join(UNITS) + ")")
    return float(m.group(1)) * UNITS[m.group(2)]


def tap_stage(run):
    """A finished run's taps: (rate [Hz], cylinder height [m], taps, the stage's start [s], its
    time series' rows)."""
    with open(os.path.join(run, "summary.json")) as f:
        j = json.load(f)
    if j.get("interrupted") or j.get("failed"):
        raise SystemExit(f"tap_series.py: {run} has not finished")
    p = j["parameters"]
    start = next(s["start_s"] for s in j["stages"] if s["name"] == "tap")
    with open(os.path.join(run, "timeseries.csv")) as f:
        rows = [r for r in csv.DictReader(l for l in f if not l.startswith("#")) if r["stage"] == "tap"]
    return quantity(p["tap_frequency"], "tap_frequency"), quantity(p["height"], "height"), int(p["taps"]), start, rows


def taps(run, stage):
    """Per period of the run's taps (its tap_stage): (bulk density [kg/m3] at the cylinder's
    lowest sample, its z [m]); period k after k impacts."""
    rate, height, count, start, rows = stage
    lowest = {}  # period -> (z, bulk density)
    for r in rows:
        k = min(int((float(r["time"]) - start) * rate), count - 1)
        z = float(r["base.position_z"])
        if k not in lowest or z < lowest[k][0]:
            lowest[k] = (z, float(r["cylinder.bulk_density"]))
    if len(lowest) != count:
        raise SystemExit(f"tap_series.py: {run}: {len(lowest)} taps in its time series, not {count}")
    return [(rho * height / (height - z), z) for z, rho in (lowest[k] for k in range(count))]


def per_decade(rho, first):
    """How fast the density still grows: the least-squares slope of rho (one value per period,
    period k after k impacts) against log10(k) over the periods from FIRST on [kg/m3 per tenfold
    taps], and a rough standard error of it (the residuals' scatter, as if independent, which
    they are not: see the module's doc); (None, None) under three periods from FIRST."""
    if len(rho) - first < 3:
        return None, None
    x = [math.log10(k) for k in range(first, len(rho))]
    y = rho[first:]
    mx, my = mean(x), mean(y)
    sxx = sum((a - mx) ** 2 for a in x)
    slope = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sxx
    rss = sum((b - my - slope * (a - mx)) ** 2 for a, b in zip(x, y))
    return slope, math.sqrt(rss / (len(x) - 2) / sxx)


def phases(stage):
    """Per bin of one sample interval into the period, over the periods after the first tenth of
    a run's taps (its tap_stage): (bin's start [s], mean kinetic energy per particle [J], mean z
    [m], samples)."""
    rate, _, count, start, rows = stage
    times = [float(r["time"]) for r in rows]
    width = median(b - a for a, b in zip(times, times[1:]))
    bins = {}  # bin -> [kinetic energies, z]
    for t, r in zip(times, rows):
        k = int((t - start) * rate)
        if count // 10 <= k < count:
            b = bins.setdefault(int(((t - start) - k / rate) / width), ([], []))
            b[0].append(float(r["kinetic_energy_per_particle"]))
            b[1].append(float(r["base.position_z"]))
    return [(i * width, mean(e), mean(z), len(e)) for i, (e, z) in sorted(bins.items())]


def quietest(bins):
    """The quietest of a run's phase bins (tuples starting with the bin's start [s] and its kinetic
    energy [J], in time order) and its kinetic energy over the first bin's, just after the impact."""
    quiet = min(bins, key=lambda b: b[1])
    return quiet, quiet[1] / bins[0][1]


def write_rows(path, header, rows, update):
    """Writes {case: its rows} under header to path; with update, the cases already in the file
    and not in rows keep their rows and places (see --update)."""
    cases = {}
    if update and os.path.exists(path):
        with open(path, newline="") as f:
            old = csv.reader(f)
            if next(old, None) != header:
                raise SystemExit(f"{os.path.basename(sys.argv[0])}: {path} does not start with the header "
                                 f"{','.join(header)}")
            for r in old:
                cases.setdefault(r[0], []).append(r)
    cases.update(rows)
    tmp = f"{path}.{os.getpid()}.tmp"
    with open(tmp, "w", newline="") as out:
        w = csv.writer(out)
        w.writerow(header)
        for r in cases.values():
            w.writerows(r)
    os.replace(tmp, path)


def write_phases(path, stages, update):
    """PHASES.csv of every run ({case: its tap_stage}), and the summary: the kinetic energy of the
    quietest bin against that just after the impact."""
    print("\n| case | kinetic energy after the impact [J] | quietest [J] | quietest / after the impact "
          "| quietest at [ms into the period] | cylinder there [mm] |")
    print("|---|" + "---|" * 5)
    rows = {}
    for case, stage in stages.items():
        bins = phases(stage)
        rows[case] = [[case, f"{t:.4f}", f"{e:.4e}", f"{z:.4e}", n] for t, e, z, n in bins]
        (t, e, z, _), ratio = quietest(bins)
        print(f"| {case} | {bins[0][1]:.3g} | {e:.3g} | {ratio:.2g} | {t * 1e3:.0f} | {z * 1e3:.2f} |")
    write_rows(path, ["case", "phase_start", "kinetic_energy_per_particle", "z", "samples"], rows, update)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--csv", required=True)
    ap.add_argument("--phases", help="also the kinetic energy and height by the time into the period")
    ap.add_argument("--update", action="store_true", help="keep the rows of the cases not given")
    ap.add_argument("runs", nargs="+")
    a = ap.parse_args()
    print("| case | taps | first tenth [kg/m3] | middle tenth [kg/m3] | last tenth [kg/m3] "
          "| standard error, last (rough) [kg/m3] | per tenfold taps, from the fifth [kg/m3] (rough error) "
          "| largest z [mm] |")
    print("|---|" + "---|" * 7)
    stages, rows = {}, {}  # case -> its tap_stage (read once for both tables), its rows
    for run in a.runs:
        case = os.path.basename(os.path.normpath(run))
        stages[case] = tap_stage(run)
        series = taps(run, stages[case])
        rows[case] = [[case, k, f"{rho:.2f}", f"{z:.3e}"] for k, (rho, z) in enumerate(series)]
        rho = [r for r, _ in series]
        n = max(2, len(rho) // 10)
        tenths = (rho[:n], rho[(len(rho) - n) // 2:(len(rho) + n) // 2], rho[-n:])
        se = stdev(tenths[-1]) / math.sqrt(n)
        slope, slope_se = per_decade(rho, max(1, len(rho) // 5))
        print(f"| {case} | {len(rho)} | " + " | ".join(f"{mean(t):.1f}" for t in tenths)
              + f" | {se:.1f} | {'' if slope is None else f'{slope:.1f} ({slope_se:.1f})'} "
              + f"| {max(z for _, z in series) * 1e3:.3f} |")
    write_rows(a.csv, ["case", "impacts", "bulk_density", "z"], rows, a.update)
    if a.phases:
        write_phases(a.phases, stages, a.update)


if __name__ == "__main__":
    main()
