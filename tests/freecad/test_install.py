"""The add-on installs with install.sh and loads headless, finds the engine
through its configuration, and says plainly when the engine is missing."""
import os
import subprocess

from conftest import ENGINE_PY, INSTALL, fc_env, run_freecad


def test_installed_addon_loads_headless_and_finds_the_engine(fc, fc_home):
    r = fc('''
import sys
pteromys = pf.engine()      # found through Mod/Pteromys/pteromys.cfg
RESULT["engine_file"] = pteromys.__file__
RESULT["import_type"] = App.getImportType("glider.json")
RESULT["export_type"] = App.getExportType("glider.json")
doc = App.newDocument("H")
g = pf.new_glider(doc)
RESULT["status"] = g.Status
RESULT["gui_modules"] = sorted(m for m in sys.modules if m.startswith("pteromys_freecad.gui") or m == "FreeCADGui")
RESULT["gui_up"] = App.GuiUp
''')
    assert r["addon_file"].startswith(str(fc_home / "Mod" / "Pteromys")), r["addon_file"]
    assert os.path.realpath(r["engine_file"]).startswith(os.path.realpath(ENGINE_PY)), r["engine_file"]
    assert r["import_type"] == ["pteromys_freecad.importer"] and r["export_type"] == ["pteromys_freecad.importer"]
    assert not r["gui_up"] and r["gui_modules"] == []       # nothing of the GUI is imported headless
    assert not r["status"].startswith("Input error"), r["status"]


def test_missing_engine_is_reported_not_crashed(tmp_path):
    home = tmp_path / "home"
    p = subprocess.run([INSTALL, "--mod-dir", str(home / "Mod"), "--python-path", str(tmp_path / "nowhere")],
                       capture_output=True, text=True)
    assert p.returncode == 0 and "warning: no engine package" in p.stderr, p.stderr
    probe = subprocess.run(["/usr/bin/python3", "-c", "import pteromys"], capture_output=True,
                           env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert probe.returncode != 0, ("pteromys is installed system-wide, so a missing engine cannot be "
                                   "simulated here; uninstall it to run this test")
    r = run_freecad(home, tmp_path, '''
doc = App.newDocument("M")
g = pf.new_glider(doc)
RESULT["status"] = g.Status
RESULT["problems"] = list(g.Problems)
RESULT["alive"] = True
''', env=fc_env(home))
    assert r["alive"]
    assert r["status"].startswith("Input error: the Pteromys engine (Python module 'pteromys') was not found")
    assert "PTEROMYS_PYTHONPATH" in r["problems"][0]


def test_install_is_idempotent_and_uninstalls(tmp_path):
    mod = tmp_path / "Mod"
    for _ in range(2):
        p = subprocess.run([INSTALL, "--mod-dir", str(mod), "--python-path", ENGINE_PY], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(mod)) == ["Pteromys"]           # no leftovers from the atomic replace
    files = set(os.listdir(mod / "Pteromys"))
    assert {"Init.py", "InitGui.py", "package.xml", "pteromys.cfg", "pteromys_freecad", "Resources"} <= files
    p = subprocess.run([INSTALL, "--mod-dir", str(mod), "--uninstall"], capture_output=True, text=True)
    assert p.returncode == 0 and not (mod / "Pteromys").exists()
    p = subprocess.run([INSTALL, "--bogus"], capture_output=True, text=True)
    assert p.returncode == 2 and "unknown option" in p.stderr
