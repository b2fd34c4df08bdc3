"""Glider files (spec/formats.md) in and out of FreeCAD.

Every example glider is imported, evaluated as mounted, and exported again.
References: the original file (outlines and mounts must survive the round
trip through sketches in millimetres), and the engine's report of the
original file through the separate `pteromys` command.
"""
import glob
import json
import os
import subprocess

import pytest

from conftest import EXAMPLES, PTEROMYS_BIN

FILES = sorted(glob.glob(os.path.join(EXAMPLES, "gliders", "*.glider.json")))


@pytest.fixture(scope="module")
def roundtrip(fc_home, tmp_path_factory):
    from conftest import run_freecad
    tmp = tmp_path_factory.mktemp("files")
    body = '''
import pteromys_freecad.importer as importer
for src in %r:
    name = os.path.basename(src).split(".")[0]
    doc = importer.open(src)
    g = pf.gliders(doc)[0]
    out = os.path.join(%r, name + ".glider.json")
    pf.export_glider_file(g, out)
    RESULT[name] = {"src": src, "out": out, "results": pf.results(g), "auto": g.AutoOptimise,
                    "n_objects": len(doc.Objects)}
    App.closeDocument(doc.Name)
''' % (FILES, str(tmp))
    return run_freecad(fc_home, tmp, body, name="roundtrip")


def flat(points):
    return [v for p in points for v in p]


def cli_report(path, tmp_path):
    rep = tmp_path / (os.path.basename(path) + ".report.json")
    p = subprocess.run([PTEROMYS_BIN, "evaluate", path, "--json", str(rep)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return json.loads(rep.read_text())


@pytest.mark.parametrize("path", FILES, ids=[os.path.basename(f).split(".")[0] for f in FILES])
def test_example_file_roundtrip(roundtrip, path, tmp_path):
    name = os.path.basename(path).split(".")[0]
    r = roundtrip[name]
    res = r["results"]
    assert res["problems"] == [], res["problems"]
    assert r["auto"] is False                          # imported as the file mounts it
    src = json.load(open(path))
    out = json.load(open(r["out"]))
    assert out["format"] == "pteromys-glider/1"
    assert out["material"] == pytest.approx(src["material"], rel=1e-12)
    assert flat(out["fuselage"]["outline_m"]) == pytest.approx(flat(src["fuselage"]["outline_m"]), abs=1e-12)
    assert [w["name"] for w in out["wings"]] == [w["name"] for w in src["wings"]]
    for a, b in zip(out["wings"], src["wings"]):
        assert flat(a["outline_m"]) == pytest.approx(flat(b["outline_m"]), abs=1e-12)
        assert [a["mount"][k] for k in ("x_m", "y_m", "angle_deg")] == \
            pytest.approx([b["mount"][k] for k in ("x_m", "y_m", "angle_deg")], abs=1e-12)
    # one ballast item in the workbench: the file's items merge at their centre of mass
    mb = sum(b["mass_kg"] for b in src["ballast"])
    assert sum(b["mass_kg"] for b in out["ballast"]) == pytest.approx(mb, rel=1e-12)
    if mb > 0:
        xb = sum(b["mass_kg"] * b["x_m"] for b in src["ballast"]) / mb
        assert out["ballast"][0]["x_m"] == pytest.approx(xb, abs=1e-12)
    cli = cli_report(path, tmp_path)
    assert res["flyable"] == cli["flyable"]
    assert res["launch_distances_m"] == pytest.approx([l["distance_m"] for l in cli["launches"]], rel=1e-9)
    assert res["mass_kg"] == pytest.approx(cli["mass_kg"], rel=1e-12)


def test_bad_file_is_refused_and_creates_nothing(fc, tmp_path):
    bad = tmp_path / "bad.glider.json"
    bad.write_text('{"format": "pteromys-glider/1", "name": "x", "material": {"thickness_m": 0.001}}')
    r = fc('''
doc = App.newDocument("B")
n = len(doc.Objects)
try:
    pf.import_glider_file(%r, doc=doc)
    RESULT["error"] = "no error raised"
except Exception as e:
    RESULT["message"] = str(e)
RESULT["created"] = len(doc.Objects) - n
''' % str(bad))
    assert "density_kg_m3" in r["message"] or "fuselage" in r["message"], r["message"]
    assert r["created"] == 0


def test_export_refuses_bad_targets_and_bad_input(fc, tmp_path):
    r = fc('''
doc = App.newDocument("E")
g = pf.new_glider(doc, auto_optimise=False)
msgs = {}
for key, path in [("folder", %r), ("suffix", %r)]:
    try:
        pf.export_glider_file(g, path)
    except pf.ExportError as e:
        msgs[key] = str(e)
g.Wings[0].MountY = 200.0          # the main wing off the fuselage
try:
    pf.export_glider_file(g, %r)
except pf.ExportError as e:
    msgs["input"] = str(e)
RESULT["msgs"] = msgs
''' % (str(tmp_path / "no" / "such" / "x.glider.json"), str(tmp_path / "x.txt"), str(tmp_path / "stale.glider.json")))
    m = r["msgs"]
    assert "does not exist" in m["folder"]
    assert "must end in .json" in m["suffix"]
    assert "input errors" in m["input"] and "does not touch the fuselage" in m["input"]
    assert not (tmp_path / "stale.glider.json").exists() and not (tmp_path / "x.txt").exists()
