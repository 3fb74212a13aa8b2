# Sourced by the validation scripts: runs that survive an interruption (docs/scenarios.md,
# checkpoints). Needs $bushel, the bushel binary.

# run_finished DIR: DIR holds a finished run (its summary says it was not interrupted).
run_finished() { grep -qs '"interrupted": false' "$1/summary.json"; }

# The status run_or_resume returns for a run that another script is running now.
run_busy=75

# run_or_resume LABEL DIR SCENARIO [ARGS...]
#   DIR holds a finished run (summary.json, not interrupted): it is kept.
#   DIR is being run by another script (on this checkout): left to it; returns $run_busy.
#   DIR holds a checkpoint: the run continues from it (bushel run --restart DIR), with the
#     ARGS other than `--set X` (the scenario and its overrides are in the checkpoint).
#   Else: bushel run SCENARIO --out DIR ARGS...
# Returns bushel's exit status; what it does goes to stderr, prefixed by LABEL.
# Two scripts may share a list of runs (two workers, one thread each): the lock on DIR.lock
# (flock, held by bushel too, so to the run's end even if the script is killed) keeps them
# from running one run twice at once, which would spoil its checkpoint.
run_or_resume() {
  local label="$1" dir="$2" scenario="$3" lock rc=0
  shift 3
  mkdir -p "$(dirname "$dir")"
  exec {lock}> "$dir.lock"
  if ! flock -n "$lock"; then
    exec {lock}>&-
    echo "$label: another script is running it now ($dir); left to it" >&2
    return "$run_busy"
  fi
  if run_finished "$dir"; then  # (after the lock: the other script may just have finished it)
    echo "$label: finished before, kept ($dir)" >&2
  elif [ -f "$dir/checkpoint.bin" ]; then
    local options=()
    while [ $# -gt 0 ]; do
      if [ "$1" = --set ]; then shift 2; else options+=("$1"); shift; fi
    done
    echo "$label: continuing from its checkpoint ($dir)" >&2
    "$bushel" run --restart "$dir" ${options[@]+"${options[@]}"} || rc=$?
  else
    echo "$label: starting: bushel run $scenario --out $dir $*" >&2
    "$bushel" run "$scenario" --out "$dir" --overwrite "$@" || rc=$?
  fi
  exec {lock}>&-
  return "$rc"
}
