# Sourced by the validation scripts: runs that survive an interruption (docs/scenarios.md,
# checkpoints). Needs $bushel, the bushel binary.

# run_finished DIR: DIR holds a finished run (its summary says it was not interrupted).
run_finished() { grep -qs '"interrupted": false' "$1/summary.json"; }

# run_or_resume LABEL DIR SCENARIO [ARGS...]
#   DIR holds a finished run (summary.json, not interrupted): it is kept.
#   DIR holds a checkpoint: the run continues from it (bushel run --restart DIR), with the
#     ARGS other than `--set X` (the scenario and its overrides are in the checkpoint).
#   Else: bushel run SCENARIO --out DIR ARGS...
# Returns bushel's exit status; what it does goes to stderr, prefixed by LABEL.
run_or_resume() {
  local label="$1" dir="$2" scenario="$3"
  shift 3
  if run_finished "$dir"; then
    echo "$label: finished before, kept ($dir)" >&2
    return 0
  fi
  if [ -f "$dir/checkpoint.bin" ]; then
    local options=()
    while [ $# -gt 0 ]; do
      if [ "$1" = --set ]; then shift 2; else options+=("$1"); shift; fi
    done
    echo "$label: continuing from its checkpoint ($dir)" >&2
    "$bushel" run --restart "$dir" ${options[@]+"${options[@]}"}
    return
  fi
  echo "$label: starting: bushel run $scenario --out $dir $*" >&2
  "$bushel" run "$scenario" --out "$dir" "$@"
}
