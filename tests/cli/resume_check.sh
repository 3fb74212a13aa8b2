#!/usr/bin/env bash
# validation/resume.sh: run_or_resume starts a run, continues one from its checkpoint (its
# --set overrides left out: the checkpoint holds them, and bushel refuses them with --restart)
# and keeps a finished one, and leaves a failed one alone; with ONE_BUILD=1 it starts again a
# run whose checkpoint another engine build wrote, and leaves alone one whose build this clone
# cannot compare (unless this build has uncommitted changes: then it never compares, and starts
# again); park_run, unpark_run and keep_run carry a run to another checkout (with the frame
# before a stage, PARK_FRAME_BEFORE), and run_case does all three under the run's lock.
#   resume_check.sh BUSHEL SOURCE_DIR WORK_DIR
set -euo pipefail
bushel="$1" src="$2" work="$3"
root="$src"
source "$src/validation/resume.sh"
rm -rf "$work" && mkdir -p "$work"
cup="$src/scenarios/cup-pour.yaml"
sets=(--set parameters.mass=5g --set parameters.cup_radius=15mm --set parameters.pour_radius=12mm
      --set parameters.measured_height=5mm)
fail() { echo "resume check failed: $*" >&2; exit 1; }

# interrupted: a checkpoint and an interrupted summary
run_or_resume cup "$work/run" "$cup" --quiet --stop-at 20ms "${sets[@]}" > /dev/null 2> "$work/1.txt"
grep -q "cup: starting: bushel run" "$work/1.txt" || fail "no start message: $(cat "$work/1.txt")"
grep -q '"interrupted": true' "$work/run/summary.json" || fail "the first call did not stop at 20 ms"
[ -f "$work/run/checkpoint.bin" ] || fail "no checkpoint"
# continued to the end (without --stop-at and --set: it would stop again, or be refused)
run_or_resume cup "$work/run" "$cup" --quiet "${sets[@]}" > /dev/null 2> "$work/2.txt" || fail "the restart failed: $(cat "$work/2.txt")"
grep -q "cup: continuing from its checkpoint" "$work/2.txt" || fail "no restart message: $(cat "$work/2.txt")"
grep -q '"interrupted": false' "$work/run/summary.json" || fail "the restart did not finish"
# kept
before=$(md5sum < "$work/run/summary.json")
run_or_resume cup "$work/run" "$cup" --quiet "${sets[@]}" 2> "$work/3.txt"
grep -q "cup: finished before, kept" "$work/3.txt" || fail "no kept message: $(cat "$work/3.txt")"
[ "$(md5sum < "$work/run/summary.json")" = "$before" ] || fail "a finished run was run again"
# a run that another script is running now is left to it ($run_busy), then run once it is free
exec {held}> "$work/next.lock"
flock -n "$held" || fail "could not take the lock"
status=0
run_or_resume next "$work/next" "$cup" --quiet "${sets[@]}" > /dev/null 2> "$work/4.txt" || status=$?
[ "$status" -eq "$run_busy" ] || fail "a run held by another script returned $status, not $run_busy"
grep -q "next: another script is running it now" "$work/4.txt" || fail "no busy message: $(cat "$work/4.txt")"
[ ! -e "$work/next" ] || fail "a run held by another script was started"
exec {held}>&-
run_or_resume next "$work/next" "$cup" --quiet --stop-at 5ms "${sets[@]}" > /dev/null 2> "$work/5.txt" ||
  fail "the freed run did not start: $(cat "$work/5.txt")"
[ -f "$work/next/checkpoint.bin" ] || fail "the freed run did not run"
# the lock is held by bushel too: to the run's end, even if the script that started it dies
# (a stand-in for bushel that says when it started, then runs until the check releases it, or
# for 60 s: a fixed time could run out on a loaded machine before the check)
stub="$work/slow-bushel"
printf '#!/bin/sh\ntouch "%s"\nfor i in $(seq 600); do [ -e "%s" ] && exit 0; sleep 0.1; done\n' \
  "$work/slow.started" "$work/slow.release" > "$stub"
