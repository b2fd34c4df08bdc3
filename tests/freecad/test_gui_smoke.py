"""GUI smoke test under Xvfb: the workbench activates, New glider works, the
flight view opens and follows recomputes, the task panel opens, a bad edit
keeps FreeCAD up, a saved document reopens with its view providers; the
screenshots are checked for content.

Set PTEROMYS_SCREENSHOTS=DIR to also keep the screenshots (docs/img uses them).
"""
import os
import shutil

import numpy as np
import pytest

from conftest import run_gui

GUI_SCRIPT = r'''
import json, os, sys, traceback
OUT = %(out)r
SHOTS = %(shots)r
R = {}
def pump(n=15):
    from PySide2 import QtWidgets
    for _ in range(n):
        QtWidgets.QApplication.processEvents()
def screen(path):
    from PySide2 import QtGui
    QtGui.QGuiApplication.primaryScreen().grabWindow(0).save(path)
try:
    import FreeCAD as App, FreeCADGui as Gui
    from PySide2 import QtWidgets, QtCore, QtGui
    mw = Gui.getMainWindow()
    mw.showMaximized()
    pump()
    R["workbenches"] = sorted(Gui.listWorkbenches())
    Gui.activateWorkbench("PteromysWorkbench")
    R["active"] = Gui.activeWorkbench().name()
    wb = Gui.activeWorkbench()
    R["toolbar"] = wb.getToolbarItems().get("Pteromys", [])
    R["menu_commands"] = [c for c in Gui.listCommands() if c.startswith("Pteromys_")]
    doc = App.newDocument("Smoke")
    Gui.runCommand("Pteromys_NewGlider")
    pump()
    import pteromys_freecad as pf
    from pteromys_freecad.gui import flight_view
    g = pf.active_glider()
    R["glider"] = g.Label if g else None
    R["status"] = g.Status
    dock = mw.findChild(QtWidgets.QDockWidget, flight_view.DOCK_NAME)
    R["dock_visible"] = bool(dock and dock.isVisible())
    view = dock.widget()
    R["plot_distances_before"] = [l["distance_m"] for l in view.plot.data["report"]["launches"]]
    R["summary"] = view.summary.text()
    R["vp"] = type(g.ViewObject.Proxy).__name__
    R["children"] = [o.Name for o in g.ViewObject.claimChildren()]
    # edit a constraint: the flight view must follow the recompute
    main = [w for w in g.Wings if w.WingName == "main"][0]
    main.Sketch.setDatum("Span", App.Units.Quantity("470 mm"))
    doc.recompute()
    pump()
    R["plot_distances_after"] = [l["distance_m"] for l in view.plot.data["report"]["launches"]]
    R["glider_distances_after"] = list(g.LaunchDistances)
    Gui.Selection.clearSelection()
    # a wider combo view and the tree unfolded, for readable screenshots
    cv = mw.findChild(QtWidgets.QDockWidget, "Combo View")
    if cv is not None:
        mw.resizeDocks([cv], [430], QtCore.Qt.Horizontal)
    for t in mw.findChildren(QtWidgets.QTreeWidget):
        t.expandAll()
    v = Gui.activeDocument().activeView()
    v.viewIsometric()
    v.fitAll()
    pump(30)
    v.saveImage(os.path.join(SHOTS, "view3d.png"), 1200, 700, "White")
    screen(os.path.join(SHOTS, "main.png"))
    flight_view.grab(os.path.join(SHOTS, "flight.png"))
    # a close-up of the main wing passing through its slot in the fuselage
    import pivy.coin as coin
    cam = v.getCameraNode()
    c = g.Shape.BoundBox.Center
    root = g.Placement.multVec(App.Vector(main.MountedX.Value - 20, main.MountedY.Value, 0))
    cam.position.setValue(cam.position.getValue() + coin.SbVec3f(root.x - c.x, root.y - c.y, root.z - c.z))
    cam.height.setValue(cam.height.getValue() / 5)
    pump(20)
    v.saveImage(os.path.join(SHOTS, "joint.png"), 1000, 700, "White")
    v.fitAll()
    pf.export_dxf(g, os.path.join(SHOTS, "glider.dxf"))
    # the task panel
    Gui.ActiveDocument.setEdit(g.Name)
    pump()
    R["task_dialog"] = Gui.Control.activeDialog()
    screen(os.path.join(SHOTS, "task.png"))
    Gui.ActiveDocument.resetEdit()
    pump()
    # the task panel writes on OK and undoes on Cancel
    from pteromys_freecad.gui import task_panel
    p = task_panel.GliderTaskPanel(g)
    Gui.Control.showDialog(p)
    p.ballast.setValue(4.5)
    p.accept()
    pump()
    R["panel_ok"] = [g.BallastGrams, g.Status]
    p = task_panel.GliderTaskPanel(g)
    Gui.Control.showDialog(p)
    p.ballast.setValue(9.0)
    p.apply()
    R["panel_applied"] = g.BallastGrams
    p.reject()
    pump()
    R["panel_cancel"] = g.BallastGrams
    # a bad edit: the tail sketch opened; FreeCAD stays up and says why
    tail = [w for w in g.Wings if w.WingName == "tail"][0]
    doc.openTransaction("break the tail")
    tail.Sketch.delGeometry(1)
    doc.commitTransaction()
    doc.recompute()
    pump()
    R["bad_status"] = g.Status
    R["bad_banner"] = view.plot.banner
    screen(os.path.join(SHOTS, "bad.png"))
    doc.undo()
    doc.recompute()
    pump()
    R["undone_status"] = g.Status
    # save, close, reopen: view providers come back
    path = os.path.join(SHOTS, "smoke.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    pump()
    doc2 = App.openDocument(path)
    pump()
    g2 = pf.gliders(doc2)[0]
    R["reopened_vp"] = type(g2.ViewObject.Proxy).__name__
    R["reopened_wing_vp"] = type(g2.Wings[0].ViewObject.Proxy).__name__
    R["reopened_status"] = g2.Status
    R["finished"] = True
except BaseException:
    R["error"] = traceback.format_exc()
finally:
    with open(OUT, "w") as f:
        json.dump(R, f, indent=1, default=str)
    try:
        for d in list(App.listDocuments()):
            App.closeDocument(d)
    finally:
        from PySide2 import QtWidgets, QtCore
        QtCore.QTimer.singleShot(0, QtWidgets.QApplication.quit)
'''


