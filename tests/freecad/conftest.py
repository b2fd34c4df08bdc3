"""Shared fixtures of the FreeCAD workbench tests.

Every test runs real FreeCAD: a script is written to a temporary folder and
run by ``freecadcmd`` (or by ``freecad`` under Xvfb for the GUI), with the
add-on installed by ``freecad_workbench/install.sh`` into a private
FREECAD_USER_HOME, exactly as a user installs it. The script writes its
findings as JSON; a missing JSON file fails the test with FreeCAD's output.

Environment (set by ctest): PTEROMYS_BUILD_DIR (the build whose engine the
add-on uses), PTEROMYS_BIN (the pteromys command).
"""
import json
import os
import shutil
import subprocess
import textwrap

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
BUILD = os.environ.get("PTEROMYS_BUILD_DIR") or os.path.join(ROOT, "build")
ENGINE_PY = os.path.join(BUILD, "python")
PTEROMYS_BIN = os.environ.get("PTEROMYS_BIN") or os.path.join(BUILD, "bin", "pteromys")
EXAMPLES = os.path.join(ROOT, "examples")
INSTALL = os.path.join(ROOT, "freecad_workbench", "install.sh")

#: Script helpers: facts(glider) gathers geometry (by OpenCASCADE) and results.
TEMPLATE_FACTS = '''
import Part
def face_of(sketch):
    """OpenCASCADE's face of a sketch, in the sketch's own frame (mm)."""
    s = sketch.Shape.copy()
    s.transformShape(sketch.getGlobalPlacement().inverse().toMatrix())
    return Part.Face(s.Wires[0])
def facts(g):
    f = {}
    fus = face_of(g.Fuselage)
    f["fus_area"] = fus.Area
    f["fus_cx"] = fus.CenterOfMass.x
    f["wings"] = {}
    for w in g.Wings:
        face = face_of(w.Sketch)
        f["wings"][w.WingName] = {"area": face.Area, "cx": face.CenterOfMass.x, "fully_constrained": w.Sketch.FullyConstrained,
                                  "span": w.Span.Value, "planform": w.PlanformArea.Value,
                                  "mounted": [w.MountedX.Value, w.MountedY.Value, w.MountedAngle.getValueAs("deg").Value],
                                  "design": [w.MountX.Value, w.MountY.Value, w.MountAngle.getValueAs("deg").Value]}
    f["fus_fully_constrained"] = g.Fuselage.FullyConstrained
    sh = g.Shape
    f["n_solids"] = len(sh.Solids)
    f["volume"] = sh.Volume
    bb = sh.BoundBox
    f["bbox"] = [bb.XMin, bb.XMax, bb.YMin, bb.YMax, bb.ZMin, bb.ZMax]
    f["results"] = pf.results(g)
    f["status"] = g.Status
    f["data"] = pf.result_data(g)
    return f
'''


PRELUDE = '''
import json, os, sys, traceback
import FreeCAD as App
RESULT = {}
_OUT = %(out)r
def _finish():
    with open(_OUT + ".tmp", "w") as f:
        json.dump(RESULT, f, indent=1, default=str)
    os.replace(_OUT + ".tmp", _OUT)
try:
    import pteromys_freecad as pf
    RESULT["addon_file"] = pf.__file__
'''

EPILOGUE = '''
    RESULT["finished"] = True
except BaseException:
    RESULT["error"] = traceback.format_exc()
_finish()
'''


def freecadcmd():
    exe = shutil.which("freecadcmd")
    if not exe:
        pytest.fail("freecadcmd is not installed (scripts/setup.sh installs Debian's freecad)")
    return exe


def _require_engine():
    if not os.path.isfile(os.path.join(ENGINE_PY, "pteromys", "__init__.py")):
        pytest.fail("no engine module at %s: build the project first (PTEROMYS_BUILD_DIR=%s)" % (ENGINE_PY, BUILD))


