#!/usr/bin/env bash
# The test command of the README and of CI: installs the Debian dependencies if any are
# missing, then configures, builds and runs the whole test suite twice: an optimised build,
# and a build under AddressSanitizer + UndefinedBehaviorSanitizer; then runs each fuzz target
# for 30 s (clang, tests/fuzz/run.sh).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/setup.sh --deps
cmake --workflow --preset release
cmake --workflow --preset asan
# The libFuzzer targets, briefly (docs/fuzzing.md): a crash, leak or hang fails the run.
# (a fixed seed, so that a failure here replays; checkpoints with broken checksums only: a
# forged checksum reaches readers that still trust some fields, docs/fuzzing.md)
FUZZ_FLAGS=-seed=1 BUSHEL_FUZZ_RESEAL=0 tests/fuzz/run.sh 30
