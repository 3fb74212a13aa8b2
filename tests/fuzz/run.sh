#!/usr/bin/env bash
# Runs bushel's libFuzzer targets (docs/fuzzing.md): configures and builds the "fuzz" preset
# if needed (build/fuzz), then runs each target for SECONDS seconds on a fresh copy of its
# seed corpus (tests/fuzz/corpus/<target>/, plus its saved reproducers in
# tests/fuzz/regressions/<target>/). Exits non-zero if any target finds a crash, a leak, a
# sanitizer report, a hang over 10 s or an input that needs over 2 GB, and says where the
# reproducer is.
#
#   tests/fuzz/run.sh                 every target, 60 s each
#   tests/fuzz/run.sh 600             every target, 10 minutes each
#   tests/fuzz/run.sh 30 stl scenario two targets, 30 s each
#
# Targets: scenario expression template_csv stl checkpoint. Each run's corpus, log and
# artifacts are in build/fuzz/runs/<target>/. Extra libFuzzer flags: FUZZ_FLAGS="-jobs=2".
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"

all=(scenario expression template_csv stl checkpoint)
seconds=${1:-60}
[[ $seconds =~ ^[0-9]+$ ]] || { echo "usage: tests/fuzz/run.sh [SECONDS] [TARGET...]" >&2; exit 2; }
shift $(($# > 0 ? 1 : 0))
targets=("$@")
((${#targets[@]})) || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "run.sh: unknown target '$t' (known: ${all[*]})" >&2; exit 2; }
done

# The longest input each target is given [bytes]: the largest shipped scenario is 15 KB,
# the seed checkpoint about 40 KB.
declare -A max_len=([scenario]=32768 [expression]=512 [template_csv]=8192 [stl]=8192 [checkpoint]=131072)

build=build/fuzz
start=$SECONDS
[[ -f $build/build.ninja ]] || cmake --preset fuzz
cmake --build --preset fuzz
echo "run.sh: build ready in $((SECONDS - start)) s"

# (stack traces with files and lines: the symbolizer of the clang that built the targets)
symbolizer=$(command -v llvm-symbolizer-16 || command -v llvm-symbolizer || true)
[[ -z $symbolizer ]] || export ASAN_SYMBOLIZER_PATH=$symbolizer
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
failed=()
for t in "${targets[@]}"; do
  work=$build/runs/$t
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts" "$work/tmp"
  for seeds in tests/fuzz/corpus/"$t" tests/fuzz/regressions/"$t"; do
    if compgen -G "$seeds/*" >/dev/null; then cp "$seeds"/* "$work/corpus/"; fi
  done
  echo "run.sh: $t for $seconds s (log: $work/fuzz.log)"
  rc=0
  # (the checkpoint target writes the seed made by this build into the corpus, and its runs'
  # folders into TMPDIR, which libFuzzer's exit leaves behind: checkpoint_fuzz.cpp)
  TMPDIR=$root/$work/tmp BUSHEL_FUZZ_SEED_DIR=$root/$work/corpus \
    "$build/fuzz/${t}_fuzz" -max_total_time="$seconds" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$work/artifacts/" -print_final_stats=1 ${FUZZ_FLAGS:-} "$work/corpus" >"$work/fuzz.log" 2>&1 || rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/fuzz.log" | tail -1)
  corpus=$(find "$work/corpus" -type f | wc -l)
  artifacts=$(find "$work/artifacts" -type f | sort)
  if ((rc != 0)) || [[ -n $artifacts ]]; then
    failed+=("$t")
    echo "run.sh: $t FAILED (exit $rc) after ${runs:-?} executions; the end of its log:"
    grep -E "^==[0-9]+==|^SUMMARY|ERROR|runtime error|fuzz check failed|#[0-9]+ 0x" "$work/fuzz.log" | head -40 || true
    tail -5 "$work/fuzz.log"
    for a in $artifacts; do
      echo "run.sh: reproducer: $a"
      echo "        replay:    $build/fuzz/${t}_fuzz $a"
      echo "        minimise:  $build/fuzz/${t}_fuzz -minimize_crash=1 -max_total_time=60 -artifact_prefix=$work/artifacts/min- $a"
      echo "        then keep it: cp <minimised> tests/fuzz/regressions/$t/ (replayed by unit_tests, FuzzRegression.*)"
    done
    [[ -n $artifacts ]] || echo "run.sh: no reproducer written; see $work/fuzz.log"
  else
    echo "run.sh: $t ok: ${runs:-?} executions in $seconds s, corpus $corpus inputs"
  fi
done

echo "run.sh: done in $((SECONDS - start)) s"
if ((${#failed[@]})); then
  echo "run.sh: failed: ${failed[*]}" >&2
  exit 1
fi
