#!/usr/bin/python3
"""A cut-away picture of a run: the vertical section y = 0 of a frame written by `bushel run`
(outputs.frames), with the equipment's walls as lines and every sphere that the plane cuts
as a disc (its section), coloured by particle type. Used for the set-up pictures in docs/.

  scripts/section-png.py RUN_DIR --frame 3 --out setup.png [--title TEXT] [--width 6]

RUN_DIR holds frames/ (particles_NNNNN.vtu, geometry_NNNNN.vtu); --frame -1 is the last.
"""
import argparse
import glob
import os
import re
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def arrays(path):
    """The ASCII DataArrays of a VTU file by name, and its points."""
    text = open(path).read()
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)"[^>]*format="ascii"[^>]*>(.*?)</DataArray>',
                         text, re.S):
        out[m.group(2)] = np.array(m.group(3).split(), dtype=float if m.group(1).startswith("Float") else np.int64)
    points = re.search(r"<Points>\s*<DataArray[^>]*>(.*?)</DataArray>", text, re.S)
    out["Points"] = np.array(points.group(1).split(), dtype=float)
    return out


def section(frames, index):
    particles = sorted(glob.glob(os.path.join(frames, "particles_*.vtu")))
    geometry = sorted(glob.glob(os.path.join(frames, "geometry_*.vtu")))
    if not particles:
        sys.exit(f"no frames in {frames}")
    p, g = arrays(particles[index]), arrays(geometry[index])
    pts = p["Points"].reshape(-1, 3)
    r = p["radius_m"]
    kind = p.get("type", np.zeros(len(r)))
    cut = np.abs(pts[:, 1]) < r  # spheres the plane y = 0 cuts
    discs = [(x, z, np.sqrt(rr * rr - y * y)) for (x, y, z), rr in zip(pts[cut], r[cut])]
    # each triangle of the walls that crosses y = 0 gives one segment
    v = g["Points"].reshape(-1, 3)
    tri = g["connectivity"].reshape(-1, 3)
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
