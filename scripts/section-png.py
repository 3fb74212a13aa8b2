#!/usr/bin/python3
"""A cut-away picture of a run: the vertical section y = 0 of a frame written by `bushel run`
(outputs.frames), with the equipment's walls as lines and every sphere that the plane cuts
as a disc (its section), coloured by particle type. Used for the set-up pictures in docs/.

  scripts/section-png.py RUN_DIR --frame 3 --out setup.png [--title TEXT] [--width 6]

RUN_DIR holds frames/ (particles.pvd, geometry.pvd); --frame -1 is the last. Drawn by the bushel
package (bushel.pictures, docs/python.md), from build/release/python or where it is installed.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "release", "python"))
from bushel.pictures import section_png  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--frame", type=int, default=-1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--width", type=float, default=5.0, help="inches")
    a = ap.parse_args()
    discs, segments = section_png(os.path.join(a.run, "frames"), a.out, a.frame, a.title, a.width)
    print(f"{a.out}: {discs} sphere sections, {segments} wall segments")


if __name__ == "__main__":
    main()
