#!/usr/bin/env python3
"""The table of the full-size calibration cup cases (validation/run-cup.sh writes it to
validation/results/cup.md; --readme puts it into a README as well): each case's results beside the
study's lab value and EDEM result (data/reference_values.csv), how far an unfinished case has
got, and per particle model whether the bulk density falls from large to medium to small
kernels, as docs/wheat.md requires.

usage: cup_table.py [--readme FILE] RUNS KEPT REFERENCES CASE...
  --readme FILE  also put the table into FILE, between the lines
                 <!-- cup_table.py: begin --> and <!-- cup_table.py: end -->
  RUNS           the run folders (runs/validation): cup-CASE/ with summary.json, or with
                 checkpoint.bin and timeseries.csv while it runs
  KEPT           the kept results (validation/results/cup-runs): cup-CASE/summary.json of
                 finished cases, cup-CASE/checkpoint.bin.xz and timeseries.csv.xz of parked
                 ones; a kept summary is read before the run folder's
  REFERENCES     data/reference_values.csv
  CASE           FRACTION-MODEL, e.g. large-5s
"""
import csv
import json
import lzma
import os
import re
import sys

FRACTIONS = ("large", "medium", "small")  # docs/wheat.md: bulk density falls in this order


def references(path):
    """The study's lab values (any model) and EDEM results (5 spheres) per fraction [kg/m3],
    as `bushel report` uses them."""
    with open(path) as f:
        rows = [r for r in csv.DictReader(l for l in f if not l.startswith("#"))
                if r["scenario"] == "calibration-cup" and r["result"] == "bulk_density"]
    measured = {r["fraction"]: float(r["value"]) for r in rows if not r["model"]}
    edem = {r["fraction"]: float(r["value"]) for r in rows if r["model"] == "5s"}
    return measured, edem


def engine(summary):
    """The engine builds that ran a case, oldest first, as short commits (summary.json names
    them since the build recorded it)."""
    e = summary.get("engine")
    if not e:
        return "(not recorded)"
    commits = []
    for b in e["builds"]:
        m = re.search(r"commit (\w+)(, uncommitted changes)?", b)
        commits.append(m.group(1)[:7] + (" (uncommitted changes)" if m.group(2) else "") if m else b)
    return commits[0] if len(commits) == 1 else ", ".join(commits[:-1]) + ", then " + commits[-1]


def reached(series, opener=open):
    """'t = T s (STAGE)' of a time series' last row, or None without one: how far an unfinished
    case has got (the series may run a little ahead of its checkpoint)."""
    if not os.path.exists(series):
        return None
    last = None
    with opener(series, "rt") as f:
        for last in f:
            pass
    cells = last.strip().split(",") if last else []
    if len(cells) < 2 or cells[0] == "stage":
        return None
    return f"t = {float(cells[1]):.2f} s ({cells[0]})"


def progress(runs, kept, case, prefix="cup-"):
    """The status of a case without a summary: where its run folder (RUNS/PREFIX+CASE) and its
    parked checkpoint (KEPT/PREFIX+CASE) have got."""
    run, parked = os.path.join(runs, prefix + case), os.path.join(kept, prefix + case)
    states = []
    if os.path.exists(os.path.join(run, "checkpoint.bin")) or os.path.exists(os.path.join(run, "timeseries.csv")):
        at = reached(os.path.join(run, "timeseries.csv"))
        states.append("running or stopped " + (f"at {at}" if at else "(a checkpoint)"))
    if os.path.exists(os.path.join(parked, "checkpoint.bin.xz")):
        at = reached(os.path.join(parked, "timeseries.csv.xz"), lzma.open)
        states.append("parked" + (f" at {at}" if at else ""))
    return "; ".join(states) or "not started"


def fmt(value, spec):
    return format(value, spec) if value is not None else ""


def exponent(value, digits=3):
    """VALUE to DIGITS significant digits in the form 8.22e5."""
    mantissa, power = f"{value:.{digits - 1}e}".split("e")
    return f"{mantissa}e{int(power)}"


