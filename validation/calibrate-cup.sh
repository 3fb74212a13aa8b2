#!/usr/bin/env bash
# The study's calibration loop (docs/wheat.md, "Calibration by design of experiments") on a reduced
# calibration cup, in one command: a Plackett-Burman screening of the six contact parameters,
# a face-centred central composite design over the significant ones (the others at the centre
# of their ranges), a quadratic fit, the settings that give the target bulk density, and
# validation runs at those settings (two seeds) against the model's prediction interval.
# Every run packs from its own seed (the design's std_order), so that replicated centre points
# measure the packing's scatter. A run whose cup did not fill (less than MIN_OVERFLOW spilled
# over its rim: the funnel clogged, as the study saw at high friction) has no bulk density of a
# full cup; it is left out of the fits and listed in calibration.md.
#
#   validation/calibrate-cup.sh [OUT]     # default runs/calibration
#
# Environment: TARGET (kg/m3, default 826.1: the study's large fraction), JOBS (runs at a time,
# default 2), ALPHA (screening significance, default 0.1), MIN_OVERFLOW (kg, default 0.001),
# BUSHEL (the program), REDUCED (the scenario overrides of the reduced cup). Each campaign resumes where it stopped, so the
# command can be run again after an interruption; finished steps are kept. About 40 runs of
# about a minute each on 2 cores with the default reduced cup. Writes OUT/calibration.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bushel="${BUSHEL:-$root/build/release/bin/bushel}"
source "$root/validation/resume.sh"
out="${1:-$root/runs/calibration}"
target="${TARGET:-826.1}" jobs="${JOBS:-2}" alpha="${ALPHA:-0.1}" min_overflow="${MIN_OVERFLOW:-0.001}"
scenario="$root/scenarios/calibration-cup.yaml"
# The reduced cup of validation/experiments-smoke.py (80 g into a 25 mm high cup, single spheres).
read -r -a reduced <<< "${REDUCED:-parameters.mass=80g parameters.cup_height=25mm parameters.model=1s parameters.frame_interval=10s}"
sets=(); for s in "${reduced[@]}"; do sets+=(--set "$s"); done
# The study's screening levels (docs/wheat.md).
declare -A low=([fr_ww]=0 [fr_ws]=0.02 [fs_ww]=0.10 [fs_ws]=0.17 [e_ww]=0.30 [e_ws]=0.30)
declare -A high=([fr_ww]=0.10 [fr_ws]=0.10 [fs_ww]=0.40 [fs_ws]=0.40 [e_ww]=0.60 [e_ws]=0.60)
all=(fr_ww fr_ws fs_ww fs_ws e_ww e_ws)
levels() { local f s=""; for f in "$@"; do s+="${s:+,}$f=${low[$f]}:${high[$f]}"; done; echo "$s"; }
mkdir -p "$out/screen" "$out/rsm" "$out/validate"
# design DIR SEED_OFFSET ARGS...: the design, with a seed column (SEED_OFFSET + std_order) that
# the campaign passes to the scenario like the factors.
design() {
  local dir="$1" offset="$2"; shift 2
  [ -f "$dir/design.csv" ] && return
  "$bushel" doe design "$@" --out "$dir/design.tmp"
  /usr/bin/python3 - "$dir/design.tmp" "$offset" <<'EOF'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
rows[0].append("seed")
for r in rows[1:]:
    r.append(str(int(sys.argv[2]) + int(r[0])))
csv.writer(open(sys.argv[1], "w", newline=""), lineterminator="\n").writerows(rows)
EOF
  mv "$dir/design.tmp" "$dir/design.csv"
}
responses=bulk_density,overflow_mass,retained_mass
filled="overflow_mass>=$min_overflow"

echo "== 1. screening: Plackett-Burman, 12 runs, 6 factors"
design "$out/screen" 0 pb --factors "$(levels "${all[@]}")" --seed 1
"$bushel" doe run "$out/screen/design.csv" --out "$out/screen/campaign" --scenario "$scenario" "${sets[@]}" \
  --response "$responses" --jobs "$jobs"
"$bushel" doe analyze "$out/screen/campaign/results.csv" --factors "$(IFS=,; echo "${all[*]}")" \
  --levels "$(levels "${all[@]}")" --where "$filled" --response bulk_density --alpha "$alpha" --out "$out/screen/analysis"
# The significant factors (at most 4, by |t|; at least the 2 strongest).
read -r -a kept <<< "$(/usr/bin/python3 - "$out/screen/analysis/analysis.json" <<'EOF'
import json, sys
terms = [t for t in json.load(open(sys.argv[1]))["terms"] if t["term"] != "Constant"]
terms.sort(key=lambda t: -abs(t["t"]))
kept = [t["term"] for t in terms if t["significant"]][:4]
for t in terms[:2]:
    if t["term"] not in kept: kept.append(t["term"])
print(" ".join(kept))
EOF
)"
fixed=()
for f in "${all[@]}"; do
  [[ " ${kept[*]} " == *" $f "* ]] || fixed+=(--set "parameters.$f=$(/usr/bin/python3 -c "print(round((${low[$f]} + ${high[$f]}) / 2, 6))")")
done
echo "   kept: ${kept[*]}; the others at the centre of their ranges"

echo "== 2. response surface: face-centred central composite over ${kept[*]}"
design "$out/rsm" 100 ccd --factors "$(levels "${kept[@]}")" --ccd face --center 3 --seed 2
"$bushel" doe run "$out/rsm/design.csv" --out "$out/rsm/campaign" --scenario "$scenario" "${sets[@]}" "${fixed[@]}" \
  --response "$responses" --jobs "$jobs"
