#!/usr/bin/env bash
# Installs every dependency of bushel from Debian 12 packages, then configures and
# builds the release preset. Idempotent: packages already present are not reinstalled,
# and an existing build tree is reused.
#
#   scripts/setup.sh            install dependencies, configure and build (release)
#   scripts/setup.sh --deps     install dependencies only
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

# One list, kept in step with ARCHITECTURE.md ("Dependencies"). clang 16 (not Debian's default
# clang 14, which cannot capture structured bindings in lambdas) builds the fuzz targets
# (tests/fuzz, docs/fuzzing.md); llvm-16 gives their stack traces files and lines.
packages=(
  build-essential cmake ninja-build pkg-config git
  libyaml-cpp-dev libcli11-dev libeigen3-dev nlohmann-json3-dev libfmt-dev libxxhash-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev libomp-dev libopenmpi-dev openmpi-bin
  python3 python3-dev pybind11-dev python3-numpy python3-matplotlib python3-yaml python3-pandas
  python3-scipy python3-sklearn
  jupyter-nbconvert python3-nbclient python3-ipykernel
  paraview python3-paraview xz-utils valgrind
  clang-16 libclang-rt-16-dev llvm-16
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  echo "setup: installing ${missing[*]}"
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} Debian packages present"
fi

[[ ${1:-} == --deps ]] && exit 0

cd "$root"
cmake --preset release
cmake --build --preset release