chmod +x "$stub"
(bushel="$stub" && run_or_resume slow "$work/slow" "$cup") 2> /dev/null &
script=$!
for _ in $(seq 300); do [ -e "$work/slow.started" ] && break; sleep 0.1; done
[ -e "$work/slow.started" ] || fail "the stand-in did not start"
kill "$script" && wait "$script" 2> /dev/null || true
status=0
run_or_resume slow "$work/slow" "$cup" 2> "$work/6.txt" || status=$?
[ "$status" -eq "$run_busy" ] || fail "a run whose script died was not left to its bushel (status $status)"
touch "$work/slow.release"
# the build that wrote a checkpoint, and whether two builds have the same engine
written=$(checkpoint_build "$work/next")
[ "$written" = "$(this_build)" ] || fail "checkpoint_build gave '$written', not '$(this_build)'"
same_engine "0.1.0 (commit 0123abc)" "0.1.0 (commit 0123abc)" || fail "a build differs from itself"
! same_engine "0.1.0 (commit 0123abc, uncommitted changes)" "0.1.0 (commit 0123abc, uncommitted changes)" ||
  fail "uncommitted changes passed for the same engine"
! same_engine "unknown" "0.1.0 (commit 0123abc)" || fail "an unknown build passed for the same engine"
status=0
same_engine "0.1.0 (commit ffffff0)" "0.1.0 (commit 0123abc)" || status=$?
[ "$status" -eq 2 ] || fail "commits git does not know gave $status, not 2 (cannot tell)"
# (the last commit that changed src/ and its parent, where this checkout has both)
if last=$(git -C "$src" log -1 --format=%H -- src 2> /dev/null) && [ -n "$last" ] &&
    parent=$(git -C "$src" rev-parse --verify -q "$last^" 2> /dev/null); then
  status=0
  same_engine "0.1.0 (commit ${parent:0:12})" "0.1.0 (commit ${last:0:12})" || status=$?
  [ "$status" -eq 1 ] || fail "a commit that changed src/ and its parent gave $status, not 1 (engines differ)"
fi
# in a repository of its own: a commit that changes only cmake/BushelBuildInfo.cmake (the
# version text) keeps the engine; one that changes another CMake file does not
toy="$work/toy-repo"
mkdir -p "$toy/cmake" && git -C "$toy" init -q
commit_toy() {
  echo "$1" >> "$toy/$2"
  git -C "$toy" add -A && git -C "$toy" -c user.name=test -c user.email=test@example.org commit -q -m "$2"
  git -C "$toy" rev-parse HEAD
}
c0=$(commit_toy start cmake/BushelBuildInfo.cmake)
c1=$(commit_toy "version text" cmake/BushelBuildInfo.cmake)
c2=$(commit_toy "-O3" cmake/BushelCompileOptions.cmake)
(root="$toy" && same_engine "0.1.0 (commit ${c0:0:12})" "0.1.0 (commit ${c1:0:12})") ||
  fail "a change to cmake/BushelBuildInfo.cmake alone counted as another engine"
