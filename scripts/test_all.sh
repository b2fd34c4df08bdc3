#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: set up, build, then run
# GoogleTest (engine) and pytest (command line, Python module, FreeCAD) via ctest.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/scripts/setup.sh"
cd "$ROOT/build"
ctest --output-on-failure -j"$(nproc)" "$@"
