# Sourced by the validation scripts: runs that survive an interruption (docs/scenarios.md,
# checkpoints). Needs $bushel, the bushel binary, and $root, the checkout.
# shellcheck shell=bash disable=SC2154  # ($bushel and $root: set by the script that sources this)

# run_finished DIR: DIR holds a finished run (its summary says it was neither interrupted nor
# failed).
run_finished() { grep -qs '"interrupted": false' "$1/summary.json" && ! run_failed "$1"; }

# run_failed DIR: DIR holds a run that failed (NaN, runaway overlaps, particles lost: its
# summary says why). Such a run is not continued: it would fail again.
run_failed() { grep -qs '"failed": "' "$1/summary.json"; }

# The status run_or_resume returns for a run that another script is running now.
run_busy=75

# The sources of the engine build: a change to any of them may change a run's bits (the two
# data tables are built into the binary, src/CMakeLists.txt). cmake/BushelBuildInfo.cmake is
# left out: it writes only the version text (`bushel --version`), never a run's numbers.
engine_sources=(src include apps cmake CMakeLists.txt CMakePresets.json data/wheat_clumps.csv
  data/reference_values.csv ':(exclude)cmake/BushelBuildInfo.cmake')

# checkpoint_build DIR: the build that wrote DIR/checkpoint.bin, as `bushel --version` names a
# build ("0.1.0 (commit 0123456789ab)", ", uncommitted changes" inside the brackets if so): the
# checkpoint's first section holds it as text.
checkpoint_build() {
  head -c 4096 "$1/checkpoint.bin" | grep -a -o -m1 '[0-9][0-9.]* (commit [0-9a-f]*[^)]*)' || echo unknown
}

# this_build: the build of $bushel, named the same way.
this_build() { "$bushel" --version | sed 's/^bushel //'; }

# same_engine BUILD_A BUILD_B: both builds were compiled from committed trees whose engine
# sources are the same (git diff), so a run continued by one from the other's checkpoint ends
# with the bits it would have had. Returns 0 if so, 1 if not, 2 if it cannot tell (a commit
# this clone does not have).
same_engine() {
  [[ "$1" != *uncommitted* && "$2" != *uncommitted* ]] || return 1
  local a b rc=0
  a=$(sed -n 's/.*commit \([0-9a-f]*\).*/\1/p' <<< "$1")
  b=$(sed -n 's/.*commit \([0-9a-f]*\).*/\1/p' <<< "$2")
  [ -n "$a" ] && [ -n "$b" ] || return 1
  [ "$a" = "$b" ] && return 0
  git -C "$root" diff --quiet "$a" "$b" -- "${engine_sources[@]}" 2>/dev/null || rc=$?
  if [ "$rc" -gt 1 ]; then return 2; fi
  return "$rc"
}

# run_or_resume LABEL DIR SCENARIO [ARGS...]
#   DIR holds a finished run (summary.json, neither interrupted nor failed): it is kept.
#   DIR holds a failed run: left as it is (returns 1); remove DIR to run it again.
#   DIR is being run by another script (on this checkout): left to it; returns $run_busy.
#   DIR holds a checkpoint: the run continues from it (bushel run --restart DIR), with the
#     ARGS other than `--set X` (the scenario and its overrides are in the checkpoint). With
#     ONE_BUILD=1, a checkpoint written by a build whose engine sources differ from $bushel's
#     (same_engine) is not continued: the run starts again, so that one engine build runs it
#     all (SAME_BITS=1 continues it anyway, where bench/ab-restart showed the same bits); one
#     whose build this clone cannot compare is left alone (returns 1).
#   Else: bushel run SCENARIO --out DIR ARGS...
# Returns bushel's exit status; what it does goes to stderr, prefixed by LABEL.
# Two scripts may share a list of runs (two workers, one thread each): the lock on DIR.lock
# (flock, held by bushel too, so to the run's end even if the script is killed) keeps them
# from running one run twice at once, which would spoil its checkpoint.
run_or_resume() { locked "$1" "$2" resume_locked "$@"; }

