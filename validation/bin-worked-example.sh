#!/usr/bin/env bash
# The worked example of docs/bins.md from start to end: the mass of wheat in a 30 ft bin filled
# to 24 ft at the wall and peaked at 25 degrees, from two simulations of the grain.
#
#   validation/bin-worked-example.sh [OUT]     # default runs/bin-example
#
#   1. drop         experiment 2 (scenarios/test-weight.yaml): the grain falls DROP (default
#                   163.2 cm, the study's largest, 32 x 5.1 cm) into the kettle; its bulk
#                   density in the kettle before striking (result bulk_density_sensor) stands
#                   for the uncompacted density of grain that has fallen into a bin.
#   2. compression  experiment 3 (scenarios/compression.yaml): the bulk density of the struck
#                   sample and under the lid at 7, 21, 34, 48, 69, 103 and 138 kPa.
#   3. the bin      `bushel bin` with D_o from 1 and D(P)/D(0) from 2; then the same bin
#                   without compaction, and from the standard test weight, to compare.
#
# By default the vessels are reduced (REDUCED=1: a 60 cm3 kettle, a 30 mm high cylinder;
# single-sphere kernels with the study's large-fraction parameters), about 20 minutes on 2
# cores; REDUCED=0 runs the full-size vessels with the scenarios' own settings (hours: run it
# in the background, it resumes). A run that was stopped goes on from its checkpoint when the
# script is run again; finished runs are kept. Environment: BUSHEL (the program), DROP.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bushel="${BUSHEL:-$root/build/release/bin/bushel}"
source "$root/validation/resume.sh"
out="${1:-$root/runs/bin-example}"
drop="${DROP:-163.2cm}"
mkdir -p "$out"

sphere=(model=1s fr_ww=0.05 fs_ww=0.172 e_ww=0.5)  # docs/wheat.md: large-large, 1 sphere
if [ "${REDUCED:-1}" = 1 ]; then
  drop_sets=(mass=150g kettle_volume=60cm3 kettle_diameter=50mm hopper_top=100mm hopper_outlet=25mm
             striker_length=90mm frame_interval=1s "${sphere[@]}")
  compression_sets=(mass=120g height=30mm frame_interval=1s "${sphere[@]}")
else
  drop_sets=() compression_sets=()
fi

# simulate NAME SCENARIO OVERRIDES...: run (or resume, or keep) $out/NAME.
simulate() {
  local name="$1" scenario="$2" sets=() p
  shift 2
  for p in "$@"; do sets+=(--set "parameters.$p"); done
  run_or_resume "== $name" "$out/$name" "$root/scenarios/$scenario" ${sets[@]+"${sets[@]}"}
}

simulate drop test-weight.yaml "drop=$drop" ${drop_sets[@]+"${drop_sets[@]}"}
simulate compression compression.yaml ${compression_sets[@]+"${compression_sets[@]}"}

bin=(--diameter 30ft --grain-height 24ft --surcharge peaked --repose-angle 25deg)
echo "== the bin, from the simulations: D_o = the drop run's bulk density, D(P) from the compression run"
"$bushel" bin "${bin[@]}" --initial-density "$out/drop:bulk_density_sensor" --compressibility "$out/compression" \
  --csv "$out/bin.csv" --plot "$out/bin.png" | tee "$out/bin.txt"
"$bushel" bin "${bin[@]}" --initial-density "$out/drop:bulk_density_sensor" --compressibility "$out/compression" \
  --json > "$out/bin.json"
echo "== the same bin without compaction"
"$bushel" bin "${bin[@]}" --initial-density "$out/drop:bulk_density_sensor" --incompressible \
  --json > "$out/bin-incompressible.json"
echo "== the same bin from the standard test weight (60 lb/bu) and the same compaction"
"$bushel" bin "${bin[@]}" --test-weight 60lb/bu --compressibility "$out/compression" --json > "$out/bin-test-weight.json"
"$bushel" report "$out/drop" "$out/compression" --out "$out/report" --title "Bin worked example: the simulations" \
  > /dev/null

/usr/bin/python3 - "$out" <<'EOF' | tee "$out/summary.md"
import json, os, sys
out = sys.argv[1]
load = lambda name: json.load(open(os.path.join(out, name)))
drop, comp = load("drop/summary.json"), load("compression/summary.json")
r = lambda run, k: run["results"][k]["value"]
print("| step | result |\n|---|---|")
print(f"| drop of {drop['parameters']['drop']} | bulk density in the kettle "
      f"{r(drop, 'bulk_density_sensor'):.1f} kg/m3 (struck: {r(drop, 'bulk_density'):.1f}) |")
levels = sorted((int(k.split("_")[-1]) for k in comp["results"] if k.startswith("pressure_")))
curve = ", ".join(f"{r(comp, f'pressure_{k}') / 1000:.0f} kPa: {r(comp, f'bulk_density_{k}'):.1f}" for k in levels)
print(f"| compression | {curve} kg/m3 |")
for name, what in (("bin.json", "bin, D_o from the drop, compacting"), ("bin-incompressible.json", "bin, no compaction"),
                   ("bin-test-weight.json", "bin, D_o = 60 lb/bu, compacting")):
    b = load(name)
    print(f"| {what} | {b['mass_kg'] / 1000:.1f} t, average {b['average_density_kg_m3']:.1f} kg/m3, "
          f"packing ratio {b['packing_ratio']:.4f}, pack factor {b['pack_factor']:.4f}, "
          f"{b['standard_bushels']:.0f} standard bu, bottom {b['bottom_pressure_Pa'] / 1000:.1f} kPa |")
EOF
