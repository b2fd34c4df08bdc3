"""Bad input stays civil: the Glider names the problem, keeps its last good
shape and results, FreeCAD carries on, and undoing the edit recovers.

Each case edits the template glider inside an undo transaction, recomputes,
records what the Glider shows, undoes, recomputes again and records that.
"""
import pytest

CASES = r'''
import Part
doc = App.newDocument("Bad")
doc.UndoMode = 1
g = pf.new_glider(doc, auto_optimise=False)
W = {w.WingName: w for w in g.Wings}

def state():
    bb = g.Shape.BoundBox
    return {"status": g.Status, "problems": list(g.Problems), "flyable": g.Flyable, "reasons": list(g.Reasons),
            "volume": g.Shape.Volume, "bbox": [bb.XMin, bb.XMax, bb.YMin, bb.YMax, bb.ZMin, bb.ZMax],
            "solid_centres": [[s.CenterOfMass.x, s.CenterOfMass.y, s.CenterOfMass.z] for s in g.Shape.Solids],
            "tail_angle": W["tail"].MountedAngle.getValueAs("deg").Value,
            "distances": list(g.LaunchDistances), "valid": g.isValid(), "invalid_state": "Invalid" in g.State}

def open_tail():                      # delete one edge of the tail outline
    W["tail"].Sketch.delGeometry(1)

def crossing_tail():                  # a bow-tie outline
    sk = pf.sketch_from_outline(doc, "BowTie", [(0.0, 0.07), (-0.04, -0.07), (-0.04, 0.07), (0.0, -0.07)])
    W["tail"].Sketch = sk

def missing_fuselage():               # the fuselage sketch is deleted
    doc.removeObject(g.Fuselage.Name)

def wing_off_fuselage():              # the main wing 10 cm above the fuselage
    W["main"].MountY = 100.0

def cannot_fly():                     # tail at +6 deg: trims nose-down (valid input)
    W["tail"].MountAngle = 6.0

def two_outlines():                   # a hole drawn in the main wing
    W["main"].Sketch.addGeometry(Part.Circle(App.Vector(-30, 0, 0), App.Vector(0, 0, 1), 5), False)

def loose_edge():                     # a stray line in the fuselage sketch
    g.Fuselage.addGeometry(Part.LineSegment(App.Vector(-100, 50, 0), App.Vector(-80, 60, 0)), False)

def duplicate_names():
    W["tail"].WingName = "main"

def zero_thickness():
    g.Thickness = 0.0

def no_wings():
    g.Wings = []

def nan_angle():                      # a NaN from a macro
    W["main"].MountAngle = float("nan")

def infinite_density():
    g.Density = float("inf")

def launch_too_high():                # the standard launches are from 0-100 m
    g.LaunchHeight = 150000.0

CASES = [open_tail, crossing_tail, missing_fuselage, wing_off_fuselage, cannot_fly, two_outlines,
         loose_edge, duplicate_names, zero_thickness, no_wings, nan_angle, infinite_density, launch_too_high]

def saved_and_reopened(tag):
    """Save the document in its bad state, open a copy, read it, recompute it."""
    import os, shutil
    path = os.path.join(os.getcwd(), tag + ".FCStd")
    doc.saveAs(path)
    copy = os.path.join(os.getcwd(), tag + "-copy.FCStd")
    shutil.copyfile(path, copy)
    d2 = App.openDocument(copy)
    g2 = d2.getObject(g.Name)
    loaded = {"volume": g2.Shape.Volume, "problems": list(g2.Problems)}
    d2.recompute()
    again = {"volume": g2.Shape.Volume, "problems": list(g2.Problems), "status": g2.Status,
             "flyable": g2.Flyable}
    App.closeDocument(d2.Name)
    App.setActiveDocument(doc.Name)
    return {"loaded": loaded, "recomputed": again}
RESULT["good"] = state()
for case in CASES:
    doc.openTransaction(case.__name__)
    case()
    doc.commitTransaction()
    n = doc.recompute()
    bad = state()
    reopened = saved_and_reopened(case.__name__)
    doc.undo()
    doc.recompute()
    RESULT[case.__name__] = {"bad": bad, "recovered": state(), "reopened": reopened}
'''