status=0
(root="$toy" && same_engine "0.1.0 (commit ${c1:0:12})" "0.1.0 (commit ${c2:0:12})") || status=$?
[ "$status" -eq 1 ] || fail "a change to the compile options gave $status, not 1 (engines differ)"
# parked and unparked: the same checkpoint and time series in a new folder, which continues;
# a finished run and one without a checkpoint are not parked
mkdir -p "$work/empty"
park_unfinished "$work" "$work/kept" run next empty 2> /dev/null
[ ! -e "$work/kept/run" ] && [ ! -e "$work/kept/empty" ] || fail "a finished run or one without a checkpoint was parked"
unpark_run next "$work/moved" "$work/kept/next" 2> "$work/7.txt"
grep -q "next: continuing from the checkpoint parked in" "$work/7.txt" || fail "no unpark message"
cmp -s "$work/next/checkpoint.bin" "$work/moved/checkpoint.bin" || fail "the unparked checkpoint differs"
cmp -s "$work/next/timeseries.csv" "$work/moved/timeseries.csv" || fail "the unparked time series differs"
# PARK_FRAME_BEFORE=STAGE: the last particle frame written before STAGE began is parked with the
# checkpoint and unparked beside it (a continued run writes only the frames after its checkpoint)
run_or_resume late "$work/late" "$cup" --quiet --stop-at 30ms "${sets[@]}" --set parameters.frame_interval=3ms \
  > /dev/null 2>&1 || fail "the run stopped in its settle stage failed"
settle=$(awk -F, 'NR > 1 && $1 == "settle" { print $2; exit }' "$work/late/timeseries.csv")
before=$(python3 - "$work/late/frames/particles.pvd" "$settle" <<'PY'
import re, sys
frames = re.findall(r'timestep="([^"]*)"[^>]*file="([^"]*)"', open(sys.argv[1]).read())
print(max((float(t), f) for t, f in frames if float(t) < float(sys.argv[2]))[1])
PY
)
[ "$(frame_before "$work/late" settle)" = "$before" ] ||
  fail "frame_before gave '$(frame_before "$work/late" settle)', not '$before' (the last frame before $settle s)"
! frame_before "$work/next" settle || fail "frame_before named a frame of a run that has not reached the stage"
rm "$work/late/frames/$before"
[ "$(frame_before "$work/late" settle)" != "$before" ] || fail "frame_before named a frame that is not there"
cp "$work/run/frames/particles_00000.vtu" "$work/late/frames/$before"  # (back, with other bits)
PARK_FRAME_BEFORE=settle park_unfinished "$work" "$work/kept" late 2> /dev/null
[ "$(ls "$work/kept/late/frames")" = "$before.xz" ] || fail "the frame before settle was not parked: $(ls "$work/kept/late")"
unpark_run late "$work/late-moved" "$work/kept/late" 2> /dev/null
cmp -s "$work/late/frames/$before" "$work/late-moved/frames/$before" || fail "the unparked frame differs"
# a run continued without the frame (by a script from before PARK_FRAME_BEFORE) leaves the
# parked one; a frame the run has replaces it
rm "$work/late-moved/frames/$before"
cp "$work/late/frames/particles.pvd" "$work/late-moved/frames/"  # (as the continued run writes it)
PARK_FRAME_BEFORE=settle park_unfinished "$work" "$work/kept" late-moved 2> /dev/null
mkdir -p "$work/kept/late-moved/frames" && cp "$work/kept/late/frames/$before.xz" "$work/kept/late-moved/frames/"
PARK_FRAME_BEFORE=settle park_unfinished "$work" "$work/kept" late-moved 2> /dev/null
cmp -s "$work/kept/late/frames/$before.xz" "$work/kept/late-moved/frames/$before.xz" ||
  fail "a parked frame went where the run had none"
echo another > "$work/late-moved/frames/$before"
touch "$work/kept/late-moved/frames/particles_99999.vtu.xz"  # (of a run since started again)
PARK_FRAME_BEFORE=settle park_unfinished "$work" "$work/kept" late-moved 2> /dev/null
[ "$(ls "$work/kept/late-moved/frames")" = "$before.xz" ] &&
  [ "$(xz -dc "$work/kept/late-moved/frames/$before.xz")" = another ] || fail "the run's frame did not replace the parked one"
