# Sourced by bench/replay, bench/replay-pair and bench/worker-layout.
# continue_copy BUSHEL PHASE_DIR STOP_AT OUT: copies a run folder (checkpoint.bin,
# timeseries.csv, summary.json) to OUT/run and continues it with the program BUSHEL on THREADS
# threads (default 1) to STOP_AT (with its unit), writing no checkpoint on the way; the run's
# output goes to OUT/run.log. Exits with a message if the run fails.
continue_copy() {
  local run="$4/run"
  rm -rf "$run" && mkdir -p "$run"
  cp "$2/checkpoint.bin" "$2/timeseries.csv" "$2/summary.json" "$run/"
  OMP_NUM_THREADS=${THREADS:-1} "$1" run --restart "$run" --stop-at "$3" --threads "${THREADS:-1}" --quiet \
    --checkpoint-every 0 \
    >"$4/run.log" 2>&1 || { echo "$(basename "$0"): $1 failed, see $4/run.log" >&2; exit 1; }
}