# run_case LABEL DIR KEPT SCENARIO [ARGS...]: one case of a series whose results are kept in
# KEPT (run-cup.sh, run-study.sh): under DIR's lock, a checkpoint parked in KEPT unparked
# (unpark_run), run_or_resume, and a finished or failed run's summary kept (keep_run).
run_case() { locked "$1" "$2" case_locked "$@"; }

# set_args OVERRIDE...: each KEY=VALUE appended to the array args as bushel's option: a dotted
# KEY as written (--set KEY=VALUE), a bare one as a scenario parameter (--set parameters.KEY=VALUE).
set_args() {
  local s
  for s in "$@"; do
    if [[ "${s%%=*}" == *.* ]]; then args+=(--set "$s"); else args+=(--set "parameters.$s"); fi
  done
}

# locked LABEL DIR FUNCTION ARGS...: FUNCTION ARGS... while this script holds DIR.lock, or
# $run_busy where another holds it.
locked() {
  local label="$1" dir="$2" fn="$3" lock rc=0
  shift 3
  mkdir -p "$(dirname "$dir")"
  if ! exec {lock}> "$dir.lock"; then
    echo "$label: cannot open its lock $dir.lock" >&2
    return 1
  fi
  if ! flock -n "$lock"; then
    exec {lock}>&-
    echo "$label: another script is running it now ($dir); left to it" >&2
    return "$run_busy"
  fi
  "$fn" "$@" || rc=$?
  exec {lock}>&-
  return "$rc"
}

case_locked() {  # (run_case, under the lock)
  local label="$1" dir="$2" kept="$3" rc=0
  shift 3
  if ! run_finished "$dir" && ! run_failed "$dir"; then unpark_run "$label" "$dir" "$kept"; fi
  resume_locked "$label" "$dir" "$@" || rc=$?
  if run_finished "$dir" || run_failed "$dir"; then keep_run "$dir" "$kept"; fi
  return "$rc"
}

resume_locked() {  # (run_or_resume, under the lock)
  local label="$1" dir="$2" scenario="$3" rc=0 same=0
  shift 3
  if run_finished "$dir"; then  # (after the lock: the other script may just have finished it)
    echo "$label: finished before, kept ($dir)" >&2
    return 0
  fi
  if run_failed "$dir"; then
    echo "$label: it failed ($dir/summary.json says why); not run again: remove $dir to start it afresh" >&2
    return 1
  fi
  if [ -f "$dir/checkpoint.bin" ] && [ "${ONE_BUILD:-0}" = 1 ] && [ "${SAME_BITS:-0}" != 1 ]; then
    same_engine "$(checkpoint_build "$dir")" "$(this_build)" || same=$?
  fi
  if [ "$same" = 2 ]; then
    echo "$label: its checkpoint was written by $(checkpoint_build "$dir"), which this clone cannot compare" \
      "with $(this_build) (a commit it lacks?); left as it is: fetch that commit, or SAME_BITS=1" \
      "continues it ($dir)" >&2
    return 1
  elif [ "$same" = 1 ]; then
    echo "$label: its checkpoint was written by $(checkpoint_build "$dir"), whose engine differs from" \
      "$(this_build)'s: starting it again ($dir)" >&2
    "$bushel" run "$scenario" --out "$dir" --overwrite "$@" || rc=$?
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
  return "$rc"
}

# park_run DIR KEPT: DIR's checkpoint and time series up to it, xz-compressed, into KEPT, so
# that the run can continue on another checkout (unpark_run). The checkpoint first: the series
# only grows, so it covers the checkpoint even if the run writes a newer one in between (the
# continued run cuts it back to the checkpoint's length). With PARK_FRAME_BEFORE=STAGE also the
# frame frame_before names, which the continued run would not write again.
park_run() {
  local dir="$1" kept="$2" frame
  mkdir -p "$kept"
  xz -T1 -c "$dir/checkpoint.bin" > "$kept/checkpoint.bin.xz.tmp"
  xz -T1 -c "$dir/timeseries.csv" > "$kept/timeseries.csv.xz.tmp"
  mv "$kept/checkpoint.bin.xz.tmp" "$kept/checkpoint.bin.xz"
  mv "$kept/timeseries.csv.xz.tmp" "$kept/timeseries.csv.xz"
  # (a frame parked before stays where DIR has none: DIR may have been continued without it)
  if [ -n "${PARK_FRAME_BEFORE:-}" ] && frame=$(frame_before "$dir" "$PARK_FRAME_BEFORE"); then
    rm -rf "$kept/frames" && mkdir -p "$kept/frames"
    xz -T1 -c "$dir/frames/$frame" > "$kept/frames/$frame.xz.tmp"
    mv "$kept/frames/$frame.xz.tmp" "$kept/frames/$frame.xz"
  fi
}

