# Pteromys macro: build a glider from scratch with curved sketches, recompute,
# read the results and save the document.
#
#   freecadcmd examples/macros/glider_from_scratch.py      (headless)
#   Macro > Macros... > glider_from_scratch.py > Execute    (GUI)
#
# Writes to $PTEROMYS_MACRO_OUT (default ./pteromys_macro_out):
#   scratch.FCStd, scratch_results.json
#
# Shows: sketches with lines, an arc and a B-spline; a wing drawn as a half
# and mirrored (HalfOutline); material, ballast, automatic optimisation.
import json
import os
import sys

import FreeCAD as App
import Part

try:
    import pteromys_freecad as pf
except ImportError:  # running from a source tree without installing the add-on
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "freecad_workbench"))
    import pteromys_freecad as pf

OUT = os.path.abspath(os.environ.get("PTEROMYS_MACRO_OUT") or "pteromys_macro_out")
os.makedirs(OUT, exist_ok=True)
V = App.Vector


def closed_sketch(doc, name, curves, placement):
    """A sketch holding one closed loop of curves, joined by coincident constraints."""
    sk = doc.addObject("Sketcher::SketchObject", name)
    sk.Placement = placement
    pf.add_closed_curves(sk, curves)
    return sk


def main():
    doc = App.newDocument("Scratch")

    # Fuselage, side view (sketch X toward the nose, Y up; mm). A rounded nose
    # (an arc through three points) and a straight boom with a fin.
    nose = Part.Arc(V(-25, 11, 0), V(2, 0, 0), V(-25, -9, 0))
    fuselage = closed_sketch(doc, "Fuselage", [
        nose,                                               # from the nose top, round, to the nose bottom
        Part.LineSegment(V(-25, -9, 0), V(-270, -3, 0)),
        Part.LineSegment(V(-270, -3, 0), V(-270, 32, 0)),
        Part.LineSegment(V(-270, 32, 0), V(-250, 32, 0)),
        Part.LineSegment(V(-250, 32, 0), V(-215, 9, 0)),
        Part.LineSegment(V(-215, 9, 0), V(-25, 11, 0)),
    ], App.Placement(V(), App.Rotation(V(1, 0, 0), 90)))
    fuselage.Label = "Fuselage (side view)"

    # Main wing, top view, drawn as one half (sketch Y >= 0) and mirrored by the
    # workbench: a straight leading edge, a B-spline tip, a straight trailing edge
    # and the root chord on the symmetry axis.
    tip = Part.BSplineCurve()
    tip.interpolate([V(-12, 190, 0), V(-30, 212, 0), V(-52, 200, 0), V(-62, 180, 0)])
    wing = closed_sketch(doc, "MainWingHalf", [
        Part.LineSegment(V(0, 0, 0), V(-12, 190, 0)),       # leading edge
        tip,                                                # rounded tip
        Part.LineSegment(V(-62, 180, 0), V(-72, 0, 0)),     # trailing edge
        Part.LineSegment(V(-72, 0, 0), V(0, 0, 0)),         # root chord on the axis
    ], App.Placement(V(-50, 0, 4), App.Rotation()))
    wing.Label = "Main wing half (top view)"

    # Tail: a plain polygon from points in metres (the helper adds the constraints).
    tail_pts = [(0.0, 0.0), (-0.022, 0.07), (-0.047, 0.07), (-0.042, 0.0), (-0.047, -0.07), (-0.022, -0.07)]
    tail = pf.sketch_from_outline(doc, "TailSketch", tail_pts, App.Placement(V(-235, 0, 6), App.Rotation()),
                                  "Tail (top view)")

    main_wing = pf.make_wing(wing, "main", mount=(-50.0, 4.0, 2.0), half=True, doc=doc, label="Main wing")
    tail_wing = pf.make_wing(tail, "tail", mount=(-235.0, 6.0, 0.0), doc=doc, label="Tail")
    glider = pf.make_glider(fuselage, [main_wing, tail_wing], name="Scratch", doc=doc)
    glider.Material = "Foam core board 1 mm"
    glider.BallastGrams, glider.BallastX = 3.0, -10.0
    glider.ChordTolerance = 0.05      # mm: curves -> polygons
    glider.AutoOptimise = True
    doc.recompute()

    r = pf.results(glider)
    print("Status:", r["status"])
    print("Flyable:", r["flyable"], "| trim %.2f m/s | glide ratio %.2f | static margin %.1f %%"
          % (r["trim_speed_m_s"], r["glide_ratio"], 100 * r["static_margin"]))
    print("Launch distances [m]:", ", ".join("%.1f" % d for d in r["launch_distances_m"]))
    for name, m in r["mounts"].items():
        print("  %s: x %.1f mm, y %.1f mm, angle %.2f deg" % (name, m["x_m"] * 1e3, m["y_m"] * 1e3, m["angle_deg"]))
    print("Wing span %.1f mm, area %.0f mm^2" % (main_wing.Span.Value, main_wing.PlanformArea.Value))

    doc.saveAs(os.path.join(OUT, "scratch.FCStd"))
    with open(os.path.join(OUT, "scratch_results.json"), "w") as f:
        json.dump({k: v for k, v in r.items() if k != "report"}, f, indent=1)
    print("wrote", OUT)


try:
    main()
except Exception:
    if App.GuiUp:   # in the GUI, show the error and keep FreeCAD running
        raise
    import traceback
    traceback.print_exc()
    sys.exit(1)     # headless: a failing macro fails its command line (freecadcmd exits 0 otherwise)
