"""The frames of the reduced cup-pour run in both encodings (binary: BIN_DIR, ascii: ASCII_DIR):
the same final state (frames never change a run), so the same particles in every frame, and
the binary frames at least 4 times smaller than the ASCII ones (the files of particles and
geometry together, summed over the frames).

usage: frame_size_check.py BIN_DIR ASCII_DIR"""
import json
import os
import re
import sys

binary, ascii_ = sys.argv[1], sys.argv[2]
summaries = [json.load(open(d + "/summary.json")) for d in (binary, ascii_)]
assert summaries[0]["final_state_hash"] == summaries[1]["final_state_hash"], summaries


def frame_files(run):
    """The frames' files as the collections name them (a geometry file named twice counts once)."""
    names = []
    for pvd in ("particles.pvd", "geometry.pvd"):
        text = open(os.path.join(run, "frames", pvd)).read()
        names += sorted(set(re.findall(r'file="([^"]+)"', text)))
    return names


sizes = [sum(os.path.getsize(os.path.join(d, "frames", f)) for f in frame_files(d)) for d in (binary, ascii_)]
ratio = sizes[1] / sizes[0]
print(f"frames: binary {sizes[0]} B, ascii {sizes[1]} B, ratio {ratio:.2f}")
assert ratio >= 4.0, ratio
print("frame size check passed")
