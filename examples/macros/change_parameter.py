# Pteromys macro: change a sketch dimension step by step, recompute, and
# record how the glider responds (a small design study).
#
#   freecadcmd examples/macros/change_parameter.py
#
# Writes to $PTEROMYS_MACRO_OUT (default ./pteromys_macro_out):
#   span_study.csv (one row per span), span_study.json, span_study.FCStd
#
# Shows: the template glider, named sketch constraints (setDatum), a lock
# (the main wing's angle), reading results after each recompute.
import csv
import json
import os
import sys

import FreeCAD as App

try:
    import pteromys_freecad as pf
except ImportError:  # running from a source tree without installing the add-on
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "freecad_workbench"))
    import pteromys_freecad as pf

OUT = os.path.abspath(os.environ.get("PTEROMYS_MACRO_OUT") or "pteromys_macro_out")
os.makedirs(OUT, exist_ok=True)
SPANS_MM = [int(s) for s in os.environ.get("PTEROMYS_SPANS_MM", "360,400,440,480,520").split(",")]


def main():
    doc = App.newDocument("SpanStudy")
    glider = pf.new_glider(doc, name="SpanStudy")
    main = next(w for w in glider.Wings if w.WingName == "main")
    main.LockAngle = True          # keep the main wing's mounting angle as designed
    sketch = main.Sketch           # named constraints: RootChord, TipChord, Span, Sweep

    rows = []
    for span in SPANS_MM:
        sketch.setDatum("Span", App.Units.Quantity("%d mm" % span))
        doc.recompute()
        r = pf.results(glider)
        if r["problems"]:
            print("span %d mm: %s" % (span, r["problems"][0]))
        rows.append({
            "span_mm": span,
            "wing_area_mm2": round(main.PlanformArea.Value, 1),
            "flyable": r["flyable"],
            "trim_speed_m_s": round(r["trim_speed_m_s"], 3),
            "glide_ratio": round(r["glide_ratio"], 3),
            "static_margin": round(r["static_margin"], 4),
            "best_distance_m": round(max(r["launch_distances_m"] or [0.0]), 2),
            "tail_x_mm": round(r["mounts"]["tail"]["x_m"] * 1e3, 2),
            "tail_angle_deg": round(r["mounts"]["tail"]["angle_deg"], 3),
            "main_angle_deg": round(r["mounts"]["main"]["angle_deg"], 3),
            "mass_g": round(r["mass_kg"] * 1e3, 3),
            "recompute_ms": round(r["recompute_ms"], 1),
            "status": r["status"],
        })
        print("span %4d mm: flyable %-5s  glide ratio %.2f  best %.1f m  tail at %.1f mm, %.2f deg  (%.0f ms)"
              % (span, r["flyable"], r["glide_ratio"], rows[-1]["best_distance_m"], rows[-1]["tail_x_mm"],
                 rows[-1]["tail_angle_deg"], r["recompute_ms"]))

    with open(os.path.join(OUT, "span_study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(OUT, "span_study.json"), "w") as f:
        json.dump(rows, f, indent=1)
    doc.saveAs(os.path.join(OUT, "span_study.FCStd"))
    print("wrote", OUT)


try:
    main()
except Exception:
    if App.GuiUp:   # in the GUI, show the error and keep FreeCAD running
        raise
    import traceback
    traceback.print_exc()
    sys.exit(1)     # headless: a failing macro fails its command line (freecadcmd exits 0 otherwise)
