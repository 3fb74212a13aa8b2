#!/usr/bin/env bash
# Runs two bushel builds on the same small scenarios and checks that their outputs are the
# same, bit for bit: for a refactoring that must not change what a run computes or writes.
#   same_outputs.sh BUSHEL_A BUSHEL_B [WORK_DIR]
# Compared, per case: the exit status, stdout and stderr; summary.json as text, except the
# values of "wall_time_s", "particle_steps_per_s" (wall time) and "engine": "commit",
# "uncommitted_changes" and "builds" (the build); timeseries.csv; every file under frames/;
# checkpoint.bin section by section: equal except the wall-clock double of section "run",
# the build names (section "build", and each build name in section "run"), the checksums of
# the sections, and the padding bytes inside the structs that section "engine" holds whole for
# each part (MotionSegment, ServoState: uninitialised memory, which differs between two runs of
# one build). Every run uses one thread (OMP_NUM_THREADS=1).
# The cases: tests/cli/same_outputs/press.yaml (clumps; region sensors, one following a part
# and one with its own volume; heap, flow and part sensors with a pressure; frames; a skipped
# stage; stable, reached, servo_held and factories_done conditions; results) run whole, stopped
# at 90 ms and continued with --restart by each build and across the builds; the same failing a
# guard; scenarios/cup-pour.yaml reduced with --set, with --json; scenarios/calibration-cup.yaml
# reduced (spheres, 3 g: a funnel, a gate turned open, a stable flow, a strike by a servo);
# `bushel validate`, of a scenario and of one it refuses.
set -euo pipefail
a="$(realpath "$1")" b="$(realpath "$2")"
here="$(cd "$(dirname "$0")" && pwd)"
src="$(cd "$here/../.." && pwd)"
work="${3:-$(mktemp -d)}"
rm -rf "$work/A" "$work/B" && mkdir -p "$work/A" "$work/B"
export OMP_NUM_THREADS=1
press="$here/same_outputs/press.yaml"
cup="$src/scenarios/cup-pour.yaml"
calibration="$src/scenarios/calibration-cup.yaml"
calibration_sets=(--set parameters.mass=3g --set parameters.model=1s)
cup_sets=(--set parameters.mass=5g --set parameters.cup_radius=15mm --set parameters.pour_radius=12mm
          --set parameters.measured_height=5mm --set parameters.frame_interval=40ms)
failures=0

# run NAME BUSHEL_SIDE ARGS...: runs in $work/SIDE with stdout, stderr and status kept as NAME.*
run() {
  local name="$1" side="$2" bin
  shift 2
  bin="$a" && [ "$side" = B ] && bin="$b"
  (cd "$work/$side" && set +e && "$bin" "$@" > "$name.out" 2> "$name.err"; echo $? > "$name.rc")
}
both() { run "$1" A "${@:2}" && run "$1" B "${@:2}"; }

compare() {  # compare LEFT RIGHT WHAT: files or folders under $work
  if python3 "$here/same_outputs_compare.py" "$1" "$2"; then
    echo "same: $3"
  else
    echo "DIFFERENT: $3"
    failures=$((failures + 1))
  fi
}
compare_case() {  # compare_case NAME [FOLDER]: its status, stdout, stderr and output folder
  local name="$1" dir="${2:-}"
  for x in rc out err; do compare "$work/A/$name.$x" "$work/B/$name.$x" "$name.$x"; done
  [ -z "$dir" ] || compare "$work/A/$dir" "$work/B/$dir" "$dir/"
}

# a whole run, with its progress output on stderr (not a terminal: stage ends and results)
both press run "$press" --out press
compare_case press press
# stopped at 90 ms (a checkpoint and an interrupted summary), then continued by each build
both stop run "$press" --out stop --quiet --stop-at 90ms
compare_case stop stop
cp -r "$work/A/stop" "$work/A/cross" && cp -r "$work/B/stop" "$work/B/cross"
both restart run --restart stop
compare_case restart stop
# continued by the other build: the checkpoint format and state are the same both ways
run cross A run --restart cross --quiet
run cross B run --restart cross --quiet
for f in timeseries.csv frames; do
  compare "$work/A/cross/$f" "$work/B/stop/$f" "A's checkpoint continued by B: $f"
  compare "$work/B/cross/$f" "$work/A/stop/$f" "B's checkpoint continued by A: $f"
done
# a run that a guard stops (exit status 3, summary marked failed, checkpoint)
both failed run "$press" --out failed --quiet --set parameters.max_speed=0.35m/s
compare_case failed failed
# the README's cup, reduced, with --json on stdout
both cup run "$cup" --out cup --quiet --json "${cup_sets[@]}"
compare_case cup cup
# the calibration cup, reduced: a funnel, a gate turned open, a stable flow, a strike by a servo
both calibration run "$calibration" --out calibration --quiet "${calibration_sets[@]}"
compare_case calibration calibration
# a scenario described, and one refused
both validate validate "$press"
compare_case validate
both invalid validate "$press" --set stages.1.until.stable.value=sample.mas
compare_case invalid

if [ "$failures" -ne 0 ]; then
  echo "same_outputs: $failures difference(s); the outputs are in $work"
  exit 1
fi
echo "same_outputs: all the same"
