"""The Python API against the command line: a reduced cup-pour run from Python gives the same
final state as `bushel run` of the same scenario and overrides; a run stopped by the progress
callback, or by Ctrl-C, and resumed ends on that state too; a scenario given as a dict runs; the outputs read
back (results, time series with units, frames as numpy arrays, matching the summary); bad
input raises InputError naming the key.

usage: test_run.py BUSHEL_CLI SCENARIO WORK_DIR"""
import json
import os
import shutil
import subprocess
import sys

import numpy as np

import bushel

cli, scenario, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
sets = {"parameters.mass": "5g", "parameters.cup_radius": "15mm", "parameters.pour_radius": "12mm",
        "parameters.measured_height": "5mm"}
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAILED:", what)


args = [cli, "run", scenario, "--out", f"{work}/cli", "--quiet", "--threads", "1"]
for k, v in sets.items():
    args += ["--set", f"{k}={v}"]
subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
cli_hash = json.load(open(f"{work}/cli/summary.json"))["final_state_hash"]

# The same run from Python, with 2 threads: the same bits.
seen = []
run = bushel.run(scenario, f"{work}/py", set=sets, threads=2, progress=lambda p: seen.append(p["time_s"]))
check(run.summary["final_state_hash"] == cli_hash, "Python and CLI runs end on the same state")
check(len(seen) > 100 and seen == sorted(seen), f"progress at every check ({len(seen)} calls)")
density = run.results["bulk_density"]
check(density.unit == "kg/m3" and 600 < density.value < 900, f"bulk density {density}")

# Stopped by the callback half way, then continued: the same final state.
half = seen[len(seen) // 2]
stopped = bushel.run(scenario, f"{work}/stopped", set=sets, progress=lambda p: p["time_s"] >= half)
check(stopped.interrupted, "a callback returning True stops the run")
check(abs(stopped.simulated_time - half) < 1e-9, f"stopped at {stopped.simulated_time}, asked {half}")
resumed = bushel.resume(f"{work}/stopped")
check(resumed.summary["final_state_hash"] == cli_hash, "stopped and resumed: the same final state")

# An exception in the callback stops the run (with a checkpoint) and is raised.
try:
    bushel.run(scenario, f"{work}/raised", set=sets, progress=lambda p: 1 / 0 if p["time_s"] > 0.01 else None)
    check(False, "the callback's exception is raised")
except ZeroDivisionError:
    check(os.path.exists(f"{work}/raised/checkpoint.bin"), "a checkpoint where the callback raised")

# Ctrl-C (SIGINT, sent here from the callback) stops the run with a checkpoint and raises
# KeyboardInterrupt; resumed, it ends on the same state.
import signal  # noqa: E402
try:
    bushel.run(scenario, f"{work}/ctrl_c", set=sets,
               progress=lambda p: os.kill(os.getpid(), signal.SIGINT) if p["time_s"] >= half else None)
    check(False, "Ctrl-C raises KeyboardInterrupt")
except KeyboardInterrupt:
    check(bushel.open_run(f"{work}/ctrl_c").interrupted, "Ctrl-C leaves an interrupted run")
    check(bushel.resume(f"{work}/ctrl_c").summary["final_state_hash"] == cli_hash, "Ctrl-C, resumed: the same state")

# The time series and its units, against the summary.
ts, units = run.timeseries, run.units
check(units["cup.bulk_density"] == "kg/m3" and units["time"] == "s", f"units {units}")
check(ts["stage"][-1] == "end" and abs(ts["time"][-1] - run.simulated_time) < 1e-6, "the last row is the end")
check(abs(ts["cup.bulk_density"][-1] - run.stages[-1]["values"]["cup.bulk_density"]) < 1e-3,
      "the last row's density is the last stage's")

# The last frame: every element of every particle, ids and types as integers, types named.
frame = run.particles(-1)
n = run.summary["final"]["particles"]
check(frame.points.shape == (5 * n, 3), f"frame points {frame.points.shape}, particles {n}")
check(frame.point_data["body_id"].dtype == np.uint32 and frame.point_data["type"].dtype == np.int32, "integer ids")
check(len(np.unique(frame.point_data["body_id"])) == n, "five elements per body")
check(frame.field_data["type_names"] == ["large", "medium", "small"], f"type names {frame.field_data}")
check(frame.point_data["velocity_m_s"].shape == (5 * n, 3), "velocities")
check(len(run.frames) == len(bushel.read_pvd(f"{work}/py/frames/geometry.pvd")), "a geometry entry per frame")
check(len(run.geometry(-1).cell_types) > 0, "the geometry's triangles")
ascii_frame = bushel.read_vtu(f"{work}/cli/frames/" + os.path.basename(run.frames[-1][1]))
check(np.array_equal(ascii_frame.points, frame.points), "the CLI's frame holds the same positions")

# A scenario as a dict (JSON, which the YAML reader takes): validates and runs.
import yaml  # noqa: E402 (Debian's python3-yaml, for the test only)
doc = yaml.safe_load(open(scenario))
for k, v in sets.items():
    doc["parameters"][k.split(".")[1]] = v
info = bushel.validate(doc)
check(info["stages"] == [s["name"] for s in run.stages], f"stages {info['stages']}")
from_dict = bushel.run(doc, f"{work}/dict", threads=1)
check(from_dict.summary["final_state_hash"] == cli_hash, "a dict scenario runs the same")

# Bad input: InputError (a ValueError) naming what is wrong.
for bad, words in ((lambda: bushel.validate(scenario, set={"parameters.mass": "5 mm"}), "parameters.mass"),
                   (lambda: bushel.validate({"parameters": {}}), "is missing"),
                   (lambda: bushel.shape_factors("5 kg", 3e-3, 2e-3), "length"),
                   (lambda: bushel.run(scenario, f"{work}/cli", set=sets), "--out")):
    try:
        bad()
        check(False, f"raises: {words}")
    except ValueError as e:
        check(words in str(e), f"'{words}' in: {e}")
print(f"{'0 failed' if not failures else str(len(failures)) + ' failed'}")
sys.exit(1 if failures else 0)
