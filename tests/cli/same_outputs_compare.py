#!/usr/bin/env python3
"""Compares two run outputs (files or folders) for tests/cli/same_outputs.sh; exit 1 if they differ.

summary.json and JSON on stdout (*.out): as text, with the values of the wall-time and build
keys masked (see same_outputs.sh). checkpoint.bin: section by section, the wall clock, the
build names and the padding inside the parts' records masked. stdout and stderr: the wall-time figures of the run's last line masked.
Anything else: bytes.
"""
import os
import re
import struct
import sys

WALL_KEYS = ("wall_time_s", "particle_steps_per_s")
BUILD_KEYS = ("commit", "uncommitted_changes")


def mask_summary(text):
    text = re.sub(r'("(?:%s)": )[^,\n]*' % "|".join(WALL_KEYS + BUILD_KEYS), r"\1#", text)
    # "builds": [ ... ] (one build name a line)
    return re.sub(r'("builds": \[)[^\]]*(\])', r"\1#\2", text)


def mask_text(text):
    # "20375 steps, 0.162 s simulated, 1.8 s wall, 7.56e+05 particle-steps/s"
    return re.sub(r"s simulated, \S+ s wall, \S+ particle-steps/s", "s simulated, # s wall, # particle-steps/s", text)


def read_string(b, at):
    (n,) = struct.unpack_from("<Q", b, at)
    return b[at + 8 : at + 8 + n], at + 8 + n


def sections(b):
    """The magic line, then {name: body} of a checkpoint (format 3: each section a name, a
    length, a checksum and its bytes; format 4: a version after the name)."""
    magic, at = read_string(b, 0)
    versioned = not magic.endswith(b" 3")
    out = {}
    while at < len(b):
        name, at = read_string(b, at)
        at += 4 if versioned else 0
        length, _sum = struct.unpack_from("<QQ", b, at)
        at += 16
        out[name.decode()] = b[at : at + length]
        at += length
    return magic, out


def run_wall_offset(run):
    """Where the wall-clock double lies in section 'run' (after the Position's members)."""
    at = 8 + 1 + 8 + 8  # stage, stage_started, t0, steps0
    for _ in range(2):  # the stable condition's sample times and values
        (n,) = struct.unpack_from("<Q", run, at)
        at += 8 + 8 * n
    return at + 3 * 8  # next_row, next_frame, particle_steps


def mask_part_padding(engine):
    """Section "engine.parts" ("engine" in format 3) with the padding bytes of its parts'
    records zeroed: it begins with
    Simulation::save_state's parts, each a Pose (56 bytes), enabled (1), its MotionSegments
    (a count, then 152 bytes each: Kind, 4 bytes of padding, doubles), has_servo (1), a
    ServoSpec (88), force, torque (24 each), a Twist (48), a ServoState (measured_force,
    speed, held, 7 bytes of padding, held_since: 32), touches and moved (8 each). Builds
    since the padding became named zero fields write zeros there; older ones left it
    uninitialised."""
    b = bytearray(engine)
    (parts,) = struct.unpack_from("<Q", b, 0)
    at = 8
    for _ in range(parts):
        at += 56 + 1
        (n,) = struct.unpack_from("<Q", b, at)
        at += 8
        for _ in range(n):
            b[at + 4 : at + 8] = bytes(4)
            at += 152
        at += 1 + 88 + 24 + 24 + 48
        b[at + 17 : at + 24] = bytes(7)
        at += 32 + 8 + 8
    return bytes(b)


def masked_checkpoint(path):
    """Its magic line and sections with the wall clock, the build names and the padding masked."""
    with open(path, "rb") as f:
        magic, s = sections(f.read())
    parts = "engine" if "engine" in s else "engine.parts"  # (formats 3 and 4)
    s[parts] = mask_part_padding(s[parts])
    build, _ = read_string(s["build"], 0)
    run = bytearray(s["run"])
    w = run_wall_offset(run)
    run[w : w + 8] = b"\0" * 8
    run = bytes(run).replace(struct.pack("<Q", len(build)) + build, b"<build>")
    s["run"] = run
    s["build"] = b"<build>"
    return magic, s


def same(left, right):
    name = os.path.basename(left)
    if os.path.isdir(left) or os.path.isdir(right):
        if not (os.path.isdir(left) and os.path.isdir(right)):
            print(f"  {left}: a folder on one side only")
            return False
        names = sorted(set(os.listdir(left)) | set(os.listdir(right)))
        return all([same(os.path.join(left, n), os.path.join(right, n)) for n in names])
    if not (os.path.exists(left) and os.path.exists(right)):
        print(f"  {name}: on one side only ({left if os.path.exists(left) else right})")
        return False
    if name == "checkpoint.bin":
        a, b = masked_checkpoint(left), masked_checkpoint(right)
        if a[0] != b[0] or list(a[1]) != list(b[1]):
            print(f"  {left}: another magic line or other sections")
            return False
        ok = True
        for k in a[1]:
            if a[1][k] != b[1][k]:
                print(f"  {left}: section '{k}' differs")
                ok = False
        return ok
    with open(left, "rb") as f:
        x = f.read()
    with open(right, "rb") as f:
        y = f.read()
    if name == "summary.json" or name.endswith(".out"):
        x, y = (mask_summary(mask_text(v.decode("utf-8", "replace"))) for v in (x, y))
    elif name.endswith(".err"):
        x, y = (mask_text(v.decode("utf-8", "replace")) for v in (x, y))
    if x != y:
        print(f"  {left} and {right} differ")
        return False
    return True


if __name__ == "__main__":
    sys.exit(0 if same(sys.argv[1], sys.argv[2]) else 1)
