#!/usr/bin/env python3
"""validation/cup_table.py, the full-size cup's table, on the committed summaries of finished
cases and on made-up states of small-5s: every row has the header's 15 cells, kept results are
read before run folders, a case without a summary is "not started", or "running or stopped"
and "parked" at the time its time series has reached, an interrupted case does not count as
finished, the line per model says whether large > medium > small holds once (and only once)
every fraction has finished, and --readme puts the table between a README's markers and
nowhere else.

usage: cup_table_check.py CUP_TABLE_PY KEPT REFERENCES WORKDIR
"""
import copy
import json
import lzma
import os
import shutil
import subprocess
import sys

script, kept_source, references, work = sys.argv[1:5]
cases = ["large-5s", "medium-5s", "small-5s", "large-1s", "medium-1s", "small-1s"]
finished_cases = [c for c in cases if c != "small-5s"]
runs, kept = os.path.join(work, "runs"), os.path.join(work, "kept")
shutil.rmtree(work, ignore_errors=True)
for c in finished_cases:
    os.makedirs(os.path.join(kept, "cup-" + c))
    shutil.copy(os.path.join(kept_source, "cup-" + c, "summary.json"), os.path.join(kept, "cup-" + c))
os.makedirs(os.path.join(runs, "cup-small-5s"))
summaries = {c: json.load(open(os.path.join(kept, "cup-" + c, "summary.json"))) for c in finished_cases}
bulk = {c: s["results"]["bulk_density"]["value"] for c, s in summaries.items()}
failures = []


def table(options=()):
    out = subprocess.run([sys.executable, script, *options, runs, kept, references] + cases,
                         check=True, capture_output=True, text=True).stdout
    rows = [l for l in out.splitlines() if l.startswith("|")]
    for r in rows:
        if r.count("|") != 16:
            failures.append(f"{r.count('|') - 1} cells, not 15: {r}")
    return {r.split("|")[1].strip(): r for r in rows[2:]}, out


def expect(condition, what, out):
    if not condition:
        failures.append(what + ":\n" + out)


def write_small_5s(folder, bulk_density, interrupted):
    s = copy.deepcopy(summaries["medium-5s"])
    s["results"]["bulk_density"]["value"] = bulk_density
    s["interrupted"] = interrupted
    with open(os.path.join(folder, "cup-small-5s", "summary.json"), "w") as f:
        json.dump(s, f)


def ladder(model, small):
    values = [bulk[f"large-{model}"], bulk[f"medium-{model}"], small]
    return ", ".join(f"{v:.1f}" for v in values) + " kg/m3"


# The committed summaries: the single-sphere model has every fraction, 5s lacks small.
rows, out = table()
expect(rows["small-5s"].endswith("| not started |"), "small-5s without a folder's files", out)
expect(f"| {bulk['large-5s']:.1f} |" in rows["large-5s"] and rows["large-5s"].endswith("| done |"),
       "large-5s's bulk density and status", out)
measured = float(rows["medium-5s"].split("|")[4])
expect(f"| {100 * (bulk['medium-5s'] - measured) / measured:+.1f} % |" in rows["medium-5s"],
       "medium-5s's difference to the lab value", out)
order_1s = "holds" if bulk["large-1s"] > bulk["medium-1s"] > bulk["small-1s"] else "does NOT hold"
expect(f"- order large > medium > small, 1s: {order_1s}: {ladder('1s', bulk['small-1s'])}" in out,
       "the 1s order line", out)
expect("- order large > medium > small, 5s: not every fraction has finished" in out, "5s unfinished", out)

# "engine": the builds' short commits, oldest first.
builds = summaries["large-1s"]["engine"]["builds"]
commits = [b.split("commit ")[1][:7] for b in builds]
expect(f"| {', '.join(commits[:-1])}, then {commits[-1]} | done |" in rows["large-1s"], "large-1s's builds", out)

# A checkpoint and no summary: running or stopped, at the time series' last row when there
# is one; a parked checkpoint beside it (its series compressed).
open(os.path.join(runs, "cup-small-5s", "checkpoint.bin"), "w").close()
rows, out = table()
expect(rows["small-5s"].endswith("| running or stopped (a checkpoint) |"), "small-5s with a checkpoint", out)
header = "stage,time,particles\n"
with open(os.path.join(runs, "cup-small-5s", "timeseries.csv"), "w") as f:
    f.write(header + "fill,0,0\nflow,8.9061,20264\n")
os.makedirs(os.path.join(kept, "cup-small-5s"))
open(os.path.join(kept, "cup-small-5s", "checkpoint.bin.xz"), "w").close()
with lzma.open(os.path.join(kept, "cup-small-5s", "timeseries.csv.xz"), "wt") as f:
    f.write(header + "flow,7.5443,20264\n")
rows, out = table()
expect(rows["small-5s"].endswith("| running or stopped at t = 8.91 s (flow); parked at t = 7.54 s (flow) |"),
       "small-5s running and parked", out)
os.rename(os.path.join(runs, "cup-small-5s"), os.path.join(work, "away"))
rows, out = table()
expect(rows["small-5s"].endswith("| parked at t = 7.54 s (flow) |"), "small-5s parked only", out)
os.rename(os.path.join(work, "away"), os.path.join(runs, "cup-small-5s"))

# --readme: the table between the markers, the rest of the file as it was.
readme = os.path.join(work, "README.md")
before, after = "# Results\n\n<!-- cup_table.py: begin -->\n", "<!-- cup_table.py: end -->\n\ntext after\n"
with open(readme, "w") as f:
    f.write(before + "an old table\n" + after)
_, out = table(["--readme", readme])
expect(open(readme).read() == before + out + after, "the table spliced into a README", open(readme).read())
with open(readme, "w") as f:
    f.write(before)
spliced = subprocess.run([sys.executable, script, "--readme", readme, runs, kept, references] + cases,
                         capture_output=True, text=True)
expect(spliced.returncode != 0 and "cup_table.py: end" in spliced.stderr and open(readme).read() == before,
       "a README without its end marker is an error and stays as it was", spliced.stderr)

# An interrupted run's summary: its status, and 5s is still unfinished.
write_small_5s(runs, 700.0, interrupted=True)
rows, out = table()
expect("| interrupted at t = " in rows["small-5s"], "small-5s interrupted", out)
expect("5s: not every fraction has finished" in out, "an interrupted case counts as unfinished", out)

# Finished below medium: holds; a kept summary is read before the run folder's.
write_small_5s(runs, 700.0, interrupted=False)
rows, out = table()
expect(f"5s: holds: {ladder('5s', 700.0)}" in out, "order holds with small at 700", out)
write_small_5s(kept, bulk["medium-5s"] + 1.0, interrupted=False)
rows, out = table()
expect(f"5s: does NOT hold: {ladder('5s', bulk['medium-5s'] + 1.0)}" in out,
       "order broken by a kept small-5s above medium (kept before runs)", out)

if failures:
    print("FAILED:\n" + "\n".join(failures))
    sys.exit(1)
print("cup table: rows, statuses and order lines as expected")
