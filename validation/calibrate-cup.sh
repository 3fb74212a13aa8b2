#!/usr/bin/env bash
# The study's calibration loop (wheat.md, "Calibration by design of experiments") on a reduced
# calibration cup, in one command: a Plackett-Burman screening of the six contact parameters,
# a face-centred central composite design over the significant ones (the others at the centre
# of their ranges), a quadratic fit, the settings that give the target bulk density, and
# validation runs at those settings (two seeds) against the model's prediction interval.
#
#   validation/calibrate-cup.sh [OUT]     # default runs/calibration
#
# Environment: TARGET (kg/m3, default 826.1: the study's large fraction), JOBS (runs at a time,
# default 2), ALPHA (screening significance, default 0.1), BUSHEL (the program), REDUCED (the
# scenario overrides of the reduced cup). Each campaign resumes where it stopped, so the
# command can be run again after an interruption; finished steps are kept. About 40 runs of
# about a minute each on 2 cores with the default reduced cup. Writes OUT/calibration.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bushel="${BUSHEL:-$root/build/release/bin/bushel}"
out="${1:-$root/runs/calibration}"
target="${TARGET:-826.1}" jobs="${JOBS:-2}" alpha="${ALPHA:-0.1}"
scenario="$root/scenarios/calibration-cup.yaml"
# The reduced cup of validation/experiments-smoke.py (80 g into a 25 mm high cup, single spheres).
read -r -a reduced <<< "${REDUCED:-parameters.mass=80g parameters.cup_height=25mm parameters.model=1s parameters.frame_interval=10s}"
sets=(); for s in "${reduced[@]}"; do sets+=(--set "$s"); done
# The study's screening levels (wheat.md).
declare -A low=([fr_ww]=0 [fr_ws]=0.02 [fs_ww]=0.10 [fs_ws]=0.17 [e_ww]=0.30 [e_ws]=0.30)
declare -A high=([fr_ww]=0.10 [fr_ws]=0.10 [fs_ww]=0.40 [fs_ws]=0.40 [e_ww]=0.60 [e_ws]=0.60)
all=(fr_ww fr_ws fs_ww fs_ws e_ww e_ws)
levels() { local f s=""; for f in "$@"; do s+="${s:+,}$f=${low[$f]}:${high[$f]}"; done; echo "$s"; }
mkdir -p "$out/screen" "$out/rsm" "$out/validate"

echo "== 1. screening: Plackett-Burman, 12 runs, 6 factors"
[ -f "$out/screen/design.csv" ] || "$bushel" doe design pb --factors "$(levels "${all[@]}")" --seed 1 --out "$out/screen/design.csv"
"$bushel" doe run "$out/screen/design.csv" --out "$out/screen/campaign" --scenario "$scenario" "${sets[@]}" \
  --response bulk_density --jobs "$jobs"
"$bushel" doe analyze "$out/screen/campaign/results.csv" --factors "$(IFS=,; echo "${all[*]}")" \
  --response bulk_density --alpha "$alpha" --out "$out/screen/analysis"
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
[ -f "$out/rsm/design.csv" ] || "$bushel" doe design ccd --factors "$(levels "${kept[@]}")" --ccd face --center 3 \
  --seed 2 --out "$out/rsm/design.csv"
"$bushel" doe run "$out/rsm/design.csv" --out "$out/rsm/campaign" --scenario "$scenario" "${sets[@]}" "${fixed[@]}" \
  --response bulk_density --jobs "$jobs"
factors="$(IFS=,; echo "${kept[*]}")"
"$bushel" doe analyze "$out/rsm/campaign/results.csv" --factors "$factors" --response bulk_density \
  --model quadratic --out "$out/rsm/analysis"

echo "== 3. the settings that give $target kg/m3"
"$bushel" doe optimize "$out/rsm/campaign/results.csv" --factors "$factors" --response bulk_density \
  --model quadratic --target "$target" --json > "$out/optimum.json"
optimum=()
while read -r kv; do optimum+=(--set "parameters.$kv"); done < <(/usr/bin/python3 -c "
import json; [print(f'{k}={v:.6g}') for k, v in json.load(open('$out/optimum.json'))['settings'].items()]")

echo "== 4. validation at the optimum (seeds 1 and 2)"
for seed in 1 2; do
  dir="$out/validate/seed-$seed"
  grep -qs '"interrupted": false' "$dir/summary.json" || "$bushel" run "$scenario" --out "$dir" --quiet "${sets[@]}" \
    "${fixed[@]}" "${optimum[@]}" --set "parameters.seed=$seed" > /dev/null
done

/usr/bin/python3 - "$out" "$target" "${kept[*]}" "${fixed[*]}" <<'EOF' | tee "$out/calibration.md"
import json, sys, os
out, target, kept, fixed = sys.argv[1], float(sys.argv[2]), sys.argv[3].split(), sys.argv[4]
screen = json.load(open(os.path.join(out, "screen/analysis/analysis.json")))
rsm = json.load(open(os.path.join(out, "rsm/analysis/analysis.json")))
opt = json.load(open(os.path.join(out, "optimum.json")))
val = [json.load(open(os.path.join(out, f"validate/seed-{s}/summary.json")))["results"]["bulk_density"]["value"]
       for s in (1, 2)]
print(f"# Calibration of the reduced calibration cup to {target} kg/m3\n")
print("## Screening (Plackett-Burman, 12 runs)\n\n| term | effect [kg/m3] | t | p | significant |\n|---|---|---|---|---|")
for t in screen["terms"]:
    if t["term"] != "Constant":
        print(f"| {t['term']} | {t['effect']:.2f} | {t['t']:.2f} | {t['p']:.3f} | {'yes' if t['significant'] else ''} |")
print(f"\nKept for the response surface: {', '.join(kept)}. Fixed: {fixed.replace('--set parameters.', '') or 'none'}.\n")
print(f"## Response surface (face-centred CCD, {rsm['runs']} runs, quadratic)\n")
print(f"R2 {rsm['r2']:.4f}, adjusted R2 {rsm['r2_adjusted']:.4f}, predicted R2 {rsm['r2_predicted']:.4f}\n")
print("## Optimum and validation\n")
print("| factor | setting |\n|---|---|")
for k, v in opt["settings"].items():
    print(f"| {k} | {v:.4g} |")
lo, hi = opt["prediction_interval_95"]
mean = sum(val) / len(val)
print(f"\npredicted {opt['predicted']:.1f} kg/m3 (95% prediction interval {lo:.1f} to {hi:.1f}); "
      f"validation runs {val[0]:.1f} and {val[1]:.1f} kg/m3, mean {mean:.1f} ({100 * (mean - target) / target:+.2f} % "
      f"from the target); {'inside' if lo <= mean <= hi else 'outside'} the prediction interval")
EOF
