#!/usr/bin/env bash
# The study's calibration cup at full size (scenarios/calibration-cup.yaml, 325 g), for the
# three size fractions with the calibrated 5-sphere model and with the single-sphere model and
# its per-pair parameters, next to the study's measurements and EDEM results (docs/wheat.md).
#
#   validation/run-cup.sh [CASE...]     # cases: large-5s medium-5s small-5s large-1s medium-1s small-1s
#   validation/run-cup.sh --park        # keep the unfinished cases' checkpoints with the results
#
# Hours on 2 cores; on a machine used for other work too, two scripts with one thread each
# (OMP_NUM_THREADS=1) go faster than one with two (bench/results/wait-policy.md). They may be given
# the same cases: each leaves the case that the other is running to it and takes the next.
# Each case runs in runs/validation/cup-CASE with a checkpoint every 5
# minutes; run the script again after an interruption (Ctrl-C, a reboot) and it continues
# each unfinished case from its checkpoint and skips finished ones. A finished case's
# summary.json is kept in validation/results/cup-runs/cup-CASE/, which is committed with the
# results: runs/ is scratch space, and a case kept there is finished on any checkout.
# `--park` (while the cases run or after) copies each unfinished case's latest checkpoint and
# time series there too, compressed, so that a case can span machines: on a checkout without
# the run folder, the script continues from the parked checkpoint. The table of every case so
# far is written to validation/results/cup.md (and printed) after each case and after --park,
# and at the end
# `bushel report` draws the cases beside the measurements in validation/results/cup/.
#
# A series of the same cases run another way: SERIES=NAME and SET="KEY=VALUE ..." (overrides
# for every case, as in the table below) put its runs in runs/validation/NAME/, its kept
# results in validation/results/cup-runs-NAME/, its table in validation/results/cup-NAME.md and
# its report in validation/results/cup-NAME/, e.g.
#   SERIES=critical-0.5 SET="simulation.time_step=50%critical" validation/run-cup.sh large-5s
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bushel="${BUSHEL:-$root/build/release/bin/bushel}"
series=${SERIES:+-$SERIES}
runs="$root/runs/validation${SERIES:+/$SERIES}"
kept="$root/validation/results/cup-runs$series"
mkdir -p "$runs" "$kept"
source "$root/validation/resume.sh"

# case -> overrides: parameters by name (docs/wheat.md: single-sphere fr_ww / fs_ww / e_ww per
# pair), other keys by path (simulation.time_step=5%rayleigh, say).
declare -A sets=(
  [large-5s]="fraction=large model=5s"
  [medium-5s]="fraction=medium model=5s"
  [small-5s]="fraction=small model=5s"
  [large-1s]="fraction=large model=1s fr_ww=0.05 fs_ww=0.172 e_ww=0.5"
  [medium-1s]="fraction=medium model=1s fr_ww=0.05 fs_ww=0.486 e_ww=0.1"
  [small-1s]="fraction=small model=1s fr_ww=0.10 fs_ww=0.500 e_ww=0.1"
)
all=(large-5s medium-5s small-5s large-1s medium-1s small-1s)

finished() { run_finished "$kept/cup-$1"; }

park() { park_unfinished "$runs" "$kept" "${all[@]/#/cup-}"; }

# the table of every case so far and whether large > medium > small holds (validation/cup_table.py)
table() {
  /usr/bin/python3 "$root/validation/cup_table.py" \
    "$runs" "$kept" "$root/data/reference_values.csv" "${all[@]}"
}

if [ "${1:-}" = --park ]; then park; table > "$root/validation/results/cup$series.md"; exit 0; fi
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=("${all[@]}")

for c in "${cases[@]}"; do
  [ -n "${sets[$c]:-}" ] || { echo "unknown case '$c' (known: ${!sets[*]})" >&2; exit 2; }
  if finished "$c"; then
    echo "$c: finished before, kept ($kept/cup-$c)" >&2
    continue
  fi
  if run_failed "$kept/cup-$c"; then
    echo "$c: failed before ($kept/cup-$c/summary.json); remove it to run it again" >&2
    continue
  fi
  args=(--set parameters.frame_interval=1s)
  # shellcheck disable=SC2086  # (the overrides split into words on purpose)
  set_args ${sets[$c]} ${SET:-}
  rc=0
  run_case "$c" "$runs/cup-$c" "$kept/cup-$c" "$root/scenarios/calibration-cup.yaml" "${args[@]}" || rc=$?
  if [ "$rc" -eq "$run_busy" ]; then continue; fi  # (another script runs it: the next case)
  if [ "$rc" -ne 0 ] && ! run_failed "$runs/cup-$c"; then
    echo "$c: stopped (exit ${rc}); run the script again to continue" >&2
    table > "$root/validation/results/cup$series.md"
    exit "$rc"
  fi
  table > "$root/validation/results/cup$series.md"
done
table | tee "$root/validation/results/cup$series.md"
# the report of every finished case (as it shows them: from the root)
dirs=()
for c in "${all[@]}"; do
  if finished "$c"; then dirs+=("validation/results/cup-runs$series/cup-$c"); fi
done
(cd "$root" && "$bushel" report "${dirs[@]}" --out "validation/results/cup$series" \
  --title "Calibration cup at full size${SERIES:+ ($SERIES)}")
