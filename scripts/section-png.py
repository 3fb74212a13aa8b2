#!/usr/bin/python3
"""A cut-away picture of a run: the vertical section y = 0 of a frame written by `bushel run`
(outputs.frames), with the equipment's walls as lines and every sphere that the plane cuts
as a disc (its section), coloured by particle type. Used for the set-up pictures in docs/.

  scripts/section-png.py RUN_DIR --frame 3 --out setup.png [--title TEXT] [--width 6]

RUN_DIR holds frames/ (particles.pvd, geometry.pvd); --frame -1 is the last. The frames are
read by the bushel package (docs/python.md), from build/release/python or where it is installed.
"""
import argparse
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "release", "python"))
from bushel.frames import read_pvd, read_vtu  # noqa: E402


def section(frames, index):
    particles, geometry = read_pvd(os.path.join(frames, "particles.pvd")), read_pvd(os.path.join(frames, "geometry.pvd"))
    if not particles:
        sys.exit(f"no frames in {frames}")
    p, g = read_vtu(particles[index][1]), read_vtu(geometry[index][1])
    pts = p.points
    r = p.point_data["radius_m"]
    kind = p.point_data.get("type", np.zeros(len(r)))
    cut = np.abs(pts[:, 1]) < r  # spheres the plane y = 0 cuts
    discs = [(x, z, np.sqrt(rr * rr - y * y)) for (x, y, z), rr in zip(pts[cut], r[cut])]
    # each triangle of the walls that crosses y = 0 gives one segment
    v = g.points
    tri = g.connectivity.reshape(-1, 3)
    segments = []
    for t in tri:
        a = v[t]
        ys = a[:, 1]
        if ys.min() > 0 or ys.max() < 0:
            continue
        ends = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            if (ys[i] <= 0) != (ys[j] <= 0):
                s = ys[i] / (ys[i] - ys[j])
                q = a[i] + s * (a[j] - a[i])
                ends.append((q[0], q[2]))
        if len(ends) == 2:
            segments.append(ends)
    return discs, kind[cut], segments


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--frame", type=int, default=-1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--width", type=float, default=5.0, help="inches")
    a = ap.parse_args()
    discs, kind, segments = section(os.path.join(a.run, "frames"), a.frame)
    mm = 1e3
    colours = ["#c8963e", "#8c5a2b", "#e0c27a", "#6b8e23"]
    fig, ax = plt.subplots(figsize=(a.width, a.width * 1.3))
    ax.add_collection(LineCollection([[(x * mm, z * mm) for x, z in s] for s in segments], colors="#333333",
                                     linewidths=1.2))
    patches = [Circle((x * mm, z * mm), rr * mm) for x, z, rr in discs]
    ax.add_collection(PatchCollection(patches, facecolors=[colours[int(k) % len(colours)] for k in kind],
                                      edgecolors="none"))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")
    if a.title:
        ax.set_title(a.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(f"{a.out}: {len(discs)} sphere sections, {len(segments)} wall segments")


if __name__ == "__main__":
    main()