@pytest.fixture(scope="session")
def fc_home(tmp_path_factory):
    """A FREECAD_USER_HOME with the add-on installed by install.sh."""
    _require_engine()
    home = tmp_path_factory.mktemp("fchome")
    r = subprocess.run([INSTALL, "--mod-dir", str(home / "Mod"), "--python-path", ENGINE_PY],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, "install.sh failed:\n%s\n%s" % (r.stdout, r.stderr)
    assert (home / "Mod" / "Pteromys" / "Init.py").is_file()
    return home


def fc_env(home, **extra):
    env = dict(os.environ)
    env["FREECAD_USER_HOME"] = str(home)
    env["QT_QPA_PLATFORM"] = "offscreen"
    # The add-on must find the engine through its own configuration, as for a user.
    env.pop("PYTHONPATH", None)
    env.pop("PTEROMYS_PYTHONPATH", None)
    env.update({k: str(v) for k, v in extra.items()})
    return env


def run_gui(home, script, out, cwd, timeout=600):
    """Run the GUI script `script` in ``freecad`` under Xvfb (the real X11
    platform, a 1600x1000 screen); returns the dict it wrote to `out`.

    A missing FreeCAD or xvfb-run, a script that wrote nothing, and an
    ``error`` key in the result (the script's traceback) fail the test.
    """
    for exe in ("xvfb-run", "freecad"):
        if not shutil.which(exe):
            pytest.fail("%s is not installed (scripts/setup.sh installs freecad, xvfb and xauth)" % exe)
    env = fc_env(home, QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox")
    env.pop("QT_QPA_PLATFORM", None)       # the real X11 platform, on Xvfb
    p = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", "freecad", str(script)],
                       capture_output=True, text=True, timeout=timeout, env=env, cwd=str(cwd))
    if not os.path.exists(out):
        pytest.fail("FreeCAD GUI wrote no result (exit %s):\n%s\n%s" % (p.returncode, p.stdout[-3000:], p.stderr[-3000:]))
    with open(out) as f:
        r = json.load(f)
    if "error" in r:
        pytest.fail("GUI script failed:\n" + r["error"])
    return r


def run_freecad(home, tmp_path, body, name="script", timeout=600, env=None):
    """Run `body` (indented into a try block) in freecadcmd; returns RESULT as a dict.

    The body fills the dict RESULT; an exception in it fails the test with
    its traceback.
    """
    out = tmp_path / (name + ".json")
    script = tmp_path / (name + ".py")
    code = PRELUDE % {"out": str(out)} + textwrap.indent(textwrap.dedent(body), "    ") + EPILOGUE
    script.write_text(code)
    r = subprocess.run([freecadcmd(), str(script)], capture_output=True, text=True, timeout=timeout,
                       env=env or fc_env(home), cwd=str(tmp_path))
    if not out.exists():
        pytest.fail("freecadcmd wrote no result (exit %s):\n--- stdout\n%s\n--- stderr\n%s"
                    % (r.returncode, r.stdout[-4000:], r.stderr[-4000:]))
    res = json.loads(out.read_text())
    if "error" in res:
        pytest.fail("the FreeCAD script failed:\n%s\n--- stderr\n%s" % (res["error"], r.stderr[-2000:]))
    assert res.get("finished"), res
    res["_stdout"] = r.stdout
    res["_stderr"] = r.stderr
    return res


@pytest.fixture
def fc(fc_home, tmp_path):
    """Callable running a script body in freecadcmd with the installed add-on."""
    def run(body, name="script", timeout=600, **env):
        return run_freecad(fc_home, tmp_path, body, name=name, timeout=timeout,
                           env=fc_env(fc_home, **env) if env else None)
    return run


def feature_reason(name):
    """Why the engine build lacks `name` (None when present): tests needing it fail with this."""
    import sys
    sys.path.insert(0, ENGINE_PY)
    try:
        import pteromys
    finally:
        sys.path.remove(ENGINE_PY)
    if hasattr(pteromys, name):
        return None
    return {"optimize": "optimisation is not available in this build (pteromys.optimize is missing)",
            "slotted_plates": "slotted plates are not available in this build (pteromys.slotted_plates is missing)",
            "export": "DXF/STEP export is not available in this build (pteromys.export is missing)"}.get(name, name)


def require(name):
    reason = feature_reason(name)
    if reason:
        pytest.fail("cannot test this: " + reason)
