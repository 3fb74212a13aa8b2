#!/usr/bin/python3
"""Reduced versions of the four reference experiments (scenarios/, docs/experiments.md), each a
few minutes on 2 cores, checked for the behaviour physics requires:

  calibration cup   the gate opens in 0.4 s (180 degrees at 7.85 rad/s); the cup fills and
                    overflows; striking lowers the bulk density below the heaped cup's;
                    sinks do not change the bulk density beyond the seed-to-seed noise
  test weight       the bulk density rises with the drop height (h and 16 h)
  compression       the bulk density rises with every pressure level; every hold ends
                    quasi-static (unbalanced force ratio below 1e-4)
  tapped density    tapping raises the bulk density

The reduced versions use the single-sphere model (the sphere of each kernel's mass) and small
vessels; they check directions, not the study's values (validation/run-cup.sh does those).

  validation/experiments-smoke.py [--bushel build/release/bin/bushel] [--out DIR] [--only NAME]

Writes each run under DIR (default validation/results/smoke-<UTC time>), a table of the checks
as DIR/checks.md and exits 1 if a check fails.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPHERE = ["model=1s", "fr_ww=0.05", "fs_ww=0.172", "e_ww=0.5"]  # docs/wheat.md: large-large, 1 sphere

# name: (scenario, parameter overrides)
CUP = ["mass=80g", "cup_height=25mm"] + SPHERE
TEST_WEIGHT = ["model=1s", "mass=150g", "kettle_volume=60cm3", "kettle_diameter=50mm", "hopper_top=100mm",
               "hopper_outlet=25mm", "striker_length=90mm"]
RUNS = {
    "cup": ("calibration-cup.yaml", CUP),
    "cup-seed2": ("calibration-cup.yaml", CUP + ["seed=2"]),
    "cup-no-sinks": ("calibration-cup.yaml", CUP + ["sinks=false"]),
    "test-weight-h": ("test-weight.yaml", TEST_WEIGHT + ["drop=5.1cm"]),
    "test-weight-16h": ("test-weight.yaml", TEST_WEIGHT + ["drop=81.6cm"]),
    "compression": ("compression.yaml", ["mass=120g", "height=30mm"] + SPHERE),
    "tapped": ("tapped-density.yaml", ["mass=120g", "height=30mm", "extension_height=20mm", "top_up=40g",
                                       "taps=10"] + SPHERE),
}


def run(bushel, name, out):
    scenario, sets = RUNS[name]
    target = os.path.join(out, name)
    summary = os.path.join(target, "summary.json")
    if os.path.exists(summary) and not json.load(open(summary))["interrupted"]:
        print(f"{name}: done before, kept", flush=True)
        return json.load(open(summary))
    args = [bushel, "run", os.path.join(ROOT, "scenarios", scenario), "--out", target, "--quiet", "--overwrite",
            "--set", "parameters.frame_interval=1s"]
    if os.path.exists(os.path.join(target, "checkpoint.bin")):
        args = [bushel, "run", "--restart", target, "--quiet"]
    for s in sets:
        if args[2] != "--restart":
            args += ["--set", "parameters." + s]
    t0 = time.time()
    print(f"{name}: {' '.join(args[1:])}", flush=True)
    subprocess.run(args, check=True)
    print(f"{name}: {time.time() - t0:.0f} s", flush=True)
    return json.load(open(summary))


def result(summary, key):
    r = summary["results"].get(key)
    return r["value"] if r else float("nan")


def stage(summary, name):
    return next(s for s in summary["stages"] if s["name"] == name)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bushel", default=os.path.join(ROOT, "build/release/bin/bushel"))
    ap.add_argument("--out", default=os.path.join(
        ROOT, "validation/results", "smoke-" + datetime.datetime.utcnow().strftime("%Y%m%dT%H%M%SZ")))
    ap.add_argument("--only", choices=["cup", "test-weight", "compression", "tapped"])
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    checks = []  # (experiment, what, measured, passed)

    def check(experiment, what, measured, passed):
        checks.append((experiment, what, measured, bool(passed)))
        print(f"  {'ok  ' if passed else 'FAIL'} {experiment}: {what}: {measured}", flush=True)

    if a.only in (None, "cup"):
        cup, seed2, bare = (run(a.bushel, n, a.out) for n in ("cup", "cup-seed2", "cup-no-sinks"))
        opened = stage(cup, "open")
        check("calibration cup", "the gate turns 180 degrees in 0.4 s",
              f"{result(cup, 'gate_angle'):.3f} deg in {opened['end_s'] - opened['start_s']:.4f} s",
              abs(result(cup, "gate_angle") - 180) < 1e-3 and abs(opened["end_s"] - opened["start_s"] - 0.4) < 0.002)
        rest = stage(cup, "rest")["values"]
        check("calibration cup", "the cup fills (grain stands above the rim) and overflows (grain removed below it)",
              f"{rest['heaped.mass'] * 1e3:.1f} g in and on the cup, {rest['cup.mass'] * 1e3:.1f} g in it, "
              f"{rest['removed_mass'] * 1e3:.1f} g overflowed",
              rest["heaped.mass"] > rest["cup.mass"] and rest["removed_mass"] > 0)
        check("calibration cup", "striking lowers the bulk density below the heaped cup's",
              f"{result(cup, 'bulk_density_struck'):.1f} < {result(cup, 'bulk_density_unstruck'):.1f} kg/m3",
              result(cup, "bulk_density_struck") < result(cup, "bulk_density_unstruck"))
        noise = abs(result(seed2, "bulk_density") - result(cup, "bulk_density"))
        diff = abs(result(bare, "bulk_density") - result(cup, "bulk_density"))
        check("calibration cup", "without sinks the bulk density differs by no more than between two seeds (+0.5%)",
              f"{result(bare, 'bulk_density'):.1f} vs {result(cup, 'bulk_density'):.1f} kg/m3 "
              f"(seed 2: {result(seed2, 'bulk_density'):.1f}); wall {bare['wall_time_s']:.0f} s vs "
              f"{cup['wall_time_s']:.0f} s", diff <= noise + 0.005 * result(cup, "bulk_density"))
    if a.only in (None, "test-weight"):
        low, high = (run(a.bushel, n, a.out) for n in ("test-weight-h", "test-weight-16h"))
        check("test weight", "the bulk density rises with the drop height (h to 16 h)",
              f"{result(low, 'bulk_density'):.1f} -> {result(high, 'bulk_density'):.1f} kg/m3",
              result(high, "bulk_density") > result(low, "bulk_density"))
        fractions = sum(result(low, k) for k in ("fraction_large", "fraction_medium", "fraction_small"))
        check("test weight", "striking lowers the bulk density; the kettle's composition adds up to 1",
              f"{result(low, 'bulk_density'):.1f} < {result(low, 'bulk_density_unstruck'):.1f} kg/m3; sum {fractions:.6f}",
              result(low, "bulk_density") < result(low, "bulk_density_unstruck") and abs(fractions - 1) < 1e-9)
    if a.only in (None, "compression"):
        comp = run(a.bushel, "compression", a.out)
        curve = [result(comp, "bulk_density_0")] + [result(comp, f"bulk_density_{k}") for k in range(1, 8)]
        check("compression", "the bulk density rises with every pressure level (0, 7 ... 138 kPa)",
              " < ".join(f"{x:.1f}" for x in curve), all(b > a_ for a_, b in zip(curve, curve[1:])))
        unbalanced = [result(comp, f"unbalanced_{k}") for k in range(1, 8)]
        check("compression", "every hold ends quasi-static: unbalanced force ratio below 1e-4 (docs/wheat.md)",
              ", ".join(f"{u:.1e}" for u in unbalanced), max(unbalanced) < 1e-4)
    if a.only in (None, "tapped"):
        tap = run(a.bushel, "tapped", a.out)
        check("tapped density", "tapping raises the bulk density",
              f"{result(tap, 'loose_bulk_density'):.1f} -> {result(tap, 'tapped_bulk_density'):.1f} kg/m3, "
              f"compressibility {result(tap, 'compressibility'):.4f}",
              result(tap, "tapped_bulk_density") > result(tap, "loose_bulk_density"))

    with open(os.path.join(a.out, "checks.md"), "w") as f:
        f.write("| experiment | check | measured | |\n|---|---|---|---|\n")
        for e, w, m, p in checks:
            f.write(f"| {e} | {w} | {m} | {'ok' if p else 'FAIL'} |\n")
    failed = sum(not p for *_, p in checks)
    print(f"{len(checks) - failed} of {len(checks)} checks passed; {os.path.join(a.out, 'checks.md')}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