def image(path):
    import matplotlib.image as mpimg
    a = mpimg.imread(str(path))
    return (a[..., :3] * 255).astype(np.uint8) if a.dtype != np.uint8 else a[..., :3]


def render_dxf(path, png):
    """The laser-cut parts of a DXF as an image (ezdxf's drawing add-on), sheet frames left out."""
    import logging
    import ezdxf
    import matplotlib
    matplotlib.use("Agg")
    from ezdxf.addons.drawing import matplotlib as draw
    logging.getLogger("matplotlib.font_manager").setLevel(logging.ERROR)
    doc = ezdxf.readfile(str(path))
    msp = doc.modelspace()
    for e in list(msp):
        if e.dxf.layer.upper() == "SHEET":
            msp.delete_entity(e)
    draw.qsave(msp, str(png), bg="#FFFFFF", dpi=200)


@pytest.fixture(scope="module")
def gui(fc_home, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("gui")
    shots = tmp / "shots"
    shots.mkdir()
    out = tmp / "gui.json"
    script = tmp / "gui_smoke.py"
    script.write_text(GUI_SCRIPT % {"out": str(out), "shots": str(shots)})
    r = run_gui(fc_home, script, out, tmp)
    keep = os.environ.get("PTEROMYS_SCREENSHOTS")
    if keep:
        os.makedirs(keep, exist_ok=True)
        for name in ("main", "view3d", "flight", "task", "bad", "joint"):
            shutil.copy(shots / (name + ".png"), os.path.join(keep, "workbench_%s.png" % name))
        render_dxf(shots / "glider.dxf", os.path.join(keep, "workbench_dxf.png"))
    r["_shots"] = shots
    return r


def test_workbench_activates_with_its_commands(gui):
    assert "PteromysWorkbench" in gui["workbenches"] and gui["active"] == "PteromysWorkbench"
    for c in ("Pteromys_NewGlider", "Pteromys_AddWing", "Pteromys_OptimiseNow", "Pteromys_FlightView",
              "Pteromys_ExportDXF", "Pteromys_ExportSTEP", "Pteromys_ImportGlider", "Pteromys_ExportGlider"):
        assert c in gui["toolbar"] and c in gui["menu_commands"], c


def test_new_glider_and_flight_view_follow_recompute(gui):
    assert gui["glider"] == "Glider" and not gui["status"].startswith("Input error"), gui["status"]
    assert gui["vp"] == "ViewProviderGlider" and len(gui["children"]) == 3
    assert gui["dock_visible"]
    assert ("Flyable" in gui["summary"]) or ("Not flyable" in gui["summary"])
    assert gui["plot_distances_after"] == pytest.approx(gui["glider_distances_after"], rel=1e-12)
    assert gui["plot_distances_after"] != pytest.approx(gui["plot_distances_before"], rel=1e-6)
    assert gui["task_dialog"]
    assert gui["panel_ok"][0] == 4.5 and not gui["panel_ok"][1].startswith("Input error")
    assert gui["panel_applied"] == 9.0 and gui["panel_cancel"] == 4.5


def test_bad_edit_in_the_gui_is_civil(gui):
    assert gui["bad_status"].startswith("Input error: wing 'tail'"), gui["bad_status"]
    assert gui["bad_banner"].startswith("Input error: wing 'tail'")
    assert not gui["undone_status"].startswith("Input error"), gui["undone_status"]
    assert gui["reopened_vp"] == "ViewProviderGlider" and gui["reopened_wing_vp"] == "ViewProviderWing"


def test_screenshots_show_the_glider_and_its_flights(gui):
    shots = gui["_shots"]
    v3d = image(shots / "view3d.png")
    # foam-board plates (ShapeColor 0.96, 0.93, 0.82 shaded): warm, non-white pixels present
    r, g, b = (v3d[..., k].astype(int) for k in range(3))
    plates = (r > 60) & (r - b > 12) & (r < 250)
    assert plates.sum() > 2000, plates.sum()
    fl = image(shots / "flight.png")
    # the six trajectories use the three speed colours (pteromys_freecad.gui.flight_view.SPEED_COLOURS)
    for hexcol in ("#1b9e77", "#d95f02", "#7570b3"):
        c = np.array([int(hexcol[i:i + 2], 16) for i in (1, 3, 5)])
        assert (np.abs(fl.astype(int) - c).sum(axis=2) < 40).sum() > 50, hexcol
    main = image(shots / "main.png")
    assert main.shape[0] >= 900 and main.std() > 20
    joint = image(shots / "joint.png")
    assert (joint.std(axis=2) > 0).sum() > 0 and joint.std() > 10     # the close-up is not blank
    assert (shots / "glider.dxf").stat().st_size > 1000
