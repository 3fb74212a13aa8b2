"""Pictures of a run's frames with matplotlib: the vertical section y = 0 of a frame, the walls
as lines and every sphere the plane cuts as a disc (its section), coloured by particle type.
`bushel report` draws each run's last frame this way; scripts/section-png.py draws any frame.

    bushel.pictures.section_png("runs/cup/frames", "cup.png", index=-1, title="the cup at rest")
"""
import os

import numpy as np

from .frames import read_pvd, read_vtu

_COLOURS = ["#c8963e", "#8c5a2b", "#e0c27a", "#6b8e23", "#4f6d8f", "#a0522d"]


def section(frames, index=-1):
    """Frame `index` of the folder `frames` (particles.pvd, geometry.pvd) cut by the plane y = 0:
    (discs [(x, z, r)] [m], their type indices, wall segments [((x, z), (x, z))] [m], type names,
    the frame's time [s])."""
    particles = read_pvd(os.path.join(frames, "particles.pvd"))
    if not particles:
        raise FileNotFoundError(f"{frames}: no frames in particles.pvd")
    time, path = particles[index]
    p = read_vtu(path)
    pts, r = p.points, p.point_data["radius_m"]
    kind = np.asarray(p.point_data.get("type", np.zeros(len(r))), dtype=int)
    cut = np.abs(pts[:, 1]) < r  # spheres the plane cuts
    discs = [(x, z, np.sqrt(rr * rr - y * y)) for (x, y, z), rr in zip(pts[cut], r[cut])]
    geometry = read_pvd(os.path.join(frames, "geometry.pvd"))
    # the geometry written last at or before the frame's time (it is written only when it moves)
    at = [g for g in geometry if g[0] <= time + 1e-12] or geometry[:1]
    segments = _wall_segments(read_vtu(at[-1][1])) if at else []
    return discs, kind[cut], segments, p.field_data.get("type_names", []), time


def _wall_segments(g):
    """The segments where the triangles of `g` cross y = 0, in (x, z)."""
    v, segments = g.points, []
    for t in g.connectivity.reshape(-1, 3):
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
    return segments


def draw_section(ax, frames, index=-1):
    """Draws the section of frame `index` into the matplotlib axes `ax` in mm, with a legend of
    the particle types; returns (discs, segments) counts and the frame's time [s]."""
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle, Patch
    discs, kind, segments, names, time = section(frames, index)
    mm = 1e3
    ax.add_collection(LineCollection([[(x * mm, z * mm) for x, z in s] for s in segments], colors="#333333",
                                     linewidths=1.2))
    ax.add_collection(PatchCollection([Circle((x * mm, z * mm), rr * mm) for x, z, rr in discs],
                                      facecolors=[_COLOURS[k % len(_COLOURS)] for k in kind], edgecolors="none"))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")
    shown = sorted(set(int(k) for k in kind))
    if names and shown:
        ax.legend(handles=[Patch(color=_COLOURS[k % len(_COLOURS)], label=names[k]) for k in shown], fontsize=7,
                  loc="upper left", bbox_to_anchor=(1.01, 1))
    return len(discs), len(segments), time


def section_png(frames, out, index=-1, title="", width=5.0, dpi=110):
    """The section of frame `index` as a PNG file `out` (written whole or not at all), `width`
    inches wide, titled `title` and the frame's time; returns (discs, segments) counts."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(width, width * 1.3))
    discs, segments, time = draw_section(ax, frames, index)
    ax.set_title(f"{title}, t = {time:.4g} s" if title else f"t = {time:.4g} s", fontsize=10)
    fig.savefig(out + ".tmp.png", dpi=dpi, bbox_inches="tight")
    os.replace(out + ".tmp.png", out)
    plt.close(fig)
    return discs, segments
