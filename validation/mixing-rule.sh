#!/usr/bin/env bash
# Whether the single-sphere model's pair rule makes its mixtures pack looser than their ideal
# mixture. The calibrated single-sphere sets are per pair of fractions: a pair of unlike kernels
# takes the smaller one's set (docs/wheat.md), whose static friction (0.486) is about three
# times the large kernels' own (0.172). On a reduced test weight (0.25 kg from h into a kettle
# of 250 cm3 and 60 mm, struck, as the study's time-step cases), five runs: the large fraction
# alone; and the medium fraction alone and a mixture of 80 % large and 20 % medium by mass, each
# with the calibrated pair rule and with the large kernels' set for every pair. The mixing
# excess of a rule: the mixture's struck density over the ideal mixture of the two fractions
# alone under the same rule (their specific volumes added by mass).
#
#   validation/mixing-rule.sh [OUT]     # default runs/validation/mixing-rule; prints the table
#
# About 0.4 h per run; JOBS runs at a time (default 2), one thread each. As the study's cases
# (validation/resume.sh, run_or_resume): a finished run is kept, an interrupted one continues
# from its checkpoint, by the same engine build only (its log, OUT/CASE.log, says so). BUSHEL:
# the build (default build/release/bin/bushel), of a committed tree.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bushel="${BUSHEL:-$root/build/release/bin/bushel}"
out="${1:-$root/runs/validation/mixing-rule}"
jobs="${JOBS:-2}"
source "$root/validation/resume.sh"  # (run_or_resume, set_args)
ONE_BUILD=1

reduced="model=1s mass=0.25kg kettle_volume=250cm3 kettle_diameter=60mm drop=5.1cm share_small=0%"
large="fr_ww=0.05 fs_ww=0.172 e_ww=0.5"  # the large pairs' set (docs/wheat.md)
declare -A rule=([pair]="$large fr_wm=0.05 fs_wm=0.486 e_wm=0.1" [uniform]="$large fr_wm=0.05 fs_wm=0.172 e_wm=0.5")
declare -A sets=(
  [large]="$reduced ${rule[pair]} share_large=100% share_medium=0%"
  [medium-pair]="$reduced ${rule[pair]} share_large=0% share_medium=100%"
  [medium-uniform]="$reduced ${rule[uniform]} share_large=0% share_medium=100%"
  [mix-pair]="$reduced ${rule[pair]} share_large=80% share_medium=20%"
  [mix-uniform]="$reduced ${rule[uniform]} share_large=80% share_medium=20%"
)

run_one() {  # run_one CASE
  local c=$1 args=(--quiet)
  # shellcheck disable=SC2086  # (the overrides split into words on purpose)
  set_args ${sets[$c]}
  OMP_NUM_THREADS=1 run_or_resume "$c" "$out/$c" "$root/scenarios/test-weight.yaml" "${args[@]}" \
    >> "$out/$c.log" 2>&1 || { echo "mixing-rule.sh: $c did not finish (log: $out/$c.log)" >&2; return 1; }
}

mkdir -p "$out"
pids=()
for c in large medium-pair medium-uniform mix-pair mix-uniform; do
  while (( $(jobs -rp | wc -l) >= jobs )); do wait -n; done
  run_one "$c" &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p"; done

/usr/bin/python3 - "$out" <<'EOF'
import json, os, sys
out = sys.argv[1]
rho = {}
for c in ("large", "medium-pair", "medium-uniform", "mix-pair", "mix-uniform"):
    with open(os.path.join(out, c, "summary.json")) as f:
        rho[c] = json.load(f)["results"]["bulk_density"]["value"]
print("| rule | large alone [kg/m3] | medium alone [kg/m3] | 80 / 20 mixture [kg/m3] | ideal mixture [kg/m3] | mixing excess |")
print("|---|---|---|---|---|---|")
for r in ("pair", "uniform"):
    ideal = 1 / (0.8 / rho["large"] + 0.2 / rho["medium-" + r])
    print(f"| {r} | {rho['large']:.1f} | {rho['medium-' + r]:.1f} | {rho['mix-' + r]:.1f} | {ideal:.1f} "
          f"| {100 * (rho['mix-' + r] / ideal - 1):+.2f} % |")
EOF
