#!/usr/bin/env bash
# A campaign over a scenario file (`bushel doe run --scenario`): a 2x2 factorial over two
# contact parameters of a tiny calibration cup. Each row's results come from its run's
# summary.json; a resume runs only the lost row; bad input is caught before anything runs; and
# the same campaign across MPI ranks (where mpiexec is given) gives the same numbers.
# usage: campaign_scenario_check.sh BUSHEL SCENARIO WORKDIR [MPIEXEC]
set -euo pipefail
bushel=$1; scenario=$2; work=$3; mpiexec=${4:-}
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAILED: $*"; exit 1; }
tiny=(--set parameters.mass=3g --set parameters.model=1s --set parameters.cup_height=8mm
      --set parameters.frame_interval=10s)

"$bushel" doe design factorial --factors fs_ww=0.2:0.4,e_ww=0.3:0.5 --no-randomize --out design.csv >/dev/null
# run OUT [LAUNCHER...]: the campaign into OUT, started by LAUNCHER (e.g. mpiexec -n 2)
run() {
  local out=$1; shift
  "$@" "$bushel" doe run design.csv --out "$out" --scenario "$scenario" "${tiny[@]}" \
    --response bulk_density,filling_time --jobs 2
}
out=$(run camp 2>&1) || fail "campaign: $out"
[[ $out == *"4 runs: 0 already done, 4 ran, 0 failed"* ]] || fail "first pass: $out"

# Each row ran with its factors as parameters, and its responses are its summary's results.
/usr/bin/python3 - camp <<'PY' || fail "results.csv does not hold the runs' results"
import csv, json, os, sys
rows = list(csv.DictReader(open(os.path.join(sys.argv[1], "results.csv"))))
assert len(rows) == 4 and all(r["status"] == "done" for r in rows), rows
for r in rows:
    s = json.load(open(os.path.join(sys.argv[1], "run_" + r["std_order"], "summary.json")))
    assert float(s["parameters"]["fs_ww"]) == float(r["fs_ww"]) and float(s["parameters"]["e_ww"]) == float(r["e_ww"])
    for k in ("bulk_density", "filling_time"):
        assert abs(float(r[k]) - s["results"][k]["value"]) <= 1e-9 * abs(s["results"][k]["value"]), (k, r)
PY

# A lost row runs again, alone.
rm camp/run_3/done.json
out=$(run camp 2>/dev/null) || fail "resume: $out"
[[ $out == *"4 runs: 3 already done, 1 ran, 0 failed"* ]] || fail "resume: $out"

# Checked before anything runs: an unknown result, a factor value the scenario refuses.
check_error() {
  local want=$1; shift
  if err=$("$@" 2>&1 >/dev/null); then fail "expected an error from: $*"; fi
  [[ $(printf '%s\n' "$err" | wc -l) -eq 1 ]] || fail "not one line: $err"
  [[ $err == *"$want"* ]] || fail "expected '$want' in: $err"
}
check_error "the scenario has no result 'bulk_densty' (did you mean 'bulk_density'?)" \
  "$bushel" doe run design.csv --out bad --scenario "$scenario" "${tiny[@]}" --response bulk_densty
sed 's/,0.2,/,-0.2,/' design.csv > negative.csv
check_error "(design row on line 2 of negative.csv)" \
  "$bushel" doe run negative.csv --out bad --scenario "$scenario" "${tiny[@]}" --response bulk_density
[[ ! -e bad ]] || fail "a bad campaign left a folder"

if [[ -n $mpiexec ]]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # (CI containers run as root)
  out=$(run camp_mpi "$mpiexec" --oversubscribe -n 2 2>/dev/null) || fail "mpi campaign: $out"
  [[ $out == *"4 runs: 0 already done, 4 ran, 0 failed"* ]] || fail "mpi: $out"
  cmp camp/results.csv camp_mpi/results.csv || fail "MPI and local results differ"
fi
echo "campaign scenario check passed"
