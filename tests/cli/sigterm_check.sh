#!/usr/bin/env bash
# SIGTERM (what `kill` and batch schedulers send) stops a run as Ctrl-C does: a checkpoint, a
# summary marked interrupted, exit 143 (128 + 15); --restart then finishes it; a second run
# into the same folder is refused without --overwrite.
# usage: sigterm_check.sh BUSHEL SCENARIO WORKDIR
set -euo pipefail
bushel=$1; scenario=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAILED: $*"; exit 1; }
small=(--set parameters.mass=5g --set parameters.cup_radius=15mm --set parameters.pour_radius=12mm
       --set parameters.measured_height=5mm)

"$bushel" run "$scenario" --out "$work/run" --quiet "${small[@]}" --checkpoint-every 0 &
pid=$!
for _ in $(seq 600); do  # the first row of the time series: the run has started stepping
  [[ -s $work/run/timeseries.csv ]] && [[ $(wc -l < "$work/run/timeseries.csv") -ge 2 ]] && break
  sleep 0.1
done
kill -TERM "$pid"
rc=0; wait "$pid" || rc=$?
[[ $rc == 143 ]] || fail "exit $rc after SIGTERM, expected 143"
[[ -f $work/run/checkpoint.bin ]] || fail "no checkpoint after SIGTERM"
grep -q '"interrupted": true' "$work/run/summary.json" || fail "summary not marked interrupted"

if "$bushel" run "$scenario" --out "$work/run" --quiet "${small[@]}" 2>"$work/err.txt"; then
  fail "a second run into the folder was accepted"
fi
grep -q "the folder holds another run" "$work/err.txt" || fail "message: $(cat "$work/err.txt")"

"$bushel" run --restart "$work/run" --quiet >"$work/out.txt" || fail "restart: $(cat "$work/out.txt")"
grep -q '"interrupted": false' "$work/run/summary.json" || fail "restarted run not finished"
grep -q "cup.bulk_density" "$work/out.txt" || fail "no result: $(cat "$work/out.txt")"
echo "sigterm check passed"
