#!/usr/bin/env bash
# A small campaign through `bushel doe run`: a factorial design over the bin model's wall
# friction and K, each row a `bushel bin --json` run; then a resume after a lost run and a run
# cut short, the analysis of the results, and a bad placeholder caught before anything runs.
# usage: campaign_check.sh BUSHEL WORKDIR
set -euo pipefail
bushel=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAILED: $*"; exit 1; }
bin_cmd=({bushel} bin --diameter 9m --grain-height 7m --test-weight 60lb/bu --wpacking 0.35,3,0.01 --moisture 12%
         --wall-friction {mu} --k {k} --json)

"$bushel" doe design factorial --factors mu=0.2:0.4,k=0.4:0.6 --center 2 --out design.csv
out=$("$bushel" doe run design.csv --out camp --response mass_kg,bottom_pressure_Pa --jobs 2 -- "${bin_cmd[@]}" 2>/dev/null)
[[ $out == *"6 runs: 0 already done, 6 ran, 0 failed"* ]] || fail "first pass: $out"
[[ $(grep -c ',done$' camp/results.csv) == 6 ]] || fail "results: $(cat camp/results.csv)"

# A run lost (no done.json) and one cut short (a partial directory): only those two run again.
rm camp/run_3/done.json
rm -r camp/run_5; mkdir camp/run_5; echo '{"mass_kg": 1' > camp/run_5/stdout.txt
out=$("$bushel" doe run design.csv --out camp --response mass_kg,bottom_pressure_Pa --jobs 2 -- "${bin_cmd[@]}" 2>/dev/null)
[[ $out == *"6 runs: 4 already done, 2 ran, 0 failed"* ]] || fail "resume: $out"
[[ $(grep -c ',done$' camp/results.csv) == 6 ]] || fail "results after resume"

# The results table goes straight into the analysis: friction and K both lower the pressure.
out=$("$bushel" doe analyze camp/results.csv --factors mu,k --response bottom_pressure_Pa --json)
python3 - "$out" <<'PY' || fail "analysis"
import json, sys
terms = {t["term"]: t for t in json.loads(sys.argv[1])["terms"]}
assert terms["mu"]["coefficient"] < 0 and terms["k"]["coefficient"] < 0, terms
PY

# A placeholder that names no column: an error, and nothing runs.
if "$bushel" doe run design.csv --out camp2 --response mass_kg -- {bushel} bin --wall-friction {mu} --k {k} {kk} \
    2>err.txt; then
  fail "bad placeholder accepted"
fi
grep -q "placeholder {kk} names no column of the design" err.txt || fail "message: $(cat err.txt)"
[[ ! -e camp2 ]] || fail "camp2 created"

# {bushel} still starts this program after its file is replaced mid-campaign (a rebuild): here
# the first row deletes the copy that runs the campaign, and the later rows still run.
cp "$bushel" ./bushel-copy
out=$(./bushel-copy doe run design.csv --out camp3 --response mass_kg -- sh -c \
  '"$0" bin --diameter 9m --grain-height 7m --test-weight 60lb/bu --incompressible --k "$1" --json; s=$?; rm -f "$0"; exit $s' \
  {bushel} {k} 2>/dev/null) || fail "after the program's file was deleted: $out"
[[ ! -e bushel-copy && $out == *"6 runs: 0 already done, 6 ran, 0 failed"* ]] || fail "deleted program: $out"
echo "campaign check passed"
