#!/usr/bin/env bash
# The dt-independence study of the critical time step (docs/physics.md section 3): the
# reduced cup (scenarios/cup-pour.yaml, 50 g of the 5-sphere size mix) and the settled clump
# bed (validation/time-step/clump-bed.yaml, 1,000 large_5s) at several fractions of the
# critical step, with several seeds each. Per scene and fraction: the bulk density and the
# coordination number in the lower part of the packing and the heap angle at the end of
# settling, mean and seed-to-seed standard deviation, and the wall time. A fraction passes
# where no mean lies further from the smallest fraction's than the seed-to-seed scatter
# allows a difference of two means: 2 sqrt(1/n + 1/n_ref) times the standard deviation over
# seeds (pooled over the fractions), 1.63 of it with 3 seeds a side.
#
# usage: validation/time-step.sh [FRACTIONS] [SEEDS] [JOBS]
#        (defaults "0.15 0.3 0.45 0.6 0.8" "1 2 3" 2: runs at a time, one thread each)
# Writes validation/results/time-step/ (each run's summary.json and runs.csv, one line a run)
# and prints the tables for validation/results/time-step.md. Finished runs
# are kept, so that an interrupted study continues where it stopped.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
out=validation/results/time-step

# One run: SCENE FRACTION SEED (a finished run is kept, so that the study can be continued).
if [ "${1:-}" = --one ]; then
  scene=$2 f=$3 seed=$4 dir="$out/$2-$3-$4"
  case $scene in
    cup) args=(scenarios/cup-pour.yaml --set parameters.mass=50g --set parameters.measured_height=10mm
               --set parameters.frame_interval=10s) ;;
    bed) args=(validation/time-step/clump-bed.yaml) ;;
  esac
  if [ -f "$dir/summary.json" ] && grep -q '"interrupted": false' "$dir/summary.json"; then exit 0; fi
  build/release/bin/bushel run "${args[@]}" --out "$dir" --overwrite --quiet --threads 1 \
    --set "simulation.time_step=$f critical" --set "simulation.seed=$seed" >/dev/null
  rm -rf "$dir/checkpoint.bin" "$dir/frames" "$dir/timeseries.csv"  # (results/ keeps summaries)
  echo "done: $scene, fraction $f, seed $seed" >&2
  exit 0
fi

FRACTIONS=${1:-"0.15 0.3 0.45 0.6 0.8"}; SEEDS=${2:-"1 2 3"}; JOBS=${3:-2}
cmake --preset release >/dev/null && cmake --build --preset release --target bushel >/dev/null
mkdir -p "$out"
for scene in cup bed; do
  for f in $FRACTIONS; do
    for s in $SEEDS; do echo "$scene $f $s"; done
  done
done | xargs -P "$JOBS" -L 1 "$0" --one || echo "some runs failed: the table has the others" >&2

python3 - "$out" <<'PY'
import glob, json, math, os, statistics, sys
out = sys.argv[1]
sensor = {"cup": "cup", "bed": "bed"}
rows = []
for path in sorted(glob.glob(os.path.join(out, "*", "summary.json"))):
    scene, f, seed = os.path.basename(os.path.dirname(path)).split("-")
    s = json.load(open(path))
    end = s["stages"][-1]["values"]
    rows.append(dict(scene=scene, fraction=float(f), seed=int(seed), dt_us=s["dt_s"] * 1e6,
                     critical_us=s["critical_step_s"] * 1e6, rayleigh_us=s["rayleigh_step_s"] * 1e6,
                     bulk_density=end[sensor[scene] + ".bulk_density"],
                     coordination=end[sensor[scene] + ".coordination"], heap_angle=end["heap.angle"],
                     wall_s=s["wall_time_s"], steps=s["steps"]))
keys = ["bulk_density", "coordination", "heap_angle"]
with open(os.path.join(out, "runs.csv"), "w") as f:
    cols = list(rows[0].keys())
    f.write(",".join(cols) + "\n")
    for r in rows:
        f.write(",".join(str(r[c]) for c in cols) + "\n")
for scene in ["cup", "bed"]:
    mine = [r for r in rows if r["scene"] == scene]
    if not mine:
        continue
    fr = sorted({r["fraction"] for r in mine})
    stat = {}
    for x in fr:
        g = [r for r in mine if r["fraction"] == x]
        stat[x] = {k: (statistics.mean(r[k] for r in g), statistics.stdev(r[k] for r in g) if len(g) > 1 else 0.0)
                   for k in keys + ["wall_s", "steps"]}
        stat[x]["n"] = len(g)
    ref = stat[fr[0]]
    # the seed-to-seed scatter: the standard deviation over seeds, pooled over the fractions
    pooled = {k: math.sqrt(statistics.mean(stat[x][k][1] ** 2 for x in fr)) for k in keys}
    print(f"\n{scene}: critical step {mine[0]['critical_us']:.3f} us, Rayleigh step {mine[0]['rayleigh_us']:.3f} us; "
          f"seed-to-seed standard deviation (pooled): bulk density {pooled['bulk_density']:.1f} kg/m3, "
          f"coordination {pooled['coordination']:.3f}, heap angle {pooled['heap_angle']:.2f} deg\n")
    print("| fraction of critical | dt [us] | seeds | bulk density [kg/m3] | coordination [-] | heap angle [deg] "
          "| wall [s] | largest shift / scatter | within scatter |")
    print("|---|---|---|---|---|---|---|---|---|")
    for x in fr:
        st = stat[x]
        shift = max(abs(st[k][0] - ref[k][0]) / pooled[k] for k in keys)
        # two standard errors of a difference of means of n and n_ref seeds
        limit = 2.0 * math.sqrt(1.0 / st["n"] + 1.0 / ref["n"])
        print(f"| {x:g} | {x * mine[0]['critical_us']:.2f} | {st['n']} | {st['bulk_density'][0]:.1f} ± {st['bulk_density'][1]:.1f} "
              f"| {st['coordination'][0]:.3f} ± {st['coordination'][1]:.3f} | {st['heap_angle'][0]:.2f} ± {st['heap_angle'][1]:.2f} "
              f"| {st['wall_s'][0]:.0f} | {shift:.2f} | {'yes' if shift <= limit else 'no'} |")
PY
