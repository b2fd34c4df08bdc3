#!/usr/bin/env bash
# The main job on a bundled example: set up, build, then optimise the glider's
# mounting and write the optimised glider, its flyability report, the
# trajectories of the six standard launches and a plot of them, and the
# slotted plates as a laser-cutting DXF and a 3D STEP; install the FreeCAD
# workbench and build the same glider there as a parametric document.
#   scripts/main_job.sh [GLIDER.glider.json] [OUT_DIR]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/scripts/setup.sh"

GLIDER=${1:-$ROOT/examples/gliders/tapered.glider.json}
OUT=${2:-$ROOT/out/main}
mkdir -p "$OUT"
PT="$ROOT/build/bin/pteromys"
export PYTHONPATH="$ROOT/build/python${PYTHONPATH:+:$PYTHONPATH}"

echo "== evaluating $GLIDER as drawn"
"$PT" evaluate "$GLIDER" --json "$OUT/report_as_drawn.json" --quiet
echo "== optimising its mounting"
"$PT" optimize "$GLIDER" -o "$OUT/optimized.glider.json" --json "$OUT/report.json" --csv "$OUT/trajectories.csv"
/usr/bin/python3 -m pteromys.plot "$OUT/report.json" "$OUT/trajectories.csv" "$OUT/launches.png"
echo "== fabrication files of the optimised glider"
"$PT" export "$OUT/optimized.glider.json" --dxf "$OUT/parts.dxf" --step "$OUT/glider.step" --json "$OUT/fabrication.json"
/usr/bin/python3 -m pteromys.fabrication layout "$OUT/parts.dxf" "$OUT/parts.png"
/usr/bin/python3 -m pteromys.fabrication assembly "$OUT/optimized.glider.json" "$OUT/assembly.png"
echo "== FreeCAD workbench: install the add-on, import the glider as sketches, recompute, export its parts"
"$ROOT/freecad_workbench/install.sh" --python-path "$ROOT/build/python"
mkdir -p "$OUT/freecad"
PTEROMYS_MACRO_GLIDER="$GLIDER" PTEROMYS_MACRO_OUT="$OUT/freecad" freecadcmd "$ROOT/examples/macros/import_glider_file.py"
PTEROMYS_MACRO_DOC="$OUT/freecad/imported.FCStd" PTEROMYS_MACRO_OUT="$OUT/freecad" freecadcmd "$ROOT/examples/macros/export_parts.py"
echo "== wrote to $OUT: optimized.glider.json, report.json, trajectories.csv, launches.png,"
echo "   parts.dxf (laser cutting), glider.step (3D print / CAD), fabrication.json, parts.png, assembly.png,"
echo "   freecad/ (the glider as a parametric FreeCAD document and its exports)"
