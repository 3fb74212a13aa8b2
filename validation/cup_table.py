#!/usr/bin/env python3
"""The table of the full-size calibration cup cases (validation/run-cup.sh writes it to
validation/results/cup.md): each case's results beside the study's lab value and EDEM result
(data/reference_values.csv), and per particle model whether the bulk density falls from large
to medium to small kernels, as wheat.md requires.

usage: cup_table.py RUNS KEPT REFERENCES CASE...
  RUNS        the run folders (runs/validation): cup-CASE/ with summary.json or checkpoint.bin
  KEPT        the kept results (validation/results/cup-runs): cup-CASE/summary.json of finished
              cases, cup-CASE/checkpoint.bin.xz of parked ones; read before RUNS
  REFERENCES  data/reference_values.csv
  CASE        FRACTION-MODEL, e.g. large-5s
"""
import csv
import json
import os
import sys

FRACTIONS = ("large", "medium", "small")  # wheat.md: bulk density falls in this order


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
    """The engine build that ran a case (summary.json names it since the build recorded it)."""
    e = summary.get("engine")
    if not e:
        return "(not recorded)"
    if len(e["builds"]) > 1:
        return "mixed: " + "; ".join(e["builds"])
    return e["commit"][:12] + (" (uncommitted changes)" if e["uncommitted_changes"] else "")


def fmt(value, spec):
    return format(value, spec) if value is not None else ""


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
            started = any(os.path.exists(os.path.join(d, "cup-" + case, f))
                          for d, f in ((runs, "checkpoint.bin"), (kept, "checkpoint.bin.xz")))
            status = "running or stopped (a checkpoint)" if started else "not started"
            lines.append(f"| {case} | | | {reference} | | | | | | | | | | {status} |")
            continue
        with open(path) as f:
            j = json.load(f)
        result = lambda k: (j["results"].get(k) or {}).get("value")
        bd = result("bulk_density")
        diff = f"{100 * (bd - measured[fraction]) / measured[fraction]:+.1f} %" if bd else ""
        # The unbalanced force ratio at the end of the rest stage says whether the heaped cup
        # was static when the sensor measured it (about 1e-4, wheat.md); a jittering packing
        # compacts.
        rest = [s["values"].get("unbalanced_force") for s in j["stages"] if s["name"] == "rest"]
        unbalanced = f"{rest[0]:.2g}" if rest and rest[0] is not None else ""
        if j["interrupted"]:
            status = "interrupted at t = %.2f s (stage %d)" % (j["simulated_time_s"], len(j["stages"]) + 1)
        else:
            status = "done"
            if bd:
                finished[case] = bd
        lines.append(
            f"| {case} | {fmt(bd, '.1f')} | {fmt(result('bulk_density_struck'), '.1f')} | {reference} | {diff} "
            f"| {fmt(result('filling_time'), '.2f')} | {fmt(result('heap_angle'), '.1f')} | {unbalanced} "
            f"| {j['factories'][0]['count']} | {j['simulated_time_s']:.2f} | {j['wall_time_s'] / 3600:.2f} "
            f"| {j['particle_steps_per_s']:.3g} | {engine(j)} | {status} |")
    lines.append("")
    lines += [order_line(model, finished) for model in ("5s", "1s")]
    return "\n".join(lines)


if __name__ == "__main__":
    if len(sys.argv) < 5:
        sys.exit(__doc__.strip())
    print(table(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]))
