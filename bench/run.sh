#!/usr/bin/env bash
# Runs the benchmarks of the release build and leaves a CSV in bench/results/, named by
# date, commit and host, with the machine described in its first lines.
#   bench/run.sh [extra Google Benchmark flags, e.g. --benchmark_filter=Asg]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null
mkdir -p bench/results
out="bench/results/$(date -u +%Y%m%dT%H%M%SZ)-$(git rev-parse --short HEAD 2>/dev/null || echo nogit)-$(hostname).csv"
{
  echo "# machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(free -g | awk '/Mem:/{print $2}') GiB"
  echo "# commit: $(git rev-parse HEAD 2>/dev/null || echo none)"
} >"$out"
build/release/bin/bench_templates --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_out="$out.tmp" --benchmark_out_format=csv "$@"
sed -n '/^name,/,$p' "$out.tmp" >>"$out" && rm -f "$out.tmp"
echo "wrote $out"