run_or_resume late "$work/late" "$cup" --quiet > /dev/null 2>&1 || fail "the run with a parked frame did not finish"
keep_run "$work/late" "$work/kept/late"
[ ! -e "$work/kept/late/frames" ] || fail "keep_run left the parked frame"
# a checkpoint that another engine build wrote (its commit changed in place): with ONE_BUILD=1
# a build this clone cannot compare is left alone, one whose engine differs starts again
LC_ALL=C sed -i 's/(commit [0-9a-f]\{12\}/(commit fffffffffff0/' "$work/moved/checkpoint.bin"
[[ "$(checkpoint_build "$work/moved")" == *fffffffffff0* ]] || fail "the checkpoint's build was not changed"
if [[ "$(this_build)" != *uncommitted* ]]; then  # (a build with uncommitted changes never compares: below)
  status=0
  ONE_BUILD=1 run_or_resume moved "$work/moved" "$cup" --quiet --stop-at 5ms "${sets[@]}" > /dev/null 2> "$work/8.txt" ||
    status=$?
  [ "$status" -eq 1 ] && grep -q "moved: its checkpoint was written by 0.1.0 (commit fffffffffff0), which this clone" \
    "$work/8.txt" || fail "a build that cannot be compared was not left alone ($status): $(cat "$work/8.txt")"
  [[ "$(checkpoint_build "$work/moved")" == *fffffffffff0* ]] || fail "a checkpoint that cannot be compared was replaced"
fi
(same_engine() { return 1; }
 ONE_BUILD=1 run_or_resume moved "$work/moved" "$cup" --quiet --stop-at 5ms "${sets[@]}" > /dev/null 2> "$work/8.txt") ||
  fail "the run of another build did not start again: $(cat "$work/8.txt")"
grep -q "moved: its checkpoint was written by 0.1.0 (commit fffffffffff0[^)]*), whose engine differs" "$work/8.txt" ||
  fail "no message of another build: $(cat "$work/8.txt")"
[ "$(checkpoint_build "$work/moved")" = "$(this_build)" ] || fail "the run started again was not this build's"
keep_run "$work/moved" "$work/kept/next"
cmp -s "$work/moved/summary.json" "$work/kept/next/summary.json" || fail "keep_run did not keep the summary"
[ ! -e "$work/kept/next/checkpoint.bin.xz" ] || fail "keep_run left the parked checkpoint"
# run_case: a run parked in KEPT continues under its lock, and once finished its summary is kept
park_unfinished "$work" "$work/kept2" next 2> /dev/null
run_case case "$work/case" "$work/kept2/next" "$cup" --quiet "${sets[@]}" > /dev/null 2> "$work/9.txt" ||
  fail "run_case failed: $(cat "$work/9.txt")"
grep -q "case: continuing from the checkpoint parked in" "$work/9.txt" || fail "run_case did not unpark: $(cat "$work/9.txt")"
run_finished "$work/kept2/next" && [ ! -e "$work/kept2/next/checkpoint.bin.xz" ] || fail "run_case did not keep the run"
# a failed run is not finished, not continued, not parked; run_case keeps its summary
mkdir -p "$work/failed" && touch "$work/failed/checkpoint.bin"
echo '{"interrupted": false, "failed": "particles lost"}' > "$work/failed/summary.json"
! run_finished "$work/failed" && run_failed "$work/failed" || fail "a failed run counted as finished"
park_unfinished "$work" "$work/kept3" failed 2> /dev/null
[ ! -e "$work/kept3/failed" ] || fail "a failed run was parked"
status=0
run_case failed "$work/failed" "$work/kept3/failed" "$cup" --quiet 2> "$work/10.txt" || status=$?
[ "$status" -eq 1 ] && grep -q "failed: it failed" "$work/10.txt" || fail "a failed run was not left alone: $(cat "$work/10.txt")"
run_failed "$work/kept3/failed" || fail "the failed run's summary was not kept"
# bushel's exit status comes back
if run_or_resume bad "$work/bad" "$cup" --quiet --set parameters.mass=-5g 2> /dev/null; then
  fail "a failed run returned 0"
fi
echo "resume check passed"
