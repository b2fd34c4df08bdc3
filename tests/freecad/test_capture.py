"""The capture command of the workbench (pteromys_freecad.capture and the
Pteromys_TrackVideo window): a video rendered by the engine from a simulated
flight, tracked in FreeCAD, a frame fixed by a click, the dataset written.

Headless logic runs in freecadcmd; the window runs under Xvfb and is clicked
with synthetic Qt mouse events. The truth is the rendered flight, not the tracker.
Set PTEROMYS_SCREENSHOTS=DIR to keep the window's screenshot (docs/img).
"""
import json
import math
import os
import shutil
import sys

import numpy as np
import pytest

from conftest import ENGINE_PY, EXAMPLES, run_gui

GLIDER = os.path.join(EXAMPLES, "training", "t04-tapered-mild.glider.json")


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    sys.path.insert(0, ENGINE_PY)
    try:
        import pteromys
        import pteromys.capture as cap
    finally:
        sys.path.remove(ENGINE_PY)
    d = tmp_path_factory.mktemp("capvideo")
    f = pteromys.simulate(GLIDER, speed=8.0, climb_deg=4.0, t_max=1.5)["samples"][:, :4]
    cam = cap.synthetic_camera(distance_m=3.5, x_m=f[0, 1] + 1.9, y_m=float(f[:40, 2].mean()), tilt_deg=1.5,
                               roll_deg=-0.8)
    video = str(d / "launch.avi")
    r = cap.render_video(video, cam, GLIDER, [f], seed=5)
    points = str(d / "points.json")
    with open(points, "w") as fh:
        json.dump(cap.synthetic_points(cam, 4, 3, click_sigma_px=0.3, seed=5, distance_m=3.5), fh)
    truth = {int(row[1]): [float(row[3]), float(row[4]), float(row[7]), float(row[8])] for row in r["truth"]}
    return {"dir": d, "video": video, "points": points, "truth": truth}


HEADLESS = '''
import pteromys_freecad.capture as pc
truth = {int(k): v for k, v in json.load(open(%(truth)r)).items()}
s = pc.CaptureSession(%(video)r, %(points)r, %(glider)r)
RESULT["frames"] = s.frame_count
RESULT["size"] = list(s.size)
fl = s.track()
RESULT["flights"] = len(fl)
f = fl[0]
err = [(f["x_m"][i] - truth[int(fr)][0]) ** 2 + (f["y_m"][i] - truth[int(fr)][1]) ** 2
       for i, fr in enumerate(f["frame"]) if int(fr) in truth]
RESULT["false_points"] = sum(1 for fr in f["frame"] if int(fr) not in truth)
RESULT["rms"] = (sum(err) / len(err)) ** 0.5
RESULT["n"] = len(err)
frames = [int(x) for x in f["frame"]]
mid = frames[len(frames) // 2]
ov = s.overlay(mid)
RESULT["overlay_path"] = len(ov["path"])
RESULT["overlay_point"] = ov["point"]
RESULT["true_px"] = truth[mid][2:]
# the window maps clicks: a 1100x600 view of a 1280x720 image, round trip
x, y = pc.image_to_view(100.25, 200.5, 1100, 600, 1280, 720)
RESULT["round_trip"] = pc.view_to_image(x, y, 1100, 600, 1280, 720)
RESULT["outside"] = pc.view_to_image(1, 1, 1100, 600, 1280, 720)
# fix: the point of `mid` is 8 px to the right; remove the next frame; undo
u, v = ov["point"]["u_px"] + 8.0, ov["point"]["v_px"]
p = s.fix(mid, u, v)
RESULT["fixed"] = p
RESULT["fixed_world"] = s.calibration.image_to_world([[u, v]])[0].tolist()
s.remove(frames[len(frames) // 2 + 1])
RESULT["after_remove"] = s.point(frames[len(frames) // 2 + 1])
RESULT["n_after_remove"] = len(s.result.flights[0]["frame"])
try:
    s.fix(mid, -40.0, 10.0)
except pc.CaptureError as e:
    RESULT["outside_click"] = str(e)
RESULT["corrections_kept"] = {str(k): v for k, v in s.corrections.items()}
s.save_corrections(os.path.join(%(dir)r, "c.json"))
import pteromys.capture as cap
RESULT["corrections_file"] = {str(k): v for k, v in cap.load_corrections(os.path.join(%(dir)r, "c.json")).items()}
RESULT["undo"] = s.undo(mid)
RESULT["after_undo"] = s.point(mid)
RESULT["dataset_flights"] = s.write_dataset(os.path.join(%(dir)r, "data"), key="g01")
RESULT["summary"] = s.summary()
for bad, args in (("video", ("/nonexistent.avi", %(points)r, %(glider)r)),
                  ("glider", (%(video)r, %(points)r, "/nonexistent.glider.json")),
                  ("calibration", (%(video)r, "/nonexistent.json", %(glider)r))):
    try:
        pc.CaptureSession(*args)
    except pc.CaptureError as e:
        RESULT["bad_" + bad] = str(e)
'''


