#!/usr/bin/env bash
# The campaign of campaign_check.sh across MPI ranks: `mpirun -n 2 bushel doe run`, rank 0
# handing out rows and rank 1 running them; then a resume with one row lost.
# usage: campaign_mpi_check.sh MPIEXEC BUSHEL WORKDIR
set -euo pipefail
mpiexec=$1; bushel=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAILED: $*"; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # (CI containers run as root)
bin_cmd=({bushel} bin --diameter 9m --grain-height 7m --test-weight 60lb/bu --wpacking 0.35,3,0.01 --moisture 12%
         --wall-friction {mu} --k {k} --json)
"$bushel" doe design factorial --factors mu=0.2:0.4,k=0.4:0.6 --center 2 --out design.csv
run() { "$mpiexec" --oversubscribe -n 2 "$bushel" doe run design.csv --out camp --response mass_kg -- "${bin_cmd[@]}"; }
out=$(run 2>progress.txt)
[[ $out == *"6 runs: 0 already done, 6 ran, 0 failed"* ]] || fail "first pass: $out $(cat progress.txt)"
[[ $(grep -c "on rank 1" progress.txt) == 6 ]] || fail "rank 1 ran the rows: $(cat progress.txt)"
[[ $(grep -c ',done$' camp/results.csv) == 6 ]] || fail "results: $(cat camp/results.csv)"
# The same numbers as a local run.
"$bushel" doe run design.csv --out local --response mass_kg -- "${bin_cmd[@]}" >/dev/null 2>&1
cmp <(cut -d, -f1-7 camp/results.csv) <(cut -d, -f1-7 local/results.csv) || fail "MPI and local results differ"
rm camp/run_2/done.json
out=$(run 2>/dev/null)
[[ $out == *"6 runs: 5 already done, 1 ran, 0 failed"* ]] || fail "resume: $out"
echo "campaign mpi check passed"
