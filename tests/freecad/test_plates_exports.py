"""Slotted plates as the Glider's shape, and the DXF/STEP exports (needs the
fabrication engine, issue 4).

References: OpenCASCADE booleans and distances on the Glider's own solids
(plates that interlock must not overlap, and must touch), the sketch faces'
areas (OpenCASCADE) for material removed by slots, the mounting angle for
each wing plate's orientation, ezdxf (an independent DXF reader) for the
laser file and FreeCAD's STEP reader for the 3D file.
"""
import math

import pytest

from conftest import require

PLATES = r'''
import Part
def face_area(sk):
    s = sk.Shape.copy()
    s.transformShape(sk.getGlobalPlacement().inverse().toMatrix())
    return Part.Face(s.Wires[0]).Area
def plates(g):
    sh = g.Shape.copy()
    sh.Placement = App.Placement()          # back to the glider frame (x nose, y up, z span; mm)
    out = []
    for s in sh.Solids:
        big = max(s.Faces, key=lambda f: f.Area)
        u0, u1, v0, v1 = big.ParameterRange
        n = big.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
        bb = s.BoundBox
        out.append({"volume": s.Volume, "normal": [n.x, n.y, n.z], "bbox": [bb.XMin, bb.XMax, bb.YMin, bb.YMax, bb.ZMin, bb.ZMax]})
    fus = max(range(len(sh.Solids)), key=lambda i: sh.Solids[i].BoundBox.XLength * (abs(out[i]["normal"][2]) > 0.99))
    overlaps, gaps = [], []
    for i, s in enumerate(sh.Solids):
        if i == fus:
            continue
        overlaps.append(sh.Solids[fus].common(s).Volume)
        gaps.append(sh.Solids[fus].distToShape(s)[0])
    return {"plates": out, "fus": fus, "overlaps": overlaps, "gaps": gaps}
'''


def test_plates_are_slotted_interlock_and_follow_the_mounts(fc):
    require("slotted_plates")
    r = fc(PLATES + '''
doc = App.newDocument("P")
g = pf.new_glider(doc, auto_optimise=False)
W = {w.WingName: w for w in g.Wings}
W["main"].MountAngle = 4.0
doc.recompute()
RESULT["p"] = plates(g)
RESULT["design_mm2"] = face_area(g.Fuselage) + sum(face_area(w.Sketch) for w in g.Wings)
RESULT["t"] = g.Thickness.Value
RESULT["clearance"] = g.Clearance.Value
RESULT["status"], RESULT["problems"], RESULT["assembly"] = g.Status, list(g.Problems), list(g.Assembly)
RESULT["angles"] = {n: w.MountedAngle.getValueAs("deg").Value for n, w in W.items()}
RESULT["data_plates"] = pf.result_data(g)["plates"]
''')
    assert r["problems"] == [], r["problems"]
    assert "not available" not in r["status"], r["status"]
    p = r["p"]
    t = r["t"]
    vol = sum(q["volume"] for q in p["plates"])
    # Slots remove material: less than the drawn area x thickness, but not much (< 5 %).
    assert vol < r["design_mm2"] * t
    assert vol > 0.95 * r["design_mm2"] * t
    assert any(q["holes"] for q in r["data_plates"]) or any(q["outline_points"] > 7 for q in r["data_plates"])
    # Interlocking plates do not overlap and touch (within the slot clearance).
    assert max(p["overlaps"]) < 1e-3 * t ** 3, p["overlaps"]
    assert max(p["gaps"]) <= r["clearance"] + 1e-6, p["gaps"]
    # Each wing plate lies in its plane: normal = (-sin a, cos a, 0) (glider frame) up to sign.
    wing_normals = [q["normal"] for i, q in enumerate(p["plates"]) if i != p["fus"]]
    for a in r["angles"].values():
        e = [-math.sin(math.radians(a)), math.cos(math.radians(a)), 0.0]
        assert any(abs(abs(sum(x * y for x, y in zip(n, e))) - 1.0) < 1e-9 for n in wing_normals), (a, wing_normals)
    assert r["assembly"] and all(s[0].isdigit() for s in r["assembly"])


