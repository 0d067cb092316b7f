#!/usr/bin/env bash
# Installs what treetrace needs on Debian (when missing), then configures and
# builds it in ./build. Usage: scripts/bootstrap.sh [extra cmake -D options]
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail
cd "$(dirname "$0")/.."

# libxxhash-dev: the checksums of saved structures; libopenmpi-dev and
# openmpi-bin: rendering across MPI ranks (optional at configure time, on
# here because they are installed); libboost-dev: Boost.Geometry's R*-tree,
# the yardstick of the insertion build (tools/rtree_boost_bench.cpp).
packages=(build-essential cmake pkg-config libpng-dev libomp-dev libembree-dev libxxhash-dev
          libopenmpi-dev openmpi-bin libboost-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "bootstrap: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

build_dir="${TT_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${TT_BUILD_TYPE:-Release}" "$@" >&2
cmake --build "$build_dir" -j"$(nproc)" >&2
