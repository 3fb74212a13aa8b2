#!/usr/bin/env python3
"""validation/tap_packing.py on made-up runs whose solid fraction is known: loose, a simple cubic
lattice of equal spheres, each written twice (counted once), in one quadrant, wholly inside the
core of 15 mm and the region's height, so that each region holds their whole volume; tapped, a
lattice of overlapping pairs of a large and a small sphere filling the cylinder (their union,
by the lens formula: overlaps count once, and a point inside the large sphere nearer the small
one's centre counts). Each state takes the last frame of its stretch (loose: from the stage
rest to the taps; tapped: from tapped_rest to the run's end, inclusive); the bulk density is
the fraction x the kernels' density; an unfinished run, a stretch without a frame, a run
without frames, a quantity without a unit, a negative margin, a core wider than the cylinder
and more element centres near a point than it checks are refused with a message that names
them.

usage: tap_packing_check.py TAP_PACKING_PY WORKDIR
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

script, work = sys.argv[1:3]
shutil.rmtree(work, ignore_errors=True)
failures = []
RADIUS, HEIGHT, DENSITY = 0.03175, 0.040, 1000.0  # the cylinder [m], the kernels [kg/m3]
A = 1e-3  # the simple cubic lattice's spheres [m], 2 A apart
BIG, SMALL, APART, CELL = 0.8e-3, 0.3e-3, 0.9e-3, 2.4e-3  # the pairs' radii and distance, their lattice [m]


def lens(R, r, d):
    """The volume two spheres of radii R and r whose centres lie d apart share."""
    return math.pi * (R + r - d) ** 2 * (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d)


PAIRS = (4 / 3 * math.pi * (BIG ** 3 + SMALL ** 3) - lens(BIG, SMALL, APART)) / CELL ** 3


TOP = HEIGHT - 7e-3  # the pairs' highest centres [m]: above the region's top (8 mm under the rim), not the rim
MARGIN, CORE = 8e-3, 15e-3  # the command's margin and core [m]
# The equal spheres: centres within CORE - A of the axis, in the layers 9, 11, ..., 31 mm, wholly
# inside the region 8 to 32 mm (nothing else there): every region holds all their volume.
LAYERS = np.arange(MARGIN + A, HEIGHT - MARGIN, 2 * A)


def lattice(step, offsets, within=RADIUS + 5e-3, layers=None, quadrant=False):
    """Sphere centres and radii: each (dx, radius) of OFFSETS at every point of a cubic lattice
    of STEP with centres within WITHIN of the axis (with QUADRANT, only where x and y > 0), in
    LAYERS (z [m]; default: up to TOP)."""
    n = int(RADIUS / step) + 2
    g = np.arange(-n, n + 1) * step
    if layers is None:
        layers = np.arange(0, int(TOP / step)) * step + step / 2
    x, y, z = np.meshgrid(g, g, layers, indexing="ij")
    base = np.column_stack((x.ravel(), y.ravel(), z.ravel()))
    base = base[(np.hypot(base[:, 0], base[:, 1]) < within) & ((base[:, 0] > 0) & (base[:, 1] > 0) | (not quadrant))]
    points = np.vstack([base + [dx, 0, 0] for dx, _ in offsets])
    radii = np.concatenate([np.full(len(base), r) for _, r in offsets])
    return points, radii


def vtu(path, points, radii):
    def array(name, values, components=1):
        text = " ".join(repr(float(v)) for v in np.ravel(values))
        named = f' Name="{name}"' if name else ""
        return (f'<DataArray type="Float64"{named} NumberOfComponents="{components}" format="ascii">'
                f'{text}</DataArray>')
    n = len(radii)
    ints = lambda name, values: (f'<DataArray type="Int64" Name="{name}" format="ascii">'  # noqa: E731
                                 + " ".join(str(v) for v in values) + "</DataArray>")
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">'
                f'<UnstructuredGrid><Piece NumberOfPoints="{n}" NumberOfCells="{n}"><PointData>'
                + array("radius_m", radii) + "</PointData><Points>" + array(None, points, 3) + "</Points><Cells>"
                + ints("connectivity", range(n)) + ints("offsets", range(1, n + 1))
                + '<DataArray type="UInt8" Name="types" format="ascii">' + " ".join(["1"] * n) + "</DataArray>"
                + "</Cells></Piece></UnstructuredGrid></VTKFile>\n")


STAGES = (("fill", 0.0), ("rest", 1.0), ("strike", 2.0), ("settle", 2.5), ("tap", 3.0), ("tapped_rest", 5.0),
          ("unextended", 5.2), ("strike_tapped", 6.0), ("tapped", 6.5), (None, 7.5))  # name, start [s]


LOOSE = lattice(2 * A, [(0.0, A), (0.0, A)], within=CORE - A, layers=LAYERS, quadrant=True)  # (each sphere twice)
PAIRS_LATTICE = lattice(CELL, [(0.0, BIG), (APART, SMALL)])
# (crowded: 20 spheres of 0.1 mm at one centre in the region, beside a sphere of A elsewhere)
CROWD = (np.vstack([np.tile([0.0, 0.0, 0.02], (20, 1)), [[0.01, 0.0, 0.02]]]), np.array([1e-4] * 20 + [A]))


END = 7.5 + 5e-7  # the last frame's time: past the run's recorded end by rounding


def make(name, interrupted=False, frame_times=(0.5, 1.5, 2.8, 3.0, 4.0, 5.5, END, 7.501, 9.0),
         height=f"{HEIGHT * 1e3:g} mm", crowded=False, loose_at=2.8):
    """A run with STAGES; the frames at LOOSE_AT (the equal spheres, in settle) and END (the
    pairs, the run's last; or the crowd) are the ones to read, the others (3.0 s the taps' start,
    5.5 s in unextended, 7.501 and 9.0 s past the end) hold one sphere far above. particles.pvd
    lists them from the last to the first."""
    run = os.path.join(work, name)
    os.makedirs(os.path.join(run, "frames"))
    summary = {"interrupted": interrupted, "failed": None,
               "parameters": {"diameter": f"{2 * RADIUS * 1e3:g} mm", "height": height,
                              "kernel_density": f"{DENSITY:g} kg/m3"},
               "stages": [{"name": n, "start_s": t, "end_s": e} for (n, t), (_, e) in zip(STAGES, STAGES[1:])]}
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump(summary, f)
    far = (np.array([[0.0, 0.0, 1.0]]), np.array([A]))  # (one sphere far above: the wrong frame reads 0)
    pvd = []
    for i, t in enumerate(frame_times):
        points, radii = {loose_at: LOOSE, END: CROWD if crowded else PAIRS_LATTICE}.get(t, far)
        vtu(os.path.join(run, "frames", f"particles_{i:05d}.vtu"), points, radii)
        pvd.append(f'<DataSet timestep="{t}" group="" part="0" file="particles_{i:05d}.vtu"/>')
    with open(os.path.join(run, "frames", "particles.pvd"), "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1"><Collection>'
                + "".join(reversed(pvd)) + "</Collection></VTKFile>\n")
    return run


def run(*args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


good = make("tap-good")
out_csv = os.path.join(work, "packing.csv")
r = run("--points", "100000", "--core", "15 mm,20mm", "--margin", "8 mm", "--csv", out_csv, good)
if r.returncode != 0:
    failures.append("a finished run: " + r.stderr)
else:
    rows = list(csv.DictReader(open(out_csv)))
    got = [(x["state"], float(x["time"]), x["stage"], x["region"], float(x["radius"])) for x in rows]
    want = [(state, t, stage, region, radius) for state, t, stage in (("loose", 2.8, "settle"),
                                                                     ("tapped", round(END, 4), "tapped"))
            for region, radius in (("core", CORE), ("core", 0.020), ("whole", RADIUS))]
    if got != want:
        failures.append(f"the rows' states, frames, regions: {got}, not {want}")
    volume = len(LOOSE[1]) / 2 * 4 / 3 * math.pi * A ** 3  # (the equal spheres', once each)
    for x in rows:
        f, se = float(x["solid_fraction"]), float(x["standard_error"])
        region = math.pi * float(x["radius"]) ** 2 * (HEIGHT - 2 * MARGIN)
        # (sampling: 4 standard errors; the pairs' lattice cut by the region's faces: 0.005)
        exact, cut = (volume / region, 0.0) if x["state"] == "loose" else (PAIRS, 0.005)
        if abs(f - exact) > 4 * se + cut:
            failures.append(f"{x['state']} {x['region']}: solid fraction {f}, not {exact:.4f}")
        if abs(se - math.sqrt(f * (1 - f) / 100000)) > 1e-5 or abs(float(x["bulk_density"]) - f * DENSITY) > 0.01:
            failures.append(f"{x['state']} {x['region']}: standard error {se} or density {x['bulk_density']}")
    if "| tap-good | tapped | 7.50 | tapped | whole | 31.75 |" not in r.stdout:
        failures.append(f"the printed table:\n{r.stdout}")

# --update: the other cases' rows stay in their places; without it only the cases given.
other = make("tap-other")
r1 = run("--points", "1000", "--csv", out_csv, "--update", other)
kept = [x for x in csv.DictReader(open(out_csv)) if x["case"] == "tap-other"]
r2 = run("--points", "1000", "--csv", out_csv, "--update", good)
cases = [x["case"] for x in csv.DictReader(open(out_csv))]
if r1.returncode or r2.returncode or cases != ["tap-good"] * 6 + ["tap-other"] * 6 \
        or [x for x in csv.DictReader(open(out_csv)) if x["case"] == "tap-other"] != kept:
    failures.append(f"--update: cases {cases}, {r1.stderr}{r2.stderr}")
if [f for f in os.listdir(work) if f.endswith(".tmp")]:
    failures.append("a temporary file left behind")
open(out_csv, "w").write("case,when\n")
r = run("--points", "1000", "--csv", out_csv, "--update", good)
if r.returncode == 0 or f"{os.path.basename(script)}: " not in r.stderr \
        or "does not start with the header case,state" not in r.stderr:
    failures.append(f"--update onto a file of another header: exit {r.returncode}, {r.stderr}")
r = run("--update", good)
if r.returncode == 0 or "--update needs --csv" not in r.stderr:
    failures.append(f"--update without --csv: exit {r.returncode}, {r.stderr}")
# A frame on a stage's start belongs to that stage (loose at 2.5 s: settle, not strike).
r = run("--points", "1000", make("tap-boundary", frame_times=(2.5, END), loose_at=2.5))
if "| tap-boundary | loose | 2.50 | settle | core |" not in r.stdout:
    failures.append(f"a frame on a stage's start: {r.stdout}{r.stderr}")
run("--points", "1000", "--csv", out_csv, other)
if {x["case"] for x in csv.DictReader(open(out_csv))} != {"tap-other"}:
    failures.append("without --update only the cases given")

for name, kw, args, words in (
        ("tap-interrupted", {"interrupted": True}, (), "has not finished"),
        ("tap-no-frame", {"frame_times": (0.5, 3.0, 4.0, 7.5)}, (), "no particle frame from the stage rest to tap"),
        ("tap-no-tapped-frame", {"frame_times": (2.8, 4.0, 9.0)}, (),
         "no particle frame from the stage tapped_rest to the end"),
        ("tap-crowd", {"crowded": True}, (), "more than 16 element centres lie within 1.000 mm of a point"),
        ("tap-negative", {}, ("--margin=-1mm",), "expected radii above 0 and a margin of 0 or more"),
        ("tap-unit", {"height": "40 furlongs"}, (), "height: cannot read the quantity '40 furlongs'"),
        ("tap-wide", {}, ("--core", "40mm"), "the core (40 mm) or the margins (10 mm) do not fit")):
    r = run(*args, make(name, **kw))
    if r.returncode == 0 or words not in r.stderr + r.stdout:
        failures.append(f"{name}: exit {r.returncode}, expected '{words}' in: {r.stderr}{r.stdout}")
bare = make("tap-no-frames")
shutil.rmtree(os.path.join(bare, "frames"))
r = run(bare)
if r.returncode == 0 or "no frames" not in r.stderr or "Traceback" in r.stderr:
    failures.append(f"a run without frames: exit {r.returncode}, {r.stderr}")

for f in failures:
    print("FAIL:", f)
print(f"tap packing check: {len(failures)} failed")
sys.exit(1 if failures else 0)
