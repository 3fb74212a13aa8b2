#!/usr/bin/env bash
# The funnel as the cone primitive and as an STL of the same cone (96 facets around) must
# discharge alike: same mass flow and same discharged mass at fixed times, within the
# seed-to-seed noise. Runs `bushel demo funnel` for several seeds each and prints a table;
# writes validation/results/funnel-cone-vs-stl-<time>/results.csv.
#
# usage: validation/funnel-cone-vs-stl.sh [COUNT] [SEEDS] [OUTLET]   (defaults 2000 4 22mm)
set -euo pipefail
COUNT=${1:-2000}; SEEDS=${2:-4}; OUTLET=${3:-22mm}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cmake --preset release >/dev/null && cmake --build --preset release --target bushel_cli >/dev/null
out="validation/results/funnel-cone-vs-stl-$(date -u +%Y%m%dT%H%M%SZ)"
mkdir -p "$out"
bin=build/release/bin/bushel
common=(demo funnel --count "$COUNT" --outlet "$OUTLET" --gate-open 0.4s --time 1.4s --frame 0.05s)
"$bin" demo funnel --count 1 --outlet "$OUTLET" --time 0.001s --write-stl "$out/funnel.stl" --json >/dev/null 2>&1
echo "funnel,seed,mass_flow_kg_s,discharged_at_0.6s_kg,discharged_at_0.8s_kg,discharged_end_kg" >"$out/results.csv"
for seed in $(seq 1 "$SEEDS"); do
  for funnel in cone stl; do
    extra=(); [[ $funnel == stl ]] && extra=(--stl "$out/funnel.stl")
    dir="$out/$funnel-$seed"
    "$bin" "${common[@]}" --seed "$seed" "${extra[@]}" --out "$dir" --json >"$dir.json" 2>/dev/null
    python3 - "$funnel" "$seed" "$dir" >>"$out/results.csv" <<'PY'
import csv, json, sys
funnel, seed, d = sys.argv[1:4]
s = json.load(open(d + ".json"))
rows = list(csv.DictReader(open(d + "/discharge.csv")))
at = lambda t: min(rows, key=lambda r: abs(float(r["time_s"]) - t))["discharged_kg"]
print("%s,%s,%.6g,%s,%s,%.6g" % (funnel, seed, s["mass_flow_kg_s"], at(0.6), at(0.8), s["discharged_mass_kg"]))
PY
    rm -rf "$dir"
  done
done
python3 - "$out/results.csv" <<'PY'
import csv, statistics as st, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cols = ["mass_flow_kg_s", "discharged_at_0.6s_kg", "discharged_at_0.8s_kg", "discharged_end_kg"]
print("%-24s %22s %22s %10s" % ("quantity", "cone mean (sd)", "stl mean (sd)", "diff/sd"))
for c in cols:
    a = [float(r[c]) for r in rows if r["funnel"] == "cone"]
    b = [float(r[c]) for r in rows if r["funnel"] == "stl"]
    sd = (st.stdev(a) + st.stdev(b)) / 2 if len(a) > 1 else 0.0
    diff = st.mean(b) - st.mean(a)
    print("%-24s %12.5g (%7.2g) %12.5g (%7.2g) %10.2f" % (c, st.mean(a), st.stdev(a) if len(a) > 1 else 0,
          st.mean(b), st.stdev(b) if len(b) > 1 else 0, diff / sd if sd > 0 else 0.0))
PY
echo "results: $out/results.csv"