def order_line(model, finished):
    """Whether large > medium > small holds for MODEL, once every fraction has finished."""
    ladder = [finished.get(f"{fraction}-{model}") for fraction in FRACTIONS]
    if None in ladder:
        verdict = "not every fraction has finished"
    else:
        holds = ladder[0] > ladder[1] > ladder[2]
        verdict = (("holds" if holds else "does NOT hold") + ": "
                   + ", ".join(f"{v:.1f}" for v in ladder) + " kg/m3")
    return f"- order large > medium > small, {model}: {verdict}"


def table(runs, kept, reference_csv, cases):
    measured, edem = references(reference_csv)
    lines = [
        "| case | bulk density [kg/m3] | struck | measured | EDEM (5s) | diff to measured | filling time [s] "
        "| heap angle [deg] | unbalanced force at rest | particles | simulated [s] | wall [h] "
        "| particle-steps/s | engine | status |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    finished = {}  # case -> bulk density [kg/m3] of a finished case
    for case in cases:
        fraction, model = case.split("-")
        reference = f"{measured[fraction]} | {edem[fraction] if model == '5s' else ''}"
        path = os.path.join(kept, "cup-" + case, "summary.json")
        if not os.path.exists(path):
            path = os.path.join(runs, "cup-" + case, "summary.json")
        if not os.path.exists(path):
            lines.append(f"| {case} | | | {reference} | | | | | | | | | | {progress(runs, kept, case)} |")
            continue
        with open(path) as f:
            j = json.load(f)
        result = lambda k: (j["results"].get(k) or {}).get("value")
        bd = result("bulk_density")
        diff = f"{100 * (bd - measured[fraction]) / measured[fraction]:+.1f} %" if bd else ""
        # The unbalanced force ratio at the end of the rest stage says whether the heaped cup
        # was static when the sensor measured it (about 1e-4, docs/wheat.md); a jittering packing
        # compacts.
        rest = [s["values"].get("unbalanced_force") for s in j["stages"] if s["name"] == "rest"]
        unbalanced = exponent(rest[0], 2) if rest and rest[0] is not None else ""
        if j["interrupted"]:
            status = "interrupted at t = %.2f s (stage %d)" % (j["simulated_time_s"], len(j["stages"]) + 1)
        else:
            status = "done"
            if bd:
                finished[case] = bd
        lines.append(
            f"| {case} | {fmt(bd, '.1f')} | {fmt(result('bulk_density_struck'), '.1f')} | {reference} | {diff} "
            f"| {fmt(result('filling_time'), '.2f')} | {fmt(result('heap_angle'), '.1f')} | {unbalanced} "
            f"| {j['factories'][0]['count']:,} | {j['simulated_time_s']:.2f} | {j['wall_time_s'] / 3600:.2f} "
            f"| {exponent(j['particle_steps_per_s'])} | {engine(j)} | {status} |")
    lines.append("")
    lines += [order_line(model, finished) for model in ("5s", "1s")]
    return "\n".join(lines)


def splice(readme, text):
    """Puts TEXT between README's begin and end lines, written atomically."""
    begin, end = "<!-- cup_table.py: begin -->", "<!-- cup_table.py: end -->"
    with open(readme) as f:
        lines = f.read().split("\n")
    if lines.count(begin) != 1 or lines.count(end) != 1 or lines.index(begin) > lines.index(end):
        sys.exit(f"{readme}: expected one line '{begin}' and, after it, one line '{end}'")
    lines[lines.index(begin) + 1:lines.index(end)] = text.split("\n")
    with open(readme + ".tmp", "w") as f:
        f.write("\n".join(lines))
    os.replace(readme + ".tmp", readme)


if __name__ == "__main__":
    args = sys.argv[1:]
    readme = None
    if args[:1] == ["--readme"] and len(args) > 1:
        readme, args = args[1], args[2:]
    if len(args) < 4:
        sys.exit(__doc__.strip())
    text = table(*args[:3], args[3:])
    if readme:
        splice(readme, text)
    print(text)
