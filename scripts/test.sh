#!/usr/bin/env bash
# The test command of the README and of CI: installs the Debian dependencies if any are
# missing, then configures, builds and runs the whole test suite twice: an optimised build,
# and a build under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/setup.sh --deps
cmake --workflow --preset release
cmake --workflow --preset asan
