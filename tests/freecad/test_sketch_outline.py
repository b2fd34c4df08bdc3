"""Sketch curves -> plate outlines: tolerance, units, half wings, placement.

References: OpenCASCADE's exact distances and face areas of the sketch
curves (not the workbench's polygon), and the stated chordal tolerance.
"""

import pytest

CURVED_WING = r'''
import Part
V = App.Vector
def curved_wing_sketch(doc, name):
    """Half span 180 mm: B-spline leading edge, arc tip, straight trailing edge (mm)."""
    sk = doc.addObject("Sketcher::SketchObject", name)
    le = Part.BSplineCurve()
    le.interpolate([V(0, 0, 0), V(-4, 90, 0), V(-15, 170, 0)])
    le_m = Part.BSplineCurve()
    le_m.interpolate([V(0, 0, 0), V(-4, -90, 0), V(-15, -170, 0)])
    tip = Part.Arc(V(-15, 170, 0), V(-35, 185, 0), V(-55, 170, 0))
    tip_m = Part.Arc(V(-15, -170, 0), V(-35, -185, 0), V(-55, -170, 0))
    curves = [le, tip, Part.LineSegment(V(-55, 170, 0), V(-70, 0, 0)),
              Part.LineSegment(V(-70, 0, 0), V(-55, -170, 0)), tip_m, le_m]
    pf.add_closed_curves(sk, curves)
    return sk
def local_shape(sk):
    s = sk.Shape.copy()
    s.transformShape(sk.getGlobalPlacement().inverse().toMatrix())
    return s
def check_outline(sk, outline_m, tol):
    shp = local_shape(sk)
    face = Part.Face(shp.Wires[0])
    pts = [V(x * 1e3, z * 1e3, 0) for x, z in outline_m]
    on_curve = max(Part.Vertex(p).distToShape(shp)[0] for p in pts)
    chord = 0.0
    n = len(pts)
    for i in range(n):
        a, b = pts[i], pts[(i + 1) % n]
        for k in range(1, 8):
            q = a + (b - a) * (k / 8.0)
            chord = max(chord, Part.Vertex(q).distToShape(shp)[0])
    area = 0.5 * abs(sum(pts[i].x * pts[(i + 1) % n].y - pts[(i + 1) % n].x * pts[i].y for i in range(n)))
    return {"n": n, "on_curve": on_curve, "chord": chord, "area_poly": area, "area_face": face.Area,
            "perimeter": shp.Wires[0].Length}
'''


def test_curves_are_discretised_within_the_chord_tolerance(fc):
    r = fc(CURVED_WING + '''
doc = App.newDocument("C")
g = pf.new_glider(doc, auto_optimise=False)
main = [w for w in g.Wings if w.WingName == "main"][0]
main.Sketch = curved_wing_sketch(doc, "Curved")
for tol in (0.1, 0.01):
    g.ChordTolerance = tol
    doc.recompute()
    wing = [w for w in pf.result_data(g)["glider"]["wings"] if w["name"] == "main"][0]
    RESULT[str(tol)] = check_outline(main.Sketch, wing["outline_m"], tol)
    RESULT[str(tol)]["problems"] = list(g.Problems)
''')
    for tol in (0.1, 0.01):
        c = r[str(tol)]
        assert c["problems"] == [], c["problems"]
        assert c["on_curve"] < 1e-6                       # vertices lie on the sketch curves
        assert c["chord"] <= tol * 1.02                   # chords stay within the stated tolerance
        assert abs(c["area_poly"] - c["area_face"]) <= c["perimeter"] * tol
    assert r["0.01"]["n"] > r["0.1"]["n"]                  # a finer tolerance gives more points
    assert abs(r["0.01"]["area_poly"] - r["0.01"]["area_face"]) < abs(r["0.1"]["area_poly"] - r["0.1"]["area_face"])