def test_plates_that_cannot_be_slotted_are_shown_plain_with_the_reason(fc, tmp_path):
    """A valid design whose slots cannot be made: the flight results stay valid,
    the plates are shown without slots, the reason is given, and the laser
    export refuses with that reason instead of writing something unusable."""
    require("slotted_plates")
    r = fc(PLATES + '''
doc = App.newDocument("W")
g = pf.new_glider(doc, auto_optimise=False)
v0 = g.Shape.Volume
g.MinWeb = 60.0          # more material beside every slot than the plates have
doc.recompute()
RESULT["v0"], RESULT["v1"] = v0, g.Shape.Volume
RESULT["design_mm3"] = (face_area(g.Fuselage) + sum(face_area(w.Sketch) for w in g.Wings)) * g.Thickness.Value
RESULT["problems"], RESULT["fab"], RESULT["status"] = list(g.Problems), list(g.FabricationProblems), g.Status
RESULT["assembly"] = list(g.Assembly)
try:
    pf.export_dxf(g, %r)
except pf.ExportError as e:
    RESULT["export"] = str(e)
''' % str(tmp_path / "never.dxf"))
    assert r["problems"] == []                          # the design is valid
    assert r["fab"] and "web" in r["fab"][0], r["fab"]
    assert "plates shown without slots: " in r["status"]
    assert r["v1"] == pytest.approx(r["design_mm3"], rel=1e-9)   # unslotted: the drawn area x thickness
    assert r["v0"] < r["v1"] and r["assembly"] == []
    assert "cannot be slotted" in r["export"]
    assert not (tmp_path / "never.dxf").exists()


def test_dxf_and_step_exports_read_back(fc, tmp_path):
    require("export")
    dxf, step = tmp_path / "glider.dxf", tmp_path / "glider.step"
    r = fc(PLATES + '''
doc = App.newDocument("X")
g = pf.new_glider(doc)
RESULT["dxf_summary"] = pf.export_dxf(g, %r)
RESULT["step_summary"] = pf.export_step(g, %r)
RESULT["design"] = {"fuselage": face_area(g.Fuselage), **{w.WingName: face_area(w.Sketch) for w in g.Wings}}
RESULT["shape_volume"] = g.Shape.Volume
sh = g.Shape.copy(); sh.Placement = App.Placement()
bb = sh.BoundBox
RESULT["shape_extents"] = sorted([bb.XLength, bb.YLength, bb.ZLength])
RESULT["n_solids"] = len(g.Shape.Solids)
st = Part.read(%r)
bb = st.BoundBox
RESULT["step"] = {"solids": len(st.Solids), "volume": st.Volume, "extents": sorted([bb.XLength, bb.YLength, bb.ZLength]),
                  "valid": st.isValid()}
''' % (str(dxf), str(step), str(step)))
    # STEP (FreeCAD's reader): one valid solid per plate, the Glider's volume and size.
    s = r["step"]
    assert s["valid"] and s["solids"] == r["n_solids"]
    assert s["volume"] == pytest.approx(r["shape_volume"], rel=1e-3)
    assert s["extents"] == pytest.approx(r["shape_extents"], abs=0.05)
    # DXF (ezdxf): millimetres, closed outlines whose areas match the drawn plates.
    import ezdxf
    from ezdxf import units
    doc = ezdxf.readfile(str(dxf))
    assert doc.units == units.MM
    areas = []
    for e in doc.modelspace().query("LWPOLYLINE POLYLINE"):
        if e.dxftype() == "LWPOLYLINE":
            pts, closed = [(p[0], p[1]) for p in e.get_points("xy")], e.closed
        else:
            pts, closed = [(v.dxf.location.x, v.dxf.location.y) for v in e.vertices], e.is_closed
        if closed and len(pts) >= 3:
            areas.append(abs(sum(pts[i][0] * pts[i - 1][1] - pts[i - 1][0] * pts[i][1] for i in range(len(pts)))) / 2)
    assert areas, "no closed outline in the DXF"
    for name, a in r["design"].items():
        # each plate's cut outline: its drawn area plus the kerf band, minus open slots (within 3 %)
        assert any(abs(x - a) <= 0.03 * a for x in areas), (name, a, sorted(areas)[-6:])