# frame_before DIR STAGE: the file name (in DIR/frames) of the last particle frame that DIR's run
# wrote before its stage STAGE began (the time series' first row of STAGE), if the run has got
# that far and the frame is there; else it fails. Set PARK_FRAME_BEFORE=STAGE and park_run keeps
# that frame too, as a run continued from a parked checkpoint writes only the frames after it:
# the state before STAGE (the tapped cylinder's loose fill before the taps, validation/tap_packing.py)
# stays measurable.
frame_before() {
  local dir="$1" stage="$2" start f
  start=$(awk -F, -v s="$stage" 'NR > 1 && $1 == s { print $2; exit }' "$dir/timeseries.csv" 2> /dev/null)
  [ -n "$start" ] && [ -f "$dir/frames/particles.pvd" ] || return 1
  # (the pvd's DataSet lines, timestep="T" ... file="F", in the order written; the last before the
  # stage's start whose file is there)
  for f in $(awk -v t0="$start" 'match($0, /timestep="[^"]*"/) {
      t = substr($0, RSTART + 10, RLENGTH - 11)
      if (t + 0 < t0 + 0 && match($0, /file="[^"]*"/)) print substr($0, RSTART + 6, RLENGTH - 7)
    }' "$dir/frames/particles.pvd" | tac); do
    if [ -f "$dir/frames/$f" ]; then echo "$f"; return 0; fi
  done
  return 1
}

# park_unfinished RUNS KEPT CASE...: park_run of each CASE (a folder in RUNS and in KEPT) that has
# a checkpoint and has not finished.
park_unfinished() {
  local runs="$1" kept="$2" c
  shift 2
  for c in "$@"; do
    if run_finished "$kept/$c" || run_finished "$runs/$c" || run_failed "$runs/$c" \
        || [ ! -f "$runs/$c/checkpoint.bin" ]; then continue; fi
    park_run "$runs/$c" "$kept/$c"
    echo "$c: checkpoint parked in $kept/$c ($(du -h "$kept/$c/checkpoint.bin.xz" | cut -f1))" >&2
  done
}

# unpark_run LABEL DIR KEPT: a run with no checkpoint in DIR but one parked in KEPT continues
# from that (with the frame parked beside it, if any).
unpark_run() {
  local label="$1" dir="$2" kept="$3"
  if [ -f "$dir/checkpoint.bin" ] || [ ! -f "$kept/checkpoint.bin.xz" ]; then return; fi
  mkdir -p "$dir"
  xz -dc "$kept/timeseries.csv.xz" > "$dir/timeseries.csv"
  local f name
  for f in "$kept"/frames/*.xz; do  # (a frame park_run kept: PARK_FRAME_BEFORE)
    [ -f "$f" ] || continue
    name=$(basename "$f" .xz)
    mkdir -p "$dir/frames"
    xz -dc "$f" > "$dir/frames/$name.tmp"
    mv "$dir/frames/$name.tmp" "$dir/frames/$name"
  done
  xz -dc "$kept/checkpoint.bin.xz" > "$dir/checkpoint.bin.tmp"
  mv "$dir/checkpoint.bin.tmp" "$dir/checkpoint.bin"  # (last: a checkpoint in DIR means unparked)
  echo "$label: continuing from the checkpoint parked in $kept" >&2
}

# keep_run DIR KEPT: a finished (or failed) run's summary.json into KEPT (committed with the
# results), and its parked checkpoint and frame gone.
keep_run() {
  local dir="$1" kept="$2"
  mkdir -p "$kept"
  cp "$dir/summary.json" "$kept/summary.json.tmp"
  mv "$kept/summary.json.tmp" "$kept/summary.json"
  rm -f "$kept/checkpoint.bin.xz" "$kept/timeseries.csv.xz"
  rm -rf "$kept/frames"
}
