#!/usr/bin/env python3
"""How much of the tapped-density cylinder the kernels fill, loose and tapped, in its core and
across its whole width, from a finished run's frames (scenarios/tapped-density.yaml): whether
the kernels' tapped packing in the core, away from the wall, is already that of random close
packing, which equal spheres exceed only by ordering.

usage: tap_packing.py [--core 15mm,20mm] [--margin 10mm] [--points 200000] [--csv OUT.csv [--update]] RUN...
  RUN: a finished run's folder (summary.json, frames/particles.pvd with its .vtu files)

For each state, the last particle frame of the stretch in which the cylinder, full, stands
still: loose, from the stage rest (the poured heap settled) to the first tap; tapped, from the
stage tapped_rest to the run's end, whose last frame bushel writes (the extension taken off and
the tapped grain struck). The strikes at the rim and the top-up falling onto the loose grain leave
it as it was MARGIN below the rim (at full size the tapped core reads the same within 0.0005
before and after the strike). The cylinder's bottom is at z = 0 there, its axis the z axis (the
scenario's). Two regions between MARGIN above the bottom and
MARGIN below the rim: the core, of each radius in CORE, and the whole cylinder (its radius, the
parameter diameter / 2). Against the wall the kernels lie in layers, so a core's fraction
depends on its radius, by up to 0.008. The solid fraction of a region is the share of POINTS points, drawn uniformly
in it with a fixed seed, that lie inside a kernel's element sphere (overlapping elements of one
clump count once): the union of the spheres, whatever their shape or sizes. Its standard error
is that of the sampling, sqrt(f (1 - f) / POINTS), not of the packing's own variation. The bulk
density there is the fraction x the kernels' density (the parameter kernel_density), the
packing ratio's measure.

Prints a table and, with --csv, writes it (case, state, time [s], the frame's stage, region,
radius [m], solid fraction, standard error, bulk density [kg/m3]); with --update, the rows of the
cases not given stay, in their places, as tap_series.py --update keeps them.
"""
import argparse
import importlib.util
import json
import math
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from tap_series import quantity, write_rows  # noqa: E402
# bushel's frame reader (python/bushel/frames.py: numpy only), without the compiled module the
# package needs.
_spec = importlib.util.spec_from_file_location("bushel_frames", os.path.join(HERE, "..", "python", "bushel",
                                                                              "frames.py"))
frames = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(frames)

STATES = (("loose", "rest", "tap"), ("tapped", "tapped_rest", None))  # state, from, to (stages; None: the end)
NEIGHBOURS = 16  # element centres checked per point, enough while fewer lie within the largest radius
END_SLACK = 1e-6  # [s] the last frame's time may pass the run's recorded end by rounding


def solid_fraction(centres, radii, radius, z0, z1, points, seed=1):
    """The share of POINTS points drawn uniformly in the cylinder r < RADIUS, z0 < z < z1 that
    lie inside a sphere (centres [m], radii [m]), and its sampling standard error."""
    rng = np.random.default_rng(seed)
    r = radius * np.sqrt(rng.random(points))
    phi = 2 * np.pi * rng.random(points)
    q = np.column_stack((r * np.cos(phi), r * np.sin(phi), z0 + (z1 - z0) * rng.random(points)))
    largest = float(radii.max())
    k = min(NEIGHBOURS, len(radii))
    dist, idx = cKDTree(centres).query(q, k=k, distance_upper_bound=largest)
    dist, idx = dist.reshape(points, k), idx.reshape(points, k)
    found = np.isfinite(dist)  # (the neighbours beyond the largest radius come back as inf)
    inside = np.zeros_like(found)
    inside[found] = dist[found] < radii[idx[found]]
    inside = inside.any(axis=1)
    # A point outside its k nearest spheres whose k-th centre is within the largest radius may lie
    # in a further one.
    if k < len(radii) and (found[:, -1] & ~inside).any():
        raise SystemExit(f"tap_packing.py: more than {k} element centres lie within {largest * 1e3:.3f} mm of "
                         "a point; raise NEIGHBOURS")
    f = float(inside.mean())
    return f, math.sqrt(f * (1 - f) / points)


