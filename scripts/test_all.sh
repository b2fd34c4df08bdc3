#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: set up, build, then run
# GoogleTest (engine) and pytest (command line, Python module, FreeCAD) via ctest,
# then the engine tests and fuzz corpora again under ASan + UBSan + LSan
# (scripts/sanitize.sh, docs/reliability.md). Any failure fails the script.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/scripts/setup.sh"
echo "test_all: set-up and build $SECONDS s"
cd "$ROOT/build"
t=$SECONDS
ctest --output-on-failure -j"$(nproc)" "$@"
echo "test_all: Release suite $((SECONDS - t)) s"
t=$SECONDS
"$ROOT/scripts/sanitize.sh"
echo "test_all: sanitizer run $((SECONDS - t)) s; all $SECONDS s"
