#!/usr/bin/env python3
"""Per-phase timing of a LIGGGHTS log of bench/liggghts/pour.in (or clump.in, clump_dense.in),
as CSV lines in the format of bench_pour: code,particle,n,threads,phase,steps,seconds,
particle_steps_per_s,contacts. SPHERES is the number of spheres a particle has (5 for the
multisphere kernels: LIGGGHTS counts spheres as atoms), so that n and the rate count particles.
usage: summarize.py LOG PARTICLE [SPHERES]"""
import re
import sys

log, particle = sys.argv[1], sys.argv[2]
spheres = int(sys.argv[3]) if len(sys.argv) > 3 else 1
text = open(log).read()
parts = re.split(r"\nBENCH_PHASE (\w+)", text)
for phase, body in zip(parts[1::2], parts[2::2]):
    m = re.search(r"Loop time of ([\d.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", body)
    if m:
        seconds, procs, steps = float(m.group(1)), int(m.group(2)), int(m.group(3))
        atoms = int(m.group(4)) // spheres
        print("liggghts,%s,%d,%d,%s,%d,%.3f,%.4e," % (particle, atoms, procs, phase, steps, seconds,
                                                     atoms * steps / seconds))
