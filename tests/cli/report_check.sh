#!/usr/bin/env bash
# `bushel report` on real run folders: the README's cup (finished) and an interrupted
# calibration cup. The report names both, sets the cup against the study's lab value (n/a: the
# run was cut short), writes CSV tables that hold the summaries' numbers, draws the figures
# where matplotlib is installed, and bad input is a one-line error.
# usage: report_check.sh BUSHEL CUP_POUR_RUN CUP_STOP_RUN WORKDIR
set -euo pipefail
bushel=$1; cup=$2; stopped=$3; work=$4
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAILED: $*"; exit 1; }

out=$("$bushel" report "$cup" "$stopped" --out "$work/rep" --no-plots)
[[ $out == *"runs     2 of 2 scenarios"* ]] || fail "summary lines: $out"
[[ $out == *"bulk_density"*"826.1"*"lab (study"* ]] || fail "no comparison printed: $out"
md=$(cat "$work/rep/report.md")
[[ $md == *"## cup-pour"* && $md == *"## calibration-cup"* ]] || fail "sections: $md"
[[ $md == *"interrupted at 0.0"* ]] || fail "the interrupted run's status: $md"
[[ $md == *"| bulk_density [kg/m3] | n/a | 826.1 ± 1.2 | lab (study"* ]] || fail "comparison row: $md"
[[ -s "$work/rep/report.html" && -s "$work/rep/figures.json" ]] || fail "html or figures.json missing"

# The CSV holds the summary's values to 10 digits.
/usr/bin/python3 - "$cup" "$work/rep/cup-pour-results.csv" <<'PY' || fail "results CSV differs from summary.json"
import csv, json, sys
summary = json.load(open(sys.argv[1] + "/summary.json"))
row = next(csv.DictReader(open(sys.argv[2])))
assert summary["results"], "the cup-pour scenario has results"
for name, r in summary["results"].items():
    if r is None:
        assert row[name] == "", name
    else:
        assert abs(float(row[name]) - r["value"]) <= 1e-9 * abs(r["value"]), (name, row[name], r["value"])
PY

# Figures, where Debian's matplotlib is installed (scripts/setup.sh installs it).
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  "$bushel" report "$cup" "$stopped" --out "$work/plots" >/dev/null
  n=$(ls "$work/plots"/*.png | wc -l)
  [[ $n -ge 1 ]] || fail "no PNG drawn"
  for f in "$work/plots"/*.png; do
    [[ $(head -c 8 "$f" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "$f is not a PNG"
  done
  # the page holds its figures: each PNG as a data: URL, byte for byte
  /usr/bin/python3 - "$work/plots" <<'PY' || fail "figures not embedded in report.html"
import base64, glob, sys
html = open(sys.argv[1] + "/report.html").read()
for png in glob.glob(sys.argv[1] + "/*.png"):
    assert '<img src="data:image/png;base64,' + base64.b64encode(open(png, "rb").read()).decode() + '"' in html, png
PY
  grep -q '<div class="wide"><table>' "$work/plots/report.html" || fail "tables not kept within the page"
  # the time series of the runs: kinetic energy and the mass in the sensor over time
  [[ -s "$work/plots/cup-pour-series-cup.mass.png" && -s "$work/plots/cup-pour-series-kinetic_energy_per_particle.png" ]] ||
    fail "time series not drawn: $(ls "$work/plots")"
  grep -q '<h3>Time series</h3>' "$work/plots/report.html" || fail "no time series section"
  # each run's last frame: drawn by the build's Python package, or the page says why not
  grep -q '<h3>Last frames</h3>' "$work/plots/report.html" || fail "no last frames section"
  if [[ -f "$(dirname "$bushel")/../python/bushel/pictures.py" ]]; then
    [[ -s "$work/plots/cup-pour-frame-cup_pour.png" && -s "$work/plots/calibration-cup-frame-cup_stop.png" ]] ||
      fail "last frames not drawn: $(ls "$work/plots")"
  else
    grep -q "The last frames are not drawn: this build of bushel has no Python package" "$work/plots/report.html" ||
      fail "no word on the frames not drawn"
  fi
fi

# Bad input: one line naming what was wrong.
check_error() {
  local want=$1; shift
  if err=$("$bushel" "$@" 2>&1 >/dev/null); then fail "expected an error from: $*"; fi
  [[ $(printf '%s\n' "$err" | wc -l) -eq 1 ]] || fail "not one line: $err"
  [[ $err == *"$want"* ]] || fail "expected '$want' in: $err"
}
check_error "nothing: no such run folder" report "$work/nothing" --out "$work/x"
check_error "no summary.json here nor in its sub-folders" report "$work/rep" --out "$work/x"
check_error "key '--curve': expected X:Y" report "$cup" --curve pressure --out "$work/x"
printf 'result,value,unit,source\nbulk_density,800,kg/m4,lab\n' > "$work/refs.csv"
check_error "refs.csv:2: key 'value'" report "$cup" --reference "$work/refs.csv" --out "$work/x"
echo "report check passed"
