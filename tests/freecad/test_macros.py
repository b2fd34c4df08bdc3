"""Every example macro runs headless in freecadcmd and writes what it promises.

The macros find the add-on installed by install.sh (as a user's would).
Outputs are checked by meaning: JSON results against physics of the edit
(mass grows with span), the DXF with ezdxf, the FreeCAD document by reopening
it, the glider file with the `pteromys` command.
"""
import csv
import glob
import json
import os
import subprocess

import pytest

from conftest import EXAMPLES, PTEROMYS_BIN, fc_env, feature_reason, freecadcmd

MACROS = sorted(glob.glob(os.path.join(EXAMPLES, "macros", "*.py")))


def run_macro(fc_home, tmp_path, name, **env):
    out = tmp_path / "out"
    e = fc_env(fc_home, PTEROMYS_MACRO_OUT=out, **env)
    p = subprocess.run([freecadcmd(), os.path.join(EXAMPLES, "macros", name)], capture_output=True, text=True,
                       timeout=900, env=e, cwd=str(tmp_path))
    text = p.stdout + p.stderr
    assert p.returncode == 0, text[-3000:]
    assert "Exception while processing file" not in text and "Traceback" not in text, text[-3000:]
    return out, text


def test_every_macro_is_tested():
    assert sorted(os.path.basename(m) for m in MACROS) == ["change_parameter.py", "export_parts.py",
                                                          "glider_from_scratch.py", "import_glider_file.py"]


def test_glider_from_scratch(fc_home, tmp_path):
    out, text = run_macro(fc_home, tmp_path, "glider_from_scratch.py")
    r = json.load(open(out / "scratch_results.json"))
    assert r["problems"] == [], r["problems"]
    assert len(r["launch_distances_m"]) == 6 and r["mass_kg"] > 0
    assert (out / "scratch.FCStd").stat().st_size > 1000
    assert "Launch distances [m]:" in text
    # the half wing drawn to 212 mm (B-spline tip) is mirrored: span 424 mm
    assert "Wing span 424.0 mm" in text


def test_change_parameter(fc_home, tmp_path):
    out, text = run_macro(fc_home, tmp_path, "change_parameter.py", PTEROMYS_SPANS_MM="380,440,500")
    rows = list(csv.DictReader(open(out / "span_study.csv")))
    assert [int(r["span_mm"]) for r in rows] == [380, 440, 500]
    areas = [float(r["wing_area_mm2"]) for r in rows]
    # template main wing: trapezoid, root 75 mm, tip 40 mm -> area = 57.5 mm x span
    assert areas == pytest.approx([57.5 * s for s in (380, 440, 500)], rel=1e-9)
    masses = [float(r["mass_g"]) for r in rows]
    # 1 mm foam board at 180 kg/m^3: 1.8e-4 g per mm^2 of plate
    assert masses[1] - masses[0] == pytest.approx((areas[1] - areas[0]) * 1.8e-4, rel=1e-6)
    assert all(r["status"] for r in rows)
    locked = {float(r["main_angle_deg"]) for r in rows}
    assert locked == {1.0}                    # the macro locks the main wing's angle at its design value


def test_import_glider_file(fc_home, tmp_path):
    src = os.path.join(EXAMPLES, "gliders", "canard.glider.json")
    out, _ = run_macro(fc_home, tmp_path, "import_glider_file.py", PTEROMYS_MACRO_GLIDER=src)
    c = json.load(open(out / "imported_compare.json"))
    rep = tmp_path / "cli.json"
    p = subprocess.run([PTEROMYS_BIN, "evaluate", src, "--json", str(rep)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    cli = json.load(open(rep))
    assert c["before"]["launch_distances_m"] == pytest.approx([l["distance_m"] for l in cli["launches"]], rel=1e-9)
    reason = feature_reason("optimize")
    if reason:
        pytest.fail("cannot test the optimised half of this macro: " + reason)
    assert c["after"]["optimised"] and c["after"]["flyable"], c["after"]["status"]
    assert (out / "imported_optimised.glider.json").exists()


def test_export_parts(fc_home, tmp_path):
    reason = feature_reason("export")
    if reason:
        pytest.fail("cannot run export_parts.py: " + reason)
    out, _ = run_macro(fc_home, tmp_path, "export_parts.py")
    for suffix in (".dxf", ".step", ".glider.json", "_flights.png", "_results.json"):
        f = out / ("Dart" + suffix)
        assert f.exists() and f.stat().st_size > 500, f
    import ezdxf
    doc = ezdxf.readfile(str(out / "Dart.dxf"))
    assert len(doc.modelspace().query("LWPOLYLINE POLYLINE")) >= 3
    rep = tmp_path / "r.json"
    p = subprocess.run([PTEROMYS_BIN, "evaluate", str(out / "Dart.glider.json"), "--json", str(rep)],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    res = json.load(open(out / "Dart_results.json"))["results"]
    assert json.load(open(rep))["flyable"] == res["flyable"]


def test_a_failing_macro_fails_its_command_line(fc_home, tmp_path):
    """freecadcmd itself exits 0 after an exception; the macros exit 1 headless so that scripts notice."""
    e = fc_env(fc_home, PTEROMYS_MACRO_OUT=tmp_path / "out", PTEROMYS_MACRO_DOC=tmp_path / "missing.FCStd")
    p = subprocess.run([freecadcmd(), os.path.join(EXAMPLES, "macros", "export_parts.py")], capture_output=True,
                       text=True, timeout=300, env=e, cwd=str(tmp_path))
    assert p.returncode == 1, (p.returncode, p.stdout[-2000:], p.stderr[-2000:])
    assert "missing.FCStd" in p.stdout + p.stderr