def test_millimetres_become_metres_and_placement_does_not_matter(fc):
    r = fc('''
doc = App.newDocument("U")
g = pf.new_glider(doc, auto_optimise=False)
fus = g.Fuselage
RESULT["sketch_mm"] = [[fus.getPoint(i, 1).x, fus.getPoint(i, 1).y] for i in range(fus.GeometryCount)]
RESULT["file_m"] = pf.result_data(g)["glider"]["fuselage"]["outline_m"]
d0 = list(g.LaunchDistances)
for sk in [fus] + [w.Sketch for w in g.Wings]:      # move and turn every sketch in 3D
    sk.Placement = App.Placement(App.Vector(123, -45, 67), App.Rotation(App.Vector(1, 2, 3), 33))
doc.recompute()
RESULT["d0"], RESULT["d1"] = d0, list(g.LaunchDistances)
RESULT["problems"] = list(g.Problems)
''')
    assert r["problems"] == []
    assert sorted(map(tuple, r["file_m"])) == pytest.approx(sorted((x / 1000.0, y / 1000.0) for x, y in r["sketch_mm"]),
                                                            abs=1e-12)
    assert r["d1"] == pytest.approx(r["d0"], rel=1e-12)


def test_half_wing_is_mirrored(fc):
    r = fc('''
import Part
V = App.Vector
doc = App.newDocument("H")
g = pf.new_glider(doc, auto_optimise=False)
main = [w for w in g.Wings if w.WingName == "main"][0]
full_area = main.PlanformArea.Value
d_full = list(g.LaunchDistances)
# the same wing, drawn as its upper half (closed, root chord on the axis)
half = pf.sketch_from_outline(doc, "Half", [(0, 0), (-0.018, 0.21), (-0.058, 0.21), (-0.075, 0)])
main.Sketch, main.HalfOutline = half, True
doc.recompute()
RESULT["closed"] = {"area": main.PlanformArea.Value, "d": list(g.LaunchDistances), "problems": list(g.Problems),
                    "outline": [w for w in pf.result_data(g)["glider"]["wings"] if w["name"] == "main"][0]["outline_m"]}
# drawn as an open chain from axis to axis (no root edge), on the negative side
chain = doc.addObject("Sketcher::SketchObject", "Chain")
pts = [V(0, 0, 0), V(-18, -210, 0), V(-58, -210, 0), V(-75, 0, 0)]
chain.addGeometry([Part.LineSegment(pts[i], pts[i + 1]) for i in range(3)], False)
main.Sketch = chain
doc.recompute()
RESULT["chain"] = {"area": main.PlanformArea.Value, "d": list(g.LaunchDistances), "problems": list(g.Problems)}
# a half that crosses the axis is refused with a reason
bad = pf.sketch_from_outline(doc, "Bad", [(0, -0.01), (-0.018, 0.21), (-0.058, 0.21), (-0.075, 0)])
main.Sketch = bad
doc.recompute()
RESULT["bad"] = list(g.Problems)
RESULT["full_area"], RESULT["d_full"] = full_area, d_full
''')
    # Template main wing: root 75, tip 40 at half span 210, tip LE 18 behind the root LE.
    expected = 0.5 * (75 + 40) * 420
    assert r["full_area"] == pytest.approx(expected, rel=1e-9)
    for k in ("closed", "chain"):
        assert r[k]["problems"] == [], r[k]["problems"]
        assert r[k]["area"] == pytest.approx(expected, rel=1e-9)
        assert r[k]["d"] == pytest.approx(r["d_full"], rel=1e-9)
    out = r["closed"]["outline"]
    assert sorted((round(x, 9), round(z, 9)) for x, z in out) == sorted((round(x, 9), round(-z, 9)) for x, z in out)
    assert any("symmetry axis" in p for p in r["bad"]), r["bad"]


def test_asymmetric_wing_is_refused_by_name(fc):
    r = fc('''
doc = App.newDocument("A")
g = pf.new_glider(doc, auto_optimise=False)
main = [w for w in g.Wings if w.WingName == "main"][0]
main.Sketch = pf.sketch_from_outline(doc, "Asym", [(0, 0), (-0.018, 0.21), (-0.058, 0.21), (-0.075, 0),
                                                  (-0.058, -0.18), (-0.018, -0.18)])
doc.recompute()
RESULT["problems"] = list(g.Problems)
''')
    assert any("main" in p and "symmetric" in p for p in r["problems"]), r["problems"]