factors="$(IFS=,; echo "${kept[*]}")"
"$bushel" doe analyze "$out/rsm/campaign/results.csv" --factors "$factors" --levels "$(levels "${kept[@]}")" \
  --where "$filled" --response bulk_density --model quadratic --out "$out/rsm/analysis"

echo "== 3. the settings that give $target kg/m3"
"$bushel" doe optimize "$out/rsm/campaign/results.csv" --factors "$factors" --levels "$(levels "${kept[@]}")" \
  --where "$filled" --response bulk_density --model quadratic --target "$target" --json > "$out/optimum.json"
optimum=()
while read -r kv; do optimum+=(--set "parameters.$kv"); done < <(/usr/bin/python3 -c "
import json; [print(f'{k}={v:.6g}') for k, v in json.load(open('$out/optimum.json'))['settings'].items()]")

echo "== 4. validation at the optimum (seeds 1 and 2)"
for seed in 1 2; do
  dir="$out/validate/seed-$seed"
  run_or_resume "seed $seed" "$dir" "$scenario" --quiet "${sets[@]}" "${fixed[@]}" "${optimum[@]}" \
    --set "parameters.seed=$seed" > /dev/null
done

/usr/bin/python3 - "$out" "$target" "${kept[*]}" "${fixed[*]}" "$min_overflow" <<'EOF' | tee "$out/calibration.md"
import csv, json, sys, os
out, target, kept, fixed, min_overflow = sys.argv[1], float(sys.argv[2]), sys.argv[3].split(), sys.argv[4], float(sys.argv[5])
load = lambda *p: json.load(open(os.path.join(out, *p)))
screen, rsm, opt = load("screen/analysis/analysis.json"), load("rsm/analysis/analysis.json"), load("optimum.json")
val = [load(f"validate/seed-{s}/summary.json")["results"] for s in (1, 2)]

def left_out(step, factors):
    """The runs of a campaign whose cup did not fill (or that failed), as a Markdown table."""
    rows = [r for r in csv.DictReader(open(os.path.join(out, step, "campaign/results.csv")))
            if not r["overflow_mass"] or float(r["overflow_mass"]) < min_overflow]
    if not rows:
        return "Every run filled its cup.\n"
    text = (f"Left out of the fit: {len(rows)} run(s) whose cup did not fill (less than {1000 * min_overflow:g} g "
            "spilled over the rim), the grain held up in the funnel:\n\n| run | " + " | ".join(factors) +
            " | bulk density [kg/m3] | left in the funnel [g] | status |\n" + "|---" * (len(factors) + 4) + "|\n")
    for r in rows:
        g = lambda k: f"{float(r[k]):.1f}" if r[k] else ""
        grams = f"{1000 * float(r['retained_mass']):.1f}" if r["retained_mass"] else ""
        text += f"| {r['std_order']} | " + " | ".join(r[f] for f in factors) + f" | {g('bulk_density')} | {grams} | {r['status']} |\n"
    return text

print(f"# Calibration of the reduced calibration cup to {target} kg/m3\n")
print(f"## Screening (Plackett-Burman, 12 runs, {screen['runs']} fitted)\n")
print(left_out("screen", [f["name"] for f in screen["factors"]]))
print("| term | effect [kg/m3] | t | p | significant |\n|---|---|---|---|---|")
for t in screen["terms"]:
    if t["term"] != "Constant":
        print(f"| {t['term']} | {t['effect']:.2f} | {t['t']:.2f} | {t['p']:.3f} | {'yes' if t['significant'] else ''} |")
print(f"\nR2 {screen['r2']:.4f}. Kept for the response surface: {', '.join(kept)}. "
      f"Fixed: {fixed.replace('--set parameters.', '') or 'none'}.\n")
print(f"## Response surface (face-centred CCD, {rsm['runs']} runs fitted, quadratic)\n")
print(left_out("rsm", kept))
# (predicted R2 is undefined, null, where a run has leverage 1: left out, nothing predicts it)
r2_predicted = "undefined" if rsm["r2_predicted"] is None else f"{rsm['r2_predicted']:.4f}"
print(f"R2 {rsm['r2']:.4f}, adjusted R2 {rsm['r2_adjusted']:.4f}, predicted R2 {r2_predicted}, "
      f"S {rsm['s']:.2f} kg/m3\n")
print("| source | DF | adj SS | F | p |\n|---|---|---|---|---|")
for a in rsm["anova"]:
    f = lambda v, fmt: format(v, fmt) if v is not None else ""
    print(f"| {a['source']} | {a['df']:g} | {a['ss']:.1f} | {f(a['f'], '.2f')} | {f(a['p'], '.3f')} |")
print("\n## Optimum and validation\n")
print("| factor | setting |\n|---|---|")
for k, v in opt["settings"].items():
    print(f"| {k} | {v:.4g} |")
lo, hi = opt["prediction_interval_95"]
bd = [v["bulk_density"]["value"] for v in val]
mean = sum(bd) / len(bd)
filled = all((v["overflow_mass"]["value"] or 0) >= min_overflow for v in val)
print(f"\npredicted {opt['predicted']:.1f} kg/m3 (95% prediction interval {lo:.1f} to {hi:.1f}); "
      f"validation runs (seeds 1 and 2) {bd[0]:.1f} and {bd[1]:.1f} kg/m3, mean {mean:.1f} "
      f"({100 * (mean - target) / target:+.2f} % from the target); {'inside' if lo <= mean <= hi else 'outside'} "
      f"the prediction interval; {'both cups filled' if filled else 'a validation cup did not fill'}")
EOF
