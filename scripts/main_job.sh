#!/usr/bin/env bash
# The main job on a bundled example: set up, build, then evaluate the glider
# and write its report, trajectories and a plot of the standard launches.
#   scripts/main_job.sh [GLIDER.glider.json] [OUT_DIR]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/scripts/setup.sh"

GLIDER=${1:-$ROOT/examples/gliders/tapered.glider.json}
OUT=${2:-$ROOT/out/main}
mkdir -p "$OUT"
PT="$ROOT/build/bin/pteromys"
export PYTHONPATH="$ROOT/build/python${PYTHONPATH:+:$PYTHONPATH}"

echo "== evaluating $GLIDER"
"$PT" evaluate "$GLIDER" --json "$OUT/report.json" --csv "$OUT/trajectories.csv"
/usr/bin/python3 -m pteromys.plot "$OUT/report.json" "$OUT/trajectories.csv" "$OUT/launches.png"
echo "== wrote $OUT/report.json, $OUT/trajectories.csv, $OUT/launches.png"
