"""Saving and reopening restores everything, in a fresh FreeCAD process;
documents hold no engine objects; older documents migrate on opening."""
import base64
import re
import zipfile

import pytest

OUTPUTS = ["Status", "Problems", "Flyable", "Reasons", "Mounts", "TrimSpeed", "GlideRatio", "StaticMargin",
           "LaunchDistances", "LaunchStable", "MassGrams", "CenterOfGravity", "ResultData"]

READ = '''
def read(g):
    out = {}
    for n in %r:
        v = getattr(g, n)
        out[n] = v.Value if hasattr(v, "Value") else ([v.x, v.y, v.z] if hasattr(v, "x") else v)
    out["volume"] = g.Shape.Volume
    out["n_solids"] = len(g.Shape.Solids)
    out["wings"] = [[w.WingName, w.Sketch.Name, w.MountedX.Value, w.MountedAngle.Value, w.LockAngle] for w in g.Wings]
    out["fuselage"] = g.Fuselage.Name
    out["material"] = [g.Material, g.Thickness.Value, g.Density]
    out["proxy"] = [type(g.Proxy).__module__, type(g.Proxy).__name__] + [[type(w.Proxy).__module__, type(w.Proxy).__name__] for w in g.Wings]
    return out
''' % OUTPUTS


def same(a, b, rel=1e-12):
    """Equal, floats to `rel` (FreeCAD writes floats with 16 significant digits)."""
    if isinstance(a, float) or isinstance(b, float):
        return a == pytest.approx(b, rel=rel, abs=1e-12)
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k], rel) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same(x, y, rel) for x, y in zip(a, b))
    return a == b


def test_save_reopen_recompute_restores_everything(fc, tmp_path):
    path = tmp_path / "saved.FCStd"
    a = fc(READ + '''
doc = App.newDocument("Saved")
g = pf.new_glider(doc, auto_optimise=False)
g.BallastGrams = 2.5
[w for w in g.Wings if w.WingName == "main"][0].LockAngle = True
g.Material = "Balsa 1.5 mm"
doc.recompute()
RESULT["before"] = read(g)
doc.saveAs(%r)
''' % str(path), name="save")
    b = fc(READ + '''
doc = App.openDocument(%r)
g = pf.gliders(doc)[0]
RESULT["reopened"] = read(g)
RESULT["touched"] = [o.Name for o in doc.Objects if "Touched" in o.State]
g.touch()
doc.recompute()
RESULT["recomputed"] = read(g)
''' % str(path), name="open")
    before, reopened, recomputed = a["before"], b["reopened"], b["recomputed"]
    assert before["Problems"] == [] and before["material"] == ["Balsa 1.5 mm", 1.5, 160.0]
    assert same(reopened, before)                    # every output, link, lock, material as saved
    assert recomputed["ResultData"] and recomputed["Problems"] == []
    for k in OUTPUTS:
        if k == "ResultData":
            continue
        if isinstance(before[k], float):
            assert recomputed[k] == pytest.approx(before[k], rel=1e-9), k
        elif isinstance(before[k], list) and before[k] and isinstance(before[k][0], float):
            assert recomputed[k] == pytest.approx(before[k], rel=1e-9), k
        else:
            assert recomputed[k] == before[k], k
    assert recomputed["volume"] == pytest.approx(before["volume"], rel=1e-9)
    assert before["proxy"][:2] == ["pteromys_freecad.glider", "Glider"]


def test_documents_hold_no_engine_objects(fc, tmp_path):
    path = tmp_path / "plain.FCStd"
    fc('''
doc = App.newDocument("Plain")
g = pf.new_glider(doc)
doc.recompute()
doc.saveAs(%r)
''' % str(path))
    with zipfile.ZipFile(path) as z:
        xml = z.read("Document.xml").decode()
    # Proxies are stored as their module/class and a JSON value: null (nothing of the engine).
    proxies = re.findall(r'<Property name="Proxy" type="App::PropertyPythonObject"[^>]*>\s*<Python ([^/]*)/>', xml)
    assert len(proxies) == 3, proxies
    for p in proxies:
        value = re.search(r'value="([^"]*)"', p).group(1)
        if 'encoded="yes"' in p:
            value = base64.b64decode(value).decode()
        assert value == "null", p
        assert re.search(r'module="pteromys_freecad\.(glider|wing)"', p), p
    assert "pteromys._core" not in xml and "OptimizeState" not in xml
    # Property names are PascalCase.
    names = set(re.findall(r'<Property name="([^"]+)"', xml))
    ours = {"Fuselage", "Wings", "AutoOptimise", "BallastGrams", "LaunchDistances", "MountX", "LockAngle", "HalfOutline"}
    assert ours <= names
    assert all(re.fullmatch(r"[A-Z][A-Za-z0-9]*", n) for n in names), sorted(n for n in names if not n[0].isupper())


def test_old_document_migrates(fc, tmp_path):
    """A document written before some properties existed (simulated by removing
    them and setting SchemaVersion 0) opens with those properties at their
    defaults, the schema updated, and recomputes to the same results."""
    path = tmp_path / "old.FCStd"
    a = fc('''
doc = App.newDocument("Old")
g = pf.new_glider(doc, auto_optimise=False)
RESULT["d"] = list(g.LaunchDistances)
for n in ("Slotted", "ChordTolerance", "MinWeb", "OptimiseBallast", "RecomputeMilliseconds"):
    g.removeProperty(n)
g.SchemaVersion = 0
w = g.Wings[0]
w.removeProperty("LockAngle")
w.removeProperty("HalfOutline")
w.SchemaVersion = 0
RESULT["props_before"] = sorted(g.PropertiesList)
doc.saveAs(%r)
''' % str(path), name="old")
    assert "ChordTolerance" not in a["props_before"]
    b = fc('''
doc = App.openDocument(%r)
g = pf.gliders(doc)[0]
w = g.Wings[0]
RESULT["schema"] = [g.SchemaVersion, w.SchemaVersion]
RESULT["defaults"] = [g.Slotted, g.ChordTolerance.Value, g.MinWeb.Value, g.OptimiseBallast, w.LockAngle, w.HalfOutline]
g.touch()
doc.recompute()
RESULT["problems"] = list(g.Problems)
RESULT["d"] = list(g.LaunchDistances)
''' % str(path), name="migrate")
    assert b["schema"] == [1, 1]
    assert b["defaults"] == [True, 0.1, 2.0, False, False, False]
    assert b["problems"] == []
    assert b["d"] == pytest.approx(a["d"], rel=1e-12)