def test_session_tracks_fixes_and_writes_the_dataset(fc, scene):
    d = scene["dir"]
    with open(d / "truth.json", "w") as fh:
        json.dump(scene["truth"], fh)
    r = fc(HEADLESS % {"truth": str(d / "truth.json"), "video": scene["video"], "points": scene["points"],
                       "glider": GLIDER, "dir": str(d)}, name="capture_headless")
    assert r["size"] == [1280, 720] and r["frames"] > 40
    assert r["flights"] == 1 and r["false_points"] == 0 and r["n"] >= 12
    assert r["rms"] <= 0.010, r["rms"]                           # the 1 cm target
    assert r["overlay_path"] == r["n"]
    # the drawn CG is the true CG's pixel within a few pixels (0.3 px click noise, ~3.6 mm/px at 3.5 m)
    pt = r["overlay_point"]
    assert math.hypot(pt["cg_u_px"] - r["true_px"][0], pt["cg_v_px"] - r["true_px"][1]) < 3.0
    assert r["round_trip"] == pytest.approx([100.25, 200.5], abs=1e-9) and r["outside"] is None
    fx = r["fixed"]
    assert fx["manual"] and fx["confidence"] == 1.0 and fx["u_px"] == pytest.approx(pt["u_px"] + 8.0)
    # the CG moved with the click: 8 px at ~3.6 mm/px
    assert math.hypot(fx["x_m"] - pt["x_m"], fx["y_m"] - pt["y_m"]) == pytest.approx(8 * 0.0036, rel=0.35)
    assert r["after_remove"] is None and r["n_after_remove"] == r["n"] - 1
    assert "outside the image" in r["outside_click"]
    assert len(r["corrections_kept"]) == 2 and r["corrections_file"] == r["corrections_kept"]
    assert r["undo"] and not r["after_undo"]["manual"]
    assert r["after_undo"]["u_px"] == pytest.approx(pt["u_px"], abs=1e-9)
    assert r["dataset_flights"] == 1
    rows = (d / "data" / "flights.csv").read_text().splitlines()
    assert rows[0].startswith("flight,glider,t_s,x_m,y_m") and len(rows) == 1 + r["n"] - 1
    assert "no such file" in r["bad_video"] and "no such file" in r["bad_glider"]
    assert "no such file" in r["bad_calibration"]


