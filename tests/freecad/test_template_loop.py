"""The template glider and the recompute loop, headless (freecadcmd).

Reference values come from geometry computed independently of the
workbench and the engine: trapezoid areas by formula, face areas and
centroids by OpenCASCADE (Part.Face of the sketch wires), mass as
area x thickness x density + ballast (spec: "Mass ... follow from plates and
ballast"), and the engine's report through the separate `pteromys` command.
"""
import json
import subprocess

import pytest

from conftest import PTEROMYS_BIN, TEMPLATE_FACTS

# Template dimensions (pteromys_freecad/template.py), mm
MAIN = dict(root=75.0, tip=40.0, span=420.0, sweep=18.0)
TAIL = dict(root=40.0, tip=30.0, span=150.0, sweep=20.0)
T_MM, RHO, BALLAST_G = 1.0, 180.0, 3.0


def trapezoid_area(w):
    return 0.5 * (w["root"] + w["tip"]) * w["span"]




def test_new_glider_from_template_builds_and_evaluates(fc, tmp_path):
    out = tmp_path / "template.glider.json"
    r = fc(TEMPLATE_FACTS + '''
doc = App.newDocument("T")
g = pf.new_glider(doc, auto_optimise=False)
RESULT["objects"] = sorted(o.TypeId for o in doc.Objects)
RESULT["f"] = facts(g)
RESULT["density"] = g.Density
RESULT["thickness"] = g.Thickness.Value
pf.export_glider_file(g, %r)
''' % str(out))
    assert r["objects"].count("Sketcher::SketchObject") == 3
    assert r["objects"].count("App::FeaturePython") == 2          # the two wings
    assert r["objects"].count("Part::FeaturePython") == 1         # the glider
    f = r["f"]
    res = f["results"]
    assert res["problems"] == [], res["problems"]
    # Sketches fully constrained (FreeCAD's solver: no degree of freedom left), dimensions as designed.
    assert f["fus_fully_constrained"] and all(w["fully_constrained"] for w in f["wings"].values())
    main, tail = f["wings"]["main"], f["wings"]["tail"]
    assert main["area"] == pytest.approx(trapezoid_area(MAIN), rel=1e-9)
    assert tail["area"] == pytest.approx(trapezoid_area(TAIL), rel=1e-9)
    assert main["planform"] == pytest.approx(main["area"], rel=1e-9)
    assert main["span"] == pytest.approx(MAIN["span"], abs=1e-6)
    assert (r["thickness"], r["density"]) == (T_MM, RHO)
    # Mass = plates (area x t x rho) + ballast.
    area_mm2 = f["fus_area"] + main["area"] + tail["area"]
    mass_g = area_mm2 * 1e-6 * T_MM * 1e-3 * RHO * 1e3 + BALLAST_G
    assert res["mass_kg"] * 1e3 == pytest.approx(mass_g, rel=1e-6)
    # Centre of gravity x from the plates' centroids placed at their mounts (independent of the engine).
    import math
    def wing_cx(w):
        x, y, a = w["mounted"]
        return x + math.cos(math.radians(a)) * w["cx"]
    m_f, m_m, m_t = (f["fus_area"], main["area"], tail["area"])
    plate = T_MM * 1e-9 * RHO * 1e3  # g per mm^2
    cg_x = (plate * (m_f * f["fus_cx"] + m_m * wing_cx(main) + m_t * wing_cx(tail)) + BALLAST_G * -12.0) / mass_g
    assert res["cg_m"][0] * 1e3 == pytest.approx(cg_x, abs=0.01)
    # Six launches; each trajectory starts at the launcher (0, 1.5 m) and ends on the ground at its distance.
    data = f["data"]
    assert len(res["launch_distances_m"]) == 6 and len(data["flights"]) == 6
    for d, fl, l in zip(res["launch_distances_m"], data["flights"], data["report"]["launches"]):
        assert fl[0] == pytest.approx([0.0, 1.5], abs=1e-3)
        if l.get("end") == "ground":
            assert fl[-1][0] == pytest.approx(d, abs=0.02) and fl[-1][1] == pytest.approx(0.0, abs=0.02)
    # Plates: one solid per plate, span across FreeCAD's Y (glider z), glider y up as FreeCAD Z.
    assert f["n_solids"] >= 3
    bb = f["bbox"]
    assert bb[3] - bb[2] == pytest.approx(MAIN["span"], abs=0.05)
    assert bb[1] == pytest.approx(0.0, abs=0.5)            # nose tip at the origin
    # The engine, through the command line, agrees with the Glider's results for the written file.
    rep = tmp_path / "rep.json"
    p = subprocess.run([PTEROMYS_BIN, "evaluate", str(out), "--json", str(rep)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    cli = json.loads(rep.read_text())
    assert [l["distance_m"] for l in cli["launches"]] == pytest.approx(res["launch_distances_m"], rel=1e-9)
    assert cli["flyable"] == res["flyable"]
    assert cli["mass_kg"] == pytest.approx(res["mass_kg"], rel=1e-12)


def test_editing_a_sketch_constraint_recomputes_the_glider(fc):
    r = fc(TEMPLATE_FACTS + '''
doc = App.newDocument("T")
g = pf.new_glider(doc, auto_optimise=False)
before = facts(g)
main = [w for w in g.Wings if w.WingName == "main"][0]
main.Sketch.setDatum("Span", App.Units.Quantity("480 mm"))
tail = [w for w in g.Wings if w.WingName == "tail"][0]
tail.Sketch.setDatum("RootChord", App.Units.Quantity("46 mm"))
doc.recompute()
RESULT["touched"] = [o.Name for o in doc.Objects if "Touched" in o.State]
RESULT["before"] = before
RESULT["after"] = facts(g)
''')
    b, a = r["before"], r["after"]
    assert a["results"]["problems"] == []
    assert a["wings"]["main"]["span"] == pytest.approx(480.0, abs=1e-6)
    assert a["wings"]["main"]["planform"] == pytest.approx(trapezoid_area(dict(MAIN, span=480.0)), rel=1e-9)
    assert a["wings"]["tail"]["planform"] == pytest.approx(trapezoid_area(dict(TAIL, root=46.0)), rel=1e-9)
    d_area = (a["wings"]["main"]["area"] - b["wings"]["main"]["area"]) + (a["wings"]["tail"]["area"] - b["wings"]["tail"]["area"])
    d_mass_g = d_area * T_MM * 1e-9 * RHO * 1e3
    assert (a["results"]["mass_kg"] - b["results"]["mass_kg"]) * 1e3 == pytest.approx(d_mass_g, rel=1e-6)
    assert a["bbox"][3] - a["bbox"][2] == pytest.approx(480.0, abs=0.05)          # the plates follow the sketch
    assert a["results"]["launch_distances_m"] != b["results"]["launch_distances_m"]  # the flights were recomputed
    assert a["volume"] > b["volume"]
    assert r["touched"] == []                                                     # one recompute settles everything


def test_add_wing_gives_a_third_plate(fc):
    r = fc('''
doc = App.newDocument("W3")
g = pf.new_glider(doc, auto_optimise=False)
n0 = len(g.Shape.Solids)
w = pf.add_wing(g, mount=(-150.0, 2.0, 0.0))
RESULT["name"], RESULT["n0"], RESULT["n1"] = w.WingName, n0, len(g.Shape.Solids)
RESULT["problems"], RESULT["wings"] = list(g.Problems), [x["name"] for x in pf.result_data(g)["glider"]["wings"]]
RESULT["area"] = w.PlanformArea.Value
try:
    pf.add_wing(g, name="main")
except ValueError as e:
    RESULT["dup"] = str(e)
''')
    assert r["problems"] == [], r["problems"]
    assert r["name"] == "wing3" and r["wings"] == ["main", "tail", "wing3"]
    assert r["n1"] >= r["n0"] + 1
    # default new wing: tapered, root 40, tip 30, span 150 mm
    assert r["area"] == pytest.approx(0.5 * (40 + 30) * 150, rel=1e-9)
    assert "already has a wing named 'main'" in r["dup"]


def test_model_file_property(fc, tmp_path):
    """The shipped model named explicitly gives the same flights as the default;
    a model with a lower stall angle changes them; a missing file is an input error."""
    other = tmp_path / "low_stall.model.json"
    other.write_text(json.dumps({"format": "pteromys-model/1", "type": "flat_plate",
                                 "params": {"stall_deg": 6.0}}))
    r = fc('''
doc = App.newDocument("M")
g = pf.new_glider(doc, auto_optimise=False)
d0 = list(g.LaunchDistances)
g.ModelFile = pf.engine().default_model_path()
doc.recompute()
d1 = list(g.LaunchDistances)
g.ModelFile = %r
doc.recompute()
d2, p2 = list(g.LaunchDistances), list(g.Problems)
g.ModelFile = %r
doc.recompute()
RESULT.update(d0=d0, d1=d1, d2=d2, p2=p2, p3=list(g.Problems), model=pf.result_data(g)["report"].get("model"))
''' % (str(other), str(tmp_path / "missing.model.json")))
    assert r["d1"] == pytest.approx(r["d0"], rel=1e-12)
    assert r["p2"] == [] and r["d2"] != pytest.approx(r["d0"], rel=1e-3)
    assert r["p3"] and "does not exist" in r["p3"][0]