@pytest.fixture(scope="module")
def cases(fc_home, tmp_path_factory):
    from conftest import run_freecad
    return run_freecad(fc_home, tmp_path_factory.mktemp("bad"), CASES, name="bad")


INPUT_ERRORS = {
    "open_tail": ["wing 'tail'", "is not closed"],
    "crossing_tail": ["wing 'tail'", "crosses itself"],
    "missing_fuselage": ["fuselage has no sketch"],
    "wing_off_fuselage": ["wing 'main'", "does not touch the fuselage"],
    "two_outlines": ["wing 'main'", "2 closed outlines"],
    "loose_edge": ["fuselage", "loose edge"],
    "duplicate_names": ["two wings are named 'main'"],
    "zero_thickness": ["thickness must be positive"],
    "no_wings": ["no wing"],
    "nan_angle": ["wing 'main'", "MountAngle", "not a finite number"],
    "infinite_density": ["Density", "not a finite number"],
    "launch_too_high": ["launch height must be at most 100 m", "150 m"],
}


@pytest.mark.parametrize("case", sorted(INPUT_ERRORS))
def test_input_error_is_named_and_last_good_shape_kept(cases, case):
    good, bad, rec = cases["good"], cases[case]["bad"], cases[case]["recovered"]
    assert good["problems"] == [] and good["volume"] > 0
    text = " ".join(bad["problems"])
    for words in INPUT_ERRORS[case]:
        assert words in text, (case, bad["problems"])
    assert bad["status"].startswith("Input error: ") and "last good design" in bad["status"], bad["status"]
    # The last good shape and results are kept.
    assert bad["volume"] == pytest.approx(good["volume"], rel=1e-12)
    assert bad["bbox"] == pytest.approx(good["bbox"], abs=1e-9)
    assert sum(bad["solid_centres"], []) == pytest.approx(sum(good["solid_centres"], []), abs=1e-9)
    assert bad["distances"] == pytest.approx(good["distances"], rel=1e-12)
    # FreeCAD does not mark the object as failed (no red error state), and undo recovers.
    assert bad["valid"] and not bad["invalid_state"]
    assert rec["problems"] == [], rec["problems"]
    assert rec["volume"] == pytest.approx(good["volume"], rel=1e-9)
    assert rec["distances"] == pytest.approx(good["distances"], rel=1e-9)
    # The document saved in its bad state reopens with the last good shape
    # and, recomputed, names the same problem.
    reo = cases[case]["reopened"]
    assert reo["loaded"]["volume"] == pytest.approx(good["volume"], rel=1e-9)
    assert reo["recomputed"]["volume"] == pytest.approx(good["volume"], rel=1e-9)
    again = " ".join(reo["recomputed"]["problems"])
    for words in INPUT_ERRORS[case]:
        assert words in again, (case, reo)


def test_design_that_cannot_fly_shows_reasons(cases):
    good, bad = cases["good"], cases["cannot_fly"]["bad"]
    assert good["flyable"] is True, good["status"]
    assert bad["problems"] == []                          # valid input: not an input error
    assert bad["flyable"] is False and bad["reasons"], bad
    assert bad["status"].startswith("Not flyable: ") and bad["reasons"][0] in bad["status"]
    assert bad["tail_angle"] == pytest.approx(6.0) and good["tail_angle"] == pytest.approx(0.0)
    # the plates show the design as it is: the tail plate turned, so its centroid moved
    assert sum(bad["solid_centres"], []) != pytest.approx(sum(good["solid_centres"], []), abs=1e-3)
    assert bad["distances"] != pytest.approx(good["distances"], rel=1e-6)
    assert cases["cannot_fly"]["recovered"]["flyable"] is True