def frame_in(run, stages, first, last):
    """(time [s], path, stage) of the run's last particle frame from the start of the stage FIRST
    to that of LAST, or to the run's end with it (LAST None; stages: the summary's records by name,
    in order)."""
    end = max(s["end_s"] for s in stages.values())
    t0, t1 = stages[first]["start_s"], stages[last]["start_s"] if last else end + END_SLACK
    pvd = os.path.join(run, "frames", "particles.pvd")
    if not os.path.exists(pvd):
        raise SystemExit(f"tap_packing.py: {run}: no frames ({pvd}); the run needs its particle frames")
    inside = sorted((t, p) for t, p in frames.read_pvd(pvd) if t0 <= t < t1)
    if not inside:
        raise SystemExit(f"tap_packing.py: {run}: no particle frame from the stage {first} to "
                         f"{last or 'the end'} "
                         f"({t0:.3f} to {t1:.3f} s); a smaller frame_interval writes one")
    t, path = inside[-1]
    if not os.path.exists(path):
        raise SystemExit(f"tap_packing.py: {run}: the frame {path} that particles.pvd names is missing")
    stage = (s["name"] for s in stages.values() if s["start_s"] <= t < s["end_s"] or t >= s["end_s"] == end)
    return t, path, next(stage, "?")


def measure(run, cores, margin, points):
    """The rows of one finished run: (state, time, stage, region, radius, fraction, error, density)."""
    with open(os.path.join(run, "summary.json")) as f:
        j = json.load(f)
    if j.get("interrupted") or j.get("failed"):
        raise SystemExit(f"tap_packing.py: {run} has not finished")
    p = j["parameters"]
    radius = quantity(p["diameter"], "diameter") / 2
    height = quantity(p["height"], "height")
    density = quantity(p["kernel_density"], "kernel_density")
    if max(cores) >= radius or 2 * margin >= height:
        raise SystemExit(f"tap_packing.py: {run}: the core ({max(cores) * 1e3:g} mm) or the margins "
                         f"({margin * 1e3:g} mm) do not fit the cylinder ({radius * 1e3:g} mm x {height * 1e3:g} mm)")
    stages = {s["name"]: s for s in j["stages"]}
    rows = []
    for state, first, last in STATES:
        t, path, stage = frame_in(run, stages, first, last)
        frame = frames.read_vtu(path)
        radii = np.asarray(frame.point_data["radius_m"], float)
        for region, r in [("core", c) for c in cores] + [("whole", radius)]:
            f, se = solid_fraction(frame.points, radii, r, margin, height - margin, points)
            rows.append((state, t, stage, region, r, f, se, f * density))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--core", default="15mm,20mm", help="the cores' radii, by commas (default 15 mm, 20 mm)")
    ap.add_argument("--margin", default="10mm", help="left out above the bottom and below the rim (default 10 mm)")
    ap.add_argument("--points", type=int, default=200000, help="points drawn per region (default 200000)")
    ap.add_argument("--csv", help="also write the table as CSV")
    ap.add_argument("--update", action="store_true", help="with --csv: keep the rows of the cases not given")
    ap.add_argument("runs", nargs="+")
    a = ap.parse_args()
    if a.update and not a.csv:
        ap.error("--update needs --csv")
    if a.points < 100:
        raise SystemExit(f"tap_packing.py: --points {a.points}: expected at least 100")
    cores, margin = [quantity(c, "--core") for c in a.core.split(",")], quantity(a.margin, "--margin")
    if min(cores) <= 0 or margin < 0:
        raise SystemExit(f"tap_packing.py: --core {a.core} --margin {a.margin}: expected radii above 0 and a "
                         "margin of 0 or more")
    print("| case | state | frame [s] | stage | region | radius [mm] | solid fraction | standard error (sampling) "
          "| bulk density [kg/m3] |")
    print("|---|" + "---|" * 8)
    out = {}  # case -> its CSV rows
    for run in a.runs:
        case = os.path.basename(os.path.normpath(run))
        for state, t, stage, region, r, f, se, rho in measure(run, cores, margin, a.points):
            print(f"| {case} | {state} | {t:.2f} | {stage} | {region} | {r * 1e3:.2f} | {f:.4f} | {se:.4f} "
                  f"| {rho:.1f} |")
            out.setdefault(case, []).append([case, state, f"{t:.4f}", stage, region, f"{r:.5f}", f"{f:.5f}",
                                             f"{se:.5f}", f"{rho:.2f}"])
    if a.csv:
        write_rows(a.csv, ["case", "state", "time", "stage", "region", "radius", "solid_fraction", "standard_error",
                           "bulk_density"], out, a.update)


if __name__ == "__main__":
    main()
