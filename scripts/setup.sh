#!/usr/bin/env bash
# Installs the Debian packages Pteromys needs (only those missing) and builds it
# in ./build. Idempotent: a second run installs nothing and rebuilds only what
# changed. Used by scripts/main_job.sh and scripts/test_all.sh.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)

PKGS=(
  build-essential cmake pkg-config git
  libcgal-dev libboost-dev libgmp-dev libmpfr-dev libeigen3-dev nlohmann-json3-dev
  pybind11-dev python3-dev libnlopt-cxx-dev libnlopt-dev libdxflib-dev
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev libocct-ocaf-dev
  libgtest-dev libbenchmark-dev
  python3-numpy python3-pytest python3-ezdxf python3-matplotlib python3-opencv libopencv-dev
  freecad xvfb xauth
  clang libclang-rt-14-dev
)

missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q "${missing[@]}"
fi

cmake -S "$ROOT" -B "$ROOT/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$ROOT/build" -j"$(nproc)"