GUI_SCRIPT = r'''
import json, os, traceback
OUT = %(out)r
R = {}
def pump(n=20):
    from PySide2 import QtWidgets
    for _ in range(n):
        QtWidgets.QApplication.processEvents()
try:
    import FreeCAD as App, FreeCADGui as Gui
    from PySide2 import QtWidgets, QtCore, QtGui
    def click(widget, x, y, button):
        pos = QtCore.QPointF(x, y)
        for kind in (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonRelease):
            ev = QtGui.QMouseEvent(kind, pos, button, button, QtCore.Qt.NoModifier)
            QtWidgets.QApplication.sendEvent(widget, ev)
    os.environ["PTEROMYS_NO_DIALOGS"] = "1"
    mw = Gui.getMainWindow()
    mw.showMaximized()
    pump()
    Gui.activateWorkbench("PteromysWorkbench")
    R["command"] = "Pteromys_TrackVideo" in Gui.listCommands()
    Gui.runCommand("Pteromys_TrackVideo")
    pump()
    from pteromys_freecad.gui import capture_view
    w = mw.findChild(QtWidgets.QWidget, capture_view.WINDOW_NAME)
    R["window"] = bool(w and w.isVisible())
    w.set_files(%(video)r, %(points)r, %(glider)r)
    R["tracked"] = w.track()
    pump()
    s = w.session
    frames = [int(x) for x in s.result.flights[0]["frame"]]
    mid = frames[len(frames) // 2]
    w.show_frame(mid)
    pump()
    pt = s.point(mid)
    R["before"] = pt
    # click 10 image pixels above the tracked point
    from pteromys_freecad import capture as pc
    x, y = pc.image_to_view(pt["u_px"], pt["v_px"] - 10.0, w.view.width(), w.view.height(), *s.size)
    click(w.view, round(x), round(y), QtCore.Qt.LeftButton)
    pump()
    R["after"] = s.point(mid)
    R["scale"] = w.view.width() / 1280.0
    R["info"] = w.info.text()
    w.view.grab().save(os.path.join(%(shots)r, "frame.png"))
    w.grab().save(os.path.join(%(shots)r, "window.png"))
    # a right click: no glider in the next frame
    w.show_frame(mid + 1)
    click(w.view, round(x), round(y), QtCore.Qt.RightButton)
    pump()
    R["removed"] = s.point(mid + 1)
    w.show_frame(mid)
    pump()
    w.grab().save(os.path.join(%(shots)r, "window.png"))
    R["finished"] = True
except BaseException:
    R["error"] = traceback.format_exc()
finally:
    with open(OUT, "w") as f:
        json.dump(R, f, indent=1, default=str)
    from PySide2 import QtWidgets, QtCore
    QtCore.QTimer.singleShot(0, QtWidgets.QApplication.quit)
'''


def test_window_shows_the_track_and_a_click_fixes_a_frame(fc_home, scene, tmp_path):
    shots = tmp_path / "shots"
    shots.mkdir()
    out = tmp_path / "gui.json"
    script = tmp_path / "capture_gui.py"
    script.write_text(GUI_SCRIPT % {"out": str(out), "shots": str(shots), "video": scene["video"],
                                    "points": scene["points"], "glider": GLIDER})
    r = run_gui(fc_home, script, out, tmp_path)
    assert r["command"] and r["window"] and r["tracked"]
    b, a = r["before"], r["after"]
    assert a["manual"] and not b["manual"]
    # the click lands on the intended pixel within the rounding to a screen pixel
    tol = 0.5 / r["scale"] + 0.01
    assert a["u_px"] == pytest.approx(b["u_px"], abs=tol) and a["v_px"] == pytest.approx(b["v_px"] - 10, abs=tol)
    assert "fixed by hand" in r["info"]
    assert r["removed"] is None
    import matplotlib.image as mpimg
    img = mpimg.imread(str(shots / "frame.png"))[..., :3]
    assert img.shape[1] > 400 and img.std() > 0.05                 # the frame is drawn
    path = np.array([0x00, 0xc8, 0xff]) / 255.0                       # capture_view.PATH_COLOUR
    assert (np.abs(img - path).sum(axis=2) < 0.25).sum() > 20         # the tracked path is drawn over it
    keep = os.environ.get("PTEROMYS_SCREENSHOTS")
    if keep:
        os.makedirs(keep, exist_ok=True)
        shutil.copy(shots / "window.png", os.path.join(keep, "capture_window.png"))
