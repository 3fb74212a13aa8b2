#!/usr/bin/env bash
# validation/resume.sh: run_or_resume starts a run, continues one from its checkpoint (its
# --set overrides left out: the checkpoint holds them, and bushel refuses them with --restart)
# and keeps a finished one.
#   resume_check.sh BUSHEL SOURCE_DIR WORK_DIR
set -euo pipefail
bushel="$1" src="$2" work="$3"
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
# (a stand-in for bushel that says when it started, then runs for 5 s)
stub="$work/slow-bushel"
printf '#!/bin/sh\ntouch "%s"\nsleep 5\n' "$work/slow.started" > "$stub"
chmod +x "$stub"
(bushel="$stub" && run_or_resume slow "$work/slow" "$cup") 2> /dev/null &
script=$!
for _ in $(seq 300); do [ -e "$work/slow.started" ] && break; sleep 0.1; done
[ -e "$work/slow.started" ] || fail "the stand-in did not start"
kill "$script" && wait "$script" 2> /dev/null || true
status=0
run_or_resume slow "$work/slow" "$cup" 2> "$work/6.txt" || status=$?
[ "$status" -eq "$run_busy" ] || fail "a run whose script died was not left to its bushel (status $status)"
# bushel's exit status comes back
if run_or_resume bad "$work/bad" "$cup" --quiet --set parameters.mass=-5g 2> /dev/null; then
  fail "a failed run returned 0"
fi
echo "resume check passed"
